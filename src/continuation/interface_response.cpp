// FRFs of a preloaded FE joint and the timing record of its curves (interface_response.hpp); the
// damping curves are in interface_backbone.cpp.
#include "jointhb/continuation/interface_response.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>

#include "jointhb/continuation/frf.hpp"
#include "jointhb/continuation/interface_error_estimate.hpp"

#include "../support/stopwatch.hpp"
#include "frf_extrema.hpp"
#include "interface_curve_support.hpp"
#include "segmented_curve.hpp"

namespace jointhb::continuation {

std::string InterfaceTimings::breakdown() const {
  const double other =
      std::max(total - aft - assembly - linear_solve - error_estimate - stability - refinement, 0.0);
  // The estimates' own evaluations and solves are counted in error_estimate only, except the
  // AFT of their evaluation at the point on the curve's balance (in aft).
  const std::string estimates =
      (error_estimate > 0.0 ? fmt::format(", error estimates {:.3g} s", error_estimate) : std::string()) +
      (stability > 0.0 ? fmt::format(", stability {:.3g} s", stability) : std::string()) +
      (refinement > 0.0 ? fmt::format(", folds and peak {:.3g} s", refinement) : std::string());
  if (products == 0.0 && preconditioner == 0.0)
    return fmt::format("{:.3g} s: AFT {:.3g} s ({} evaluations), assembly {:.3g} s, linear solves {:.3g} s "
                       "({} factorisations){}, other {:.3g} s",
                       total, aft, evaluations, assembly, linear_solve, factorisations, estimates, other);
  // Products run inside the linear solves (GMRES) and, for the EPMC's ∂R/∂λ, in the evaluations.
  return fmt::format("{:.3g} s: AFT {:.3g} s ({} evaluations), assembly {:.3g} s, linear solves {:.3g} s "
                     "({} GMRES iterations; preconditioner {} builds {:.3g} s, {} applications {:.3g} s), "
                     "Jacobian products {:.3g} s ({}){}, other {:.3g} s",
                     total, aft, evaluations, assembly, linear_solve, krylov_iterations, factorisations,
                     preconditioner, preconditioner_calls, preconditioner_apply, products, product_calls, estimates,
                     other);
}

std::string InterfaceFrfOptions::validate(const hb::InterfaceModel& model) const {
  if (!(omega_start > 0.0) || !std::isfinite(omega_start))
    return fmt::format("omega_start: must be finite and > 0, got {}", omega_start);
  if (!(omega_end > 0.0) || !std::isfinite(omega_end))
    return fmt::format("omega_end: must be finite and > 0, got {}", omega_end);
  if (omega_start == omega_end) return "omega_end: must differ from omega_start";
  if (!std::isfinite(load_amplitude) || load_amplitude == 0.0)
    return fmt::format("load_amplitude: must be finite and ≠ 0, got {}", load_amplitude);
  if (output < 0 || output >= static_cast<int>(model.outputs.size()))
    return fmt::format("output: must be in [0, {}), got {}", model.outputs.size(), output);
  if (std::string msg = accuracy.validate({balance.harmonics, balance.time_samples}); !msg.empty()) return msg;
  if (auto msg = monodromy.validate(); !msg.empty()) return "monodromy." + msg;
  if (auto msg = hill.validate(); !msg.empty()) return "hill." + msg;
  return balance.validate();
}

bool computes_interface_stability(Stability stability, int points, StabilityMethod method, int harmonics) {
  if (stability != Stability::automatic) return stability == Stability::always;
  if (method == StabilityMethod::hill) return 3L * points * (2L * harmonics + 1) <= kAutomaticInterfaceHillGapUnknowns;
  return points <= kAutomaticInterfaceStabilityPoints;
}

namespace {

// One continuation run of a finite-element FRF at one level (H, N_t): the balance, the load, the
// error estimator and the cached last evaluation (segmented_curve.hpp).
class InterfaceFrfSegment {
 public:
  using Judge = std::function<bool(InterfaceFrfPoint&, const Point&)>;

  InterfaceFrfSegment(const hb::InterfaceModel& model, const InterfaceFrfOptions& options, Level level,
                      const std::vector<InterfaceFrfPoint>& curve_points)
      : model_(model),
        options_(options),
        curve_points_(curve_points),
        matrix_free_(options.matrix_free && options.continuation.linear_solver == LinearSolver::newton_krylov),
        balance_options_(balance_at(options, level, matrix_free_)),
        balance_(model, balance_options_),
        load_(balance_.cosine_load(options.load_amplitude)),
        level_(level) {
    if (options.error_estimate || options.accuracy.active())
      estimator_.emplace(model, balance_options_, options.load_amplitude, options.output);
  }

