// Damping curves by EPMC continued over log10 q (continuation/backbone.hpp).
#include "jointhb/continuation/backbone.hpp"

#include "../support/stopwatch.hpp"
#include "curve_from_both_ends.hpp"
#include "curve_turns.hpp"
#include "linear_limits.hpp"
#include "mode_outputs.hpp"
#include "segmented_curve.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "jointhb/contact/harmonic_loop.hpp"

namespace jointhb::continuation {
namespace {

// The internal resonance at Ω, if any: a harmonic k Ω (k ≥ 2 among the kept orders) within 2 % of
// a natural frequency ω_j of the stuck or the contact-free linear system. There the followed mode
// exchanges energy with mode j (a k:1 internal resonance): the EPMC curve turns back in amplitude,
// many times where it meets non-smooth points of the friction laws.
std::optional<detail::NearResonance> internal_resonance(const hb::DiscreteSystem& system,
                                                        const hb::FourierBasis& basis, double omega) {
  std::vector<int> harmonics;
  for (const int k : basis.orders())
    if (k >= 2) harmonics.push_back(k);
  return detail::nearest_resonance(system, omega, harmonics, 0.02, std::numeric_limits<double>::infinity());
}

// "k Ω = … is within … % of mode j of the stuck system (ω_j)".
std::string resonance_words(const detail::NearResonance& r, double omega) {
  return fmt::format("{} Ω = {:.6g} rad/s is within {:.2g} % of mode {} of the {} system ({:.6g} rad/s)", r.harmonic,
                     r.harmonic * omega, 100.0 * r.distance, r.mode, r.stuck ? "stuck" : "contact-free", r.omega);
}

// The continuation's view of an EPMC evaluation (its residual and Jacobian moved out of `e`).
Evaluation continuation_evaluation(hb::NonlinearModeResidual::Evaluation& e) {
  Evaluation out;
  out.ok = e.ok;
  out.message = e.message;
  out.residual = std::move(e.residual);
  out.d_state = std::move(e.d_state);
  out.d_parameter = std::move(e.d_parameter);
  return out;
}

// Every output a point reports is a finite number (a curve whose amplitude range reaches ~1e154
// overflows W_D ∝ q² while the state itself is still finite).
bool finite_outputs(const hb::NonlinearModeState& s) {
  for (const double v : {s.amplitude, s.omega, s.damping_ratio, s.dissipation, s.viscous_dissipation,
                         s.injected_energy, s.damping_ratio_energy, s.slip_fraction}) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

}  // namespace

std::string BackboneOptions::validate(int dofs) const {
  if (auto msg = mode.validate(dofs); !msg.empty()) return msg;
  if (!std::isfinite(log10_amplitude_start) || !std::isfinite(log10_amplitude_end)) {
    return "log10_amplitude: must be finite";
  }
  if (log10_amplitude_start == log10_amplitude_end) {
    return "log10_amplitude: end must differ from start";
  }
  if (output_dof < 0 || output_dof >= dofs) {
    return fmt::format("output_dof: must be in [0, {}], got {}", dofs - 1, output_dof);
  }
  if (!(max_damping_ratio >= 0.0) || !std::isfinite(max_damping_ratio)) {
    return fmt::format("max_damping_ratio: must be finite and >= 0 (0: none), got {}", max_damping_ratio);
  }
  if (std::string msg = accuracy.validate({mode.harmonics, mode.time_samples}); !msg.empty()) return msg;
  return {};
}

namespace {

// One continuation run of a discrete damping curve at one level (H, N_t): the EPMC residual, the
// error estimator and the cached last evaluation (segmented_curve.hpp).
class DiscreteBackboneSegment {
 public:
  using Judge = std::function<bool(BackbonePoint&, const Point&)>;

  DiscreteBackboneSegment(const hb::DiscreteSystem& system, const BackboneOptions& options, Level level)
      : options_(options), epmc_(system, mode_at(options.mode, level)), level_(level) {
    // The finer residuals of the estimates; none when the H + 2 basis cannot be built (the points
    // then carry error.known = false).
    if (options.error_estimate || options.accuracy.active()) {
      try {
        estimator_.emplace(system, mode_at(options.mode, level));
      } catch (const std::invalid_argument&) {
        estimator_.reset();
      }
    }
  }