  [[nodiscard]] const hb::InterfaceBalance& balance() const { return balance_; }
  [[nodiscard]] double error_seconds() const { return error_seconds_; }
  [[nodiscard]] double stability_seconds() const { return stability_seconds_; }
  [[nodiscard]] const std::vector<std::size_t>& kept() const { return kept_; }

  // The linear response at Ω_start, or the start's unknowns transferred to this level.
  [[nodiscard]] Eigen::VectorXd start_state(const segment_detail::SegmentStart& from) const {
    return from.y.size() == 0 ? balance_.linear_solution(options_.omega_start, load_)
                              : segment_detail::transfer_unknowns(from.y, from.from, balance_.basis(),
                                                                  balance_.modes() + 3 * balance_.points());
  }

  [[nodiscard]] Options continuation(double omega0, double end) {
    Options c = options_.continuation;
    c.parameter_start = omega0;
    c.parameter_end = end;
    c.direction = end > omega0 ? 1 : -1;
    c.parameter_scale = std::abs(options_.omega_end - options_.omega_start);
    // Scales: the static modal response |φᵀf| F / ω_ref² (rows and η), g_ref per unit η for gaps.
    const double w2 = balance_.reference_omega() * balance_.reference_omega();
    const double eta = std::abs(options_.load_amplitude) *
                       std::max(model_.load_modal.lpNorm<Eigen::Infinity>(), 1e-300) / w2;
    // Near resonance the response is the static one amplified by about 1/(2ζ) of the first elastic
    // mode: scale the state by that, so that the arclength is not dominated by it.
    const int elastic = model_.rigid_modes;
    const double zeta = std::max((model_.rayleigh_mass + model_.rayleigh_stiffness * model_.omega2[elastic]) /
                                     (2.0 * std::sqrt(model_.omega2[elastic])),
                                 1e-4);
    c.state_scale = eta / (2.0 * zeta) * interface_detail::arclength_scale(balance_);
    c.residual_scale = eta;
    if (c.max_state_turn == 0.0) c.max_state_turn = kMaxStateTurn;  // frf.hpp
    // |fundamental| of the output, for max_output_change: from the corrector's last evaluation,
    // which is at the converged point (one more evaluation otherwise).
    continuation_ = c;  // with the outputs below, for the refinement of the extrema
    c.outputs = [this](const Eigen::VectorXd& x, double omega) {
      if (omega != last_omega_ || x.size() != last_x_.size() || x != last_x_) {
        last_x_.resize(0);
        balance_.evaluate(x, omega, 0.0, load_, false, last_);
        last_x_ = x;
        last_omega_ = omega;
      }
      const Eigen::VectorXd u = balance_.output_coefficients(options_.output, x, omega, 0.0, load_, last_.contact_force);
      const int a1 = balance_.basis().cosine_index(1);
      return Eigen::VectorXd::Constant(1, std::hypot(u[a1], u[a1 + 1]));
    };
    return c;
  }

  Result run(const Eigen::VectorXd& x0, const Options& c, const Judge& judge,
             const std::function<bool()>& wants_truncation) {
    const AcceptCallback accept = [&](const Point& p) {
      if (p.lambda != last_omega_ || p.x.size() != last_x_.size() || p.x != last_x_)
        balance_.evaluate(p.x, p.lambda, 0.0, load_, false, last_);
      InterfaceFrfPoint f;
      f.omega = p.lambda;
      const Eigen::VectorXd u =
          balance_.output_coefficients(options_.output, p.x, p.lambda, 0.0, load_, last_.contact_force);
      const int a1 = balance_.basis().cosine_index(1);
      f.amplitude_h1 = std::hypot(u[a1], u[a1 + 1]);
      f.amplitude_max = balance_.basis().peak_magnitude(u);
      f.dissipation = last_.dissipation;
      f.open_points = last_.open_points;
      f.slipping_points = last_.slipping_points;
      f.states = last_.states;
      f.iterations = p.iterations;
      f.unknowns = p.x;
      f.harmonics = level_.harmonics;
      f.time_samples = level_.time_samples;
      if (estimator_) {
        const auto estimate_start = support::Clock::now();
        // `last_` is at the point (above); the truncation part always where estimates were asked for.
        f.error = estimator_->estimate(balance_, p.x, p.lambda, &last_, options_.error_estimate || wants_truncation());
        error_seconds_ += support::seconds_since(estimate_start);
      }
      f.fold = p.fold;
      const std::size_t before = curve_points_.size();
      const bool go_on = judge(f, p);
      if (curve_points_.size() > before) {  // kept (judge appended it)
        kept_.push_back(before);
        tangents_.push_back(p.tangent);
      }
      return go_on;
    };
    Result r = trace(residual_, x0, c, accept);
    if (r.reason == StopReason::start_failed) {
      // Newton from the stuck linear response fails where the contacts slip far at Ω_start (the
      // one-point joint of the tests at 0.8 rad/s, force 0.2: "no decrease of the residual along
      // the Newton step"). Ramp the load from zero at Ω_start instead, as the discrete FRF does
      // (frf.cpp, force_ramp), and start from the ramp's end.
      std::string why;
      if (const std::optional<Eigen::VectorXd> start = load_ramp(c, why)) {
        const int failed_iterations = r.corrector_iterations;
        r = trace(residual_, *start, c, accept);
        r.corrector_iterations += failed_iterations;
      } else {
        r.message += "; " + why;
      }
    }
    return r;
  }

  // What only a kept point needs (segmented_curve.hpp): its stability, not paid for a point that a
  // finer level traces again (options.accuracy).
  void complete(InterfaceFrfPoint& f, const Point& p) { add_stability(f, p); }

  // The folds (and with `peak` the peak) of this run's kept points (frf_extrema.hpp), by bordered
  // Newton on the run's own Jacobian: dense, or matrix-free with GMRES and the run's preconditioner.
  detail::FrfExtrema extrema(bool peak) {
    return detail::locate_frf_extrema(residual_, continuation_,
                                      detail::run_points(curve_points_, kept_, tangents_, &InterfaceFrfPoint::unknowns),
                                      amplitude_quantity(), peak);
  }

 private:
  // |fundamental| of the output at (ŷ, Ω) (eq. T-25: its residual part needs the contact forces,
  // one evaluation), its slope along a direction by central differences (10⁻⁶ of the scaled unit
  // tangent the refinement passes).
  detail::CurveQuantity amplitude_quantity() const {
    detail::CurveQuantity q;
    q.value = [this](const Eigen::VectorXd& x, double omega) {
      hb::InterfaceBalanceEvaluation at;
      balance_.evaluate(x, omega, 0.0, load_, false, at);
      const Eigen::VectorXd u = balance_.output_coefficients(options_.output, x, omega, 0.0, load_, at.contact_force);
      const int a1 = balance_.basis().cosine_index(1);
      return std::hypot(u[a1], u[a1 + 1]);
    };
    q.slope = [value = q.value](const Eigen::VectorXd& x, double omega, const Eigen::VectorXd& dx, double dw) {
      constexpr double h = 1e-6;
      return (value(x + h * dx, omega + h * dw) - value(x - h * dx, omega - h * dw)) / (2.0 * h);
    };
    return q;
  }

  static hb::InterfaceBalanceOptions balance_at(const InterfaceFrfOptions& options, Level level, bool matrix_free) {
    hb::InterfaceBalanceOptions b = options.balance;
    b.harmonics = level.harmonics;
    b.time_samples = level.time_samples;
    if (matrix_free) b.dense_jacobian = false;
    return b;
  }

  // The solution at Ω = c.parameter_start under the full load, by continuation in the load factor
  // s ∈ [0, 1] from the preloaded state (s = 0: no motion): R_s(x) = R(x) + (s − 1) ℓ, where
  // ℓ = R(x, load) − R(x, 0) is the load's part of the residual (affine in the load, independent
  // of x), ∂R_s/∂s = ℓ.
  std::optional<Eigen::VectorXd> load_ramp(const Options& c, std::string& why) {
    const double omega = c.parameter_start;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(balance_.unknowns());
    hb::InterfaceBalanceEvaluation loaded, unloaded;
    balance_.evaluate(zero, omega, 0.0, load_, false, loaded);
    balance_.evaluate(zero, omega, 0.0, Eigen::VectorXd::Zero(load_.size()), false, unloaded);
    const Eigen::VectorXd load_part = loaded.residual - unloaded.residual;
    Options h = c;
    h.outputs = nullptr;  // they read λ as Ω
    h.max_output_change = 0.0;
    const Result ramp = segment_detail::trace_load_ramp(residual_, omega, load_part, zero, h);
    if (ramp.completed()) return ramp.points.back().x;
    why = "load ramp at Ω_start: " + ramp.message;
    return std::nullopt;
  }

  // The Floquet multipliers of an accepted point (options.stability) and what changed since the
  // previous one of this run; without them, a turn of Ω is reported as a fold.
  void add_stability(InterfaceFrfPoint& f, const Point& p) {
    if (!computes_interface_stability(options_.stability, balance_.points(), options_.stability_method,
                                      balance_.options().harmonics)) {
      if (p.fold) f.bifurcation = hb::Bifurcation::fold;
      return;
    }
    const auto start = support::Clock::now();
    hb::FloquetResult floquet =
        options_.stability_method == StabilityMethod::hill
            ? hb::interface_hill_floquet(balance_, p.x, p.lambda, options_.hill)
            : hb::interface_orbit_floquet(balance_, p.x, p.lambda, options_.monodromy);
    stability_seconds_ += support::seconds_since(start);
    f.stability_known = floquet.ok;
    f.stable = floquet.stable();
    f.max_multiplier = floquet.max_multiplier;
    f.unstable_multipliers = floquet.unstable;
    f.multipliers = floquet.multipliers;
    if (previous_floquet_) f.bifurcation = hb::classify_bifurcation(*previous_floquet_, floquet, p.fold);
    previous_floquet_ = std::move(floquet);
  }