  [[nodiscard]] const hb::NonlinearModeResidual& epmc() const { return epmc_; }
  [[nodiscard]] double error_seconds() const { return error_seconds_; }
  [[nodiscard]] std::optional<double> overflow_at() const { return overflow_at_; }
  [[nodiscard]] const std::vector<BackboneTurn>& turns() const { return turns_; }

  // The linear limit when `from` holds no point: the stuck linear mode (and, should the start
  // corrector fail from it, the slipping one: run()).
  [[nodiscard]] Eigen::VectorXd start_state(const segment_detail::SegmentStart& from) {
    from_linear_limit_ = from.y.size() == 0;
    return from_linear_limit_ ? epmc_.linear_start()
                              : segment_detail::transfer_unknowns(from.y, from.from, epmc_.balance().basis(),
                                                                  epmc_.balance().system().dofs(), 2);
  }

  [[nodiscard]] Options continuation(double lambda0, double end) const {
    Options c = options_.continuation;
    c.parameter_start = lambda0;
    c.parameter_end = end;
    c.direction = end > lambda0 ? 1 : -1;
    c.parameter_scale = std::abs(options_.log10_amplitude_end - options_.log10_amplitude_start);
    // X̂ is O(1) by construction; Ω against its linear value; ξ against a small fraction of ω.
    c.state_scale = Eigen::VectorXd::Ones(epmc_.unknowns());
    c.state_scale[epmc_.unknowns() - 2] = epmc_.linear_omega();
    c.state_scale[epmc_.unknowns() - 1] = 0.1 * epmc_.linear_omega();
    // R̂'s scale: the stiffness seen by the mode, ω² (mass-normalised shape).
    c.residual_scale = epmc_.linear_omega() * epmc_.linear_omega();
    c.outputs = mode_outputs;  // Ω and ζ, for max_output_change
    return c;
  }

  // Discrete estimates are one Newton step each: the truncation part is always made.
  Result run(const Eigen::VectorXd& y0, const Options& c, const Judge& judge,
             const std::function<bool()>& /*wants_truncation*/) {
    // The last evaluation's contact results are kept so that an accepted point's diagnostics cost
    // no extra evaluation when the corrector ended on it (as in trace_frf).
    const ResidualFunction residual = [&](const Eigen::VectorXd& y, double lambda, bool jacobian) {
      last_y_.resize(0);  // an evaluation that throws leaves no valid cache behind
      epmc_.evaluate(y, lambda, jacobian, last_);
      last_y_ = y;
      last_lambda_ = lambda;
      return continuation_evaluation(last_);
    };
    const AcceptCallback accept = [&](const Point& p) {
      BackbonePoint b;
      const bool cached = p.lambda == last_lambda_ && p.x.size() == last_y_.size() && p.x == last_y_;
      b.state = epmc_.state(p.x, p.lambda, cached ? &last_ : nullptr);
      const Eigen::VectorXd x_hat = p.x.head(epmc_.balance().unknowns());  // x = q X̂
      if (!finite_outputs(b.state) ||
          !(epmc_.balance().max_slip_ratio(b.state.amplitude * x_hat) <= contact::kMaxSlipRatio)) {
        overflow_at_ = p.lambda;
        return false;
      }
      b.output_amplitude = b.state.amplitude * epmc_.balance().fundamental_amplitude(x_hat, options_.output_dof);
      b.iterations = p.iterations;
      b.step = p.step;
      b.unknowns = p.x;
      b.harmonics = level_.harmonics;
      b.time_samples = level_.time_samples;
      if (estimator_) {
        const auto estimate_start = support::Clock::now();
        b.error = estimator_->estimate(epmc_, p.x, p.lambda);
        error_seconds_ += support::seconds_since(estimate_start);
      }
      return judge(b, p);
    };
    Result r = trace(residual, y0, c, accept);
    // A curve that starts at large amplitude (e.g. traced from its far end), where the contacts
    // slip and the stuck linear mode is no guess: from the mode with every friction contact slipping.
    if (r.reason == StopReason::start_failed && from_linear_limit_) {
      if (const std::optional<Eigen::VectorXd> slipping = epmc_.slipping_start()) {
        Result again = trace(residual, *slipping, c, accept);
        if (again.reason != StopReason::start_failed) r = std::move(again);
      }
    }
    const std::vector<BackboneTurn> turns = detail::locate_turns(residual, c, r);
    turns_.insert(turns_.end(), turns.begin(), turns.end());
    return r;
  }