  Evaluation evaluate(const Eigen::VectorXd& x, double omega, bool jacobian) {
    last_x_.resize(0);
    balance_.evaluate(x, omega, 0.0, load_, jacobian, last_);
    last_x_ = x;
    last_omega_ = omega;
    Evaluation e;
    e.ok = last_.ok;
    e.message = last_.message;
    e.residual = last_.residual;
    if (jacobian && matrix_free_) {
      auto at = std::make_shared<const hb::InterfaceBalanceEvaluation>(last_);
      const hb::InterfaceBalance& balance = balance_;
      e.d_parameter = last_.d_omega;
      e.d_state_product = [&balance, at, omega](const Eigen::VectorXd& v) {
        return balance.apply_jacobian(*at, omega, 0.0, v);
      };
      if (options_.mixed_precision)
        e.d_state_product_inner = [&balance, at, omega](const Eigen::VectorXd& v) {
          return balance.apply_jacobian(*at, omega, 0.0, v, true);
        };
      e.make_preconditioner = [&balance, at, omega, kind = options_.preconditioner]() -> LinearOperator {
        return balance.preconditioner(*at, omega, 0.0, kind);
      };
    } else if (jacobian) {
      e.d_state = std::move(last_.jacobian);
      e.d_parameter = last_.d_omega;
    }
    return e;
  }

  const hb::InterfaceModel& model_;
  const InterfaceFrfOptions& options_;
  const std::vector<InterfaceFrfPoint>& curve_points_;
  bool matrix_free_;
  hb::InterfaceBalanceOptions balance_options_;
  hb::InterfaceBalance balance_;
  Eigen::VectorXd load_;
  Level level_;
  std::optional<InterfaceFrfErrorEstimator> estimator_;
  double error_seconds_ = 0.0;
  double stability_seconds_ = 0.0;
  std::optional<hb::FloquetResult> previous_floquet_;
  Options continuation_;                     // of the run (scales, tolerances)
  std::vector<std::size_t> kept_;            // the kept points' indices in the curve
  std::vector<Eigen::VectorXd> tangents_;    // and their unit tangents
  hb::InterfaceBalanceEvaluation last_;
  Eigen::VectorXd last_x_;
  double last_omega_ = std::numeric_limits<double>::quiet_NaN();
  // The run's residual (evaluate above), for the continuation, the load ramp and the extrema.
  const ResidualFunction residual_ = [this](const Eigen::VectorXd& x, double omega, bool jacobian) {
    return evaluate(x, omega, jacobian);
  };
};

}  // namespace

InterfaceFrf trace_interface_frf(const hb::InterfaceModel& model, const InterfaceFrfOptions& options,
                                 const std::function<bool(const InterfaceFrfPoint&)>& on_point) {
  const auto start = support::Clock::now();
  if (std::string msg = options.validate(model); !msg.empty()) throw std::invalid_argument(msg);
  InterfaceFrf curve;
  std::vector<std::unique_ptr<InterfaceFrfSegment>> segments;  // kept alive for the folds and the peak
  const auto make_segment = [&](Level level) {
    segments.push_back(std::make_unique<InterfaceFrfSegment>(model, options, level, curve.points));
    if (curve.unknowns == 0) curve.unknowns = segments.back()->balance().unknowns();
    return segments.back().get();
  };
  const std::function<bool(InterfaceFrfPoint&)> keep = segment_detail::append_to(curve.points, on_point);
  const auto after_run = [&](const InterfaceFrfSegment& run, const Result& r) {
    curve.newton_iterations += r.corrector_iterations;
    curve.rejected_steps += r.rejected_steps;
    interface_detail::add_curve_timings(curve.timings, run.balance().timings(), r);
    curve.timings.error_estimate += run.error_seconds();
    curve.timings.stability += run.stability_seconds();
  };
  const segment_detail::SegmentedOutcome outcome = segment_detail::trace_in_segments(
      options.accuracy, {options.balance.harmonics, options.balance.time_samples}, options.omega_start,
      options.omega_end, options.continuation, make_segment, keep, after_run);
  if (options.refine_extrema) {
    const auto refinement_start = support::Clock::now();
    detail::locate_in_segments(segments, curve, [](InterfaceFrfSegment& run, bool peak) { return run.extrema(peak); });
    curve.timings.refinement = support::seconds_since(refinement_start);
  }
  segment_detail::put_outcome(outcome, curve);
  curve.timings.total = support::seconds_since(start);
  return curve;
}

}  // namespace jointhb::continuation