 private:
  static hb::NonlinearModeOptions mode_at(hb::NonlinearModeOptions mode, Level level) {
    mode.harmonics = level.harmonics;
    mode.time_samples = level.time_samples;
    return mode;
  }

  const BackboneOptions& options_;
  hb::NonlinearModeResidual epmc_;
  Level level_;
  std::optional<BackboneErrorEstimator> estimator_;
  bool from_linear_limit_ = false;  // the run starts from a linear mode, not a point of the curve
  double error_seconds_ = 0.0;
  hb::NonlinearModeResidual::Evaluation last_;
  Eigen::VectorXd last_y_;
  double last_lambda_ = std::numeric_limits<double>::quiet_NaN();
  std::optional<double> overflow_at_;  // λ of a point whose outputs are not finite or slip too far
  std::vector<BackboneTurn> turns_;
};

// The curve completed from λ_end where its run from λ_start stopped (curve_from_both_ends.hpp):
// `pass(points, turns, meets)` traces from λ_end towards λ_start until `meets` holds. True when
// that run met the curve, which is then joined and reaches λ_end; false leaves the curve as it was
// and says so in its message.
template <class Pass>
bool complete_from_far_end(BackboneCurve& curve, const hb::DiscreteSystem& system, const BackboneOptions& options,
                           const detail::CurveMetric& metric, const Pass& pass) {
  // The joint's check (branch_between) on the EPMC equations at the first level, whose points the
  // metric compares (points of other levels never meet).
  const hb::NonlinearModeResidual epmc(system, options.mode);
  const ResidualFunction residual = [&](const Eigen::VectorXd& y, double lambda, bool jacobian) {
    hb::NonlinearModeResidual::Evaluation e;
    epmc.evaluate(y, lambda, jacobian, e);
    return continuation_evaluation(e);
  };
  const double tolerance =
      10.0 * options.continuation.residual_tolerance * epmc.linear_omega() * epmc.linear_omega();
  const auto unknowns = [](const BackbonePoint& p) -> const Eigen::VectorXd& { return p.unknowns; };
  const auto lambda = [](const BackbonePoint& p) { return std::log10(p.state.amplitude); };
  const auto step = [](const BackbonePoint& p) { return p.step; };
  std::vector<BackbonePoint> back;
  std::vector<BackboneTurn> back_turns;
  std::optional<std::size_t> met;  // in curve.points
  int refused = 0;  // points within one step of the first run where no branch joins the two
  const std::function<bool(const BackbonePoint&)> meets = [&](const BackbonePoint& p) {
    met = detail::meeting_point(curve.points, p, metric, unknowns, lambda, step);
    if (met && !detail::branch_between(residual, metric, curve.points[*met].unknowns, lambda(curve.points[*met]),
                                       p.unknowns, lambda(p), tolerance)) {
      met.reset();
      ++refused;
    }
    return met.has_value();
  };
  const segment_detail::SegmentedOutcome far = pass(back, back_turns, meets);
  curve.level_changes += far.level_changes;
  curve.short_of_accuracy += far.short_points;
  if (!met) {
    curve.message += back.empty()
        ? fmt::format(". Traced from log10 q = {:g} as well, the curve did not start there: {}",
                      options.log10_amplitude_end, far.message)
        : fmt::format(". Traced back from log10 q = {:g} as well, the curve did not meet this run ({} points, "
                      "the last at log10 q = {:.6g}: {})",
                      options.log10_amplitude_end, back.size(), lambda(back.back()), far.message);
    return false;
  }
  const std::size_t k = *met, j = back.size() - 1, first_points = curve.points.size();
  const double first_stop = lambda(curve.points.back()), joint = lambda(curve.points[k]);
  const double joint_step = metric.distance(back[j].unknowns, lambda(back[j]), curve.points[k].unknowns, joint);
  detail::join_from_both_ends(curve.points, curve.turns, k, back, back_turns, j, joint_step);
  curve.reason = StopReason::reached_end;
  curve.message = fmt::format(
      "reached λ_end = {:.10g} ({} points) from both ends: the run from log10 q = {:g} stopped after {} points at "
      "log10 q = {:.6g} ({}); traced back from log10 q = {:g}, the curve met it within one step at its point {} "
      "(log10 q = {:.6g}) after {} points, and is joined there ({} points of the first run beyond it dropped{})",
      options.log10_amplitude_end, curve.points.size(), options.log10_amplitude_start, first_points, first_stop,
      curve.message, options.log10_amplitude_end, k, joint, back.size(), first_points - k - 1,
      refused > 0 ? fmt::format("; {} nearer points on other sheets passed", refused) : "");
  return true;
}

// The joined curve ends at its first point whose ζ reaches max_damping_ratio, as a single run
// does; its λ, or empty when no point does.
std::optional<double> cut_at_damping_ratio(BackboneCurve& curve, double max_damping_ratio) {
  for (std::size_t i = 0; i < curve.points.size(); ++i) {
    if (curve.points[i].state.damping_ratio < max_damping_ratio) continue;
    curve.points.resize(i + 1);
    std::erase_if(curve.turns, [&](const BackboneTurn& t) { return t.after_point > static_cast<int>(i); });
    return std::log10(curve.points.back().state.amplitude);
  }
  return std::nullopt;
}

}  // namespace

BackboneCurve trace_backbone(const hb::DiscreteSystem& system, const BackboneOptions& options,
                             const std::function<bool(const BackbonePoint&)>& on_point) {
  const auto start_time = support::Clock::now();
  if (auto msg = options.validate(system.dofs()); !msg.empty()) throw std::invalid_argument(msg);
  BackboneCurve curve;
  std::optional<double> overflow_at;
  std::optional<hb::FourierBasis> last_basis;  // of the first run, for the internal-resonance message
  std::optional<double> overdamped_at;         // λ of the first point with ζ ≥ max_damping_ratio
  bool user_stopped = false;
  std::optional<detail::CurveMetric> metric;  // the first run's arclength norm (curve_from_both_ends.hpp)
  // One pass over λ from `from` to `to`: its kept points to `points` (and on_point), its turns to
  // `turns`; `meets(point)` returns true to end the pass at a kept point.
  const auto pass = [&](double from, double to, std::vector<BackbonePoint>& points, std::vector<BackboneTurn>& turns,
                        const std::function<bool(const BackbonePoint&)>& meets) {
    const auto make_segment = [&](Level level) {
      auto run = std::make_unique<DiscreteBackboneSegment>(system, options, level);
      if (!last_basis) {
        curve.linear_omega = run->epmc().linear_omega();
        curve.linear_damping_ratio = run->epmc().linear_damping_ratio();
        last_basis = run->epmc().balance().basis();
        const Options c = run->continuation(options.log10_amplitude_start, options.log10_amplitude_end);
        metric = detail::CurveMetric{c.state_scale, c.parameter_scale};
      }
      return run;
    };
    const std::function<bool(BackbonePoint&)> keep = [&](BackbonePoint& b) {
      points.push_back(b);
      if (on_point && !on_point(points.back())) {
        user_stopped = true;
        return false;
      }
      if (!meets && options.max_damping_ratio > 0.0 && b.state.damping_ratio >= options.max_damping_ratio) {
        overdamped_at = std::log10(b.state.amplitude);
        return false;
      }
      return !(meets && meets(points.back()));
    };
    const auto after_run = [&](const DiscreteBackboneSegment& run, const Result& r) {
      curve.newton_iterations += r.corrector_iterations;
      curve.rejected_steps += r.rejected_steps;
      curve.error_seconds += run.error_seconds();
      if (run.overflow_at()) overflow_at = run.overflow_at();
      const std::vector<BackboneTurn> placed =
          detail::place_turns(run.turns(), r, points, [](const BackbonePoint& p) -> const Eigen::VectorXd& { return p.unknowns; });
      turns.insert(turns.end(), placed.begin(), placed.end());
    };
    return segment_detail::trace_in_segments(options.accuracy, {options.mode.harmonics, options.mode.time_samples},
                                             from, to, options.continuation, make_segment, keep, after_run);
  };
  const segment_detail::SegmentedOutcome outcome =
      pass(options.log10_amplitude_start, options.log10_amplitude_end, curve.points, curve.turns, {});
  segment_detail::put_outcome(outcome, curve);
  // A run that stopped short of λ_end by itself (not by the user or a limit of the outputs): why, in
  // physical terms, and the curve completed from λ_end where it can be — also after the run spent
  // max_points, which bounds each run: at an internal resonance the first run can wander through
  // the knot for all of them (four of the light-damping corpus's six 10-DOF chain curves, H = 7: 2000
  // points between log10 q = 0.3 and 3.1), and the run from λ_end meets it after 19–85.
  if (outcome.reason != StopReason::reached_end && !user_stopped && !overflow_at && !overdamped_at &&
      !curve.points.empty()) {
    const double omega = curve.points.back().state.omega;
    const std::optional<detail::NearResonance> resonance = internal_resonance(system, *last_basis, omega);
    if (resonance) {
      curve.message += fmt::format(
          ". {}: the curve runs through a {}:1 internal resonance, where a damping curve turns back in amplitude "
          "and can meet non-smooth points of the friction laws",
          resonance_words(*resonance, omega), resonance->harmonic);
    }
    const bool met = complete_from_far_end(
        curve, system, options, *metric,
        [&](std::vector<BackbonePoint>& back, std::vector<BackboneTurn>& turns,
            const std::function<bool(const BackbonePoint&)>& meets) {
          return pass(options.log10_amplitude_end, options.log10_amplitude_start, back, turns, meets);
        });
    if (!met) overflow_at.reset();  // of the run from λ_end, whose points are not kept
    if (user_stopped) {             // during the run from λ_end: the curve ends as the user asked
      curve.reason = StopReason::stopped_by_user;
      curve.message = "stopped by the callback while the curve was traced from its far end: " + curve.message;
    }
    if (met && options.max_damping_ratio > 0.0)
      overdamped_at = cut_at_damping_ratio(curve, options.max_damping_ratio);
    if (resonance && !met) {
      curve.message += fmt::format(". Harmonics below {} leave that interaction out", resonance->harmonic);
    }
  }
  if (overdamped_at && !overflow_at) {
    const double zeta = curve.points.back().state.damping_ratio;
    curve.reason = StopReason::reached_end;
    curve.message = fmt::format(
        "ended at log10 q = {:.6g} (log10_amplitude end {:g}) where ζ = {:.4g} reached max_damping_ratio {:g}{}",
        *overdamped_at, options.log10_amplitude_end, zeta, options.max_damping_ratio,
        options.max_damping_ratio >= 1.0
            ? ": the mode is overdamped there (the joint dissipates more per cycle than a critically "
              "damped oscillator), beyond it there is no free vibration whose damping the curve could describe"
            : "");
  }
  if (overflow_at) {
    curve.reason = StopReason::out_of_range;
    curve.message = fmt::format(
        "at log10 q = {:.4g} the contacts slip more than {:g} times their stick range μF_N/k_T0, "
        "or an output overflows (W_D or the energies exceed the range of doubles); the curve ends "
        "on the last point before: narrow log10_amplitude",
        *overflow_at, contact::kMaxSlipRatio);
  }
  if (!curve.completed() && !overflow_at && !user_stopped && !curve.points.empty()) {
    if (const hb::NonlinearModeState& last = curve.points.back().state; last.damping_ratio >= 1.0) {
      curve.message += fmt::format(
          ". The curve stopped where the mode is overdamped (ζ = {:.4g} at log10 q = {:.6g}): it does not "
          "vibrate freely there, and the extended periodic motion can turn back at its stick-slip kinks; "
          "max_damping_ratio: 1 ends a damping curve where ζ reaches 1",
          last.damping_ratio, std::log10(last.amplitude));
    }
  }
  curve.seconds = support::seconds_since(start_time);
  return curve;
}

}  // namespace jointhb::continuation
