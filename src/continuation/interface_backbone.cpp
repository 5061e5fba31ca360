// Damping curves of a preloaded FE joint (continuation/interface_response.hpp): at fixed harmonics
// and time samples, or with both chosen per point from the error estimates (continuation/accuracy.hpp,
// docs/theory.md §13 eq. T-44).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>

#include "jointhb/continuation/accuracy.hpp"
#include "jointhb/continuation/interface_error_estimate.hpp"
#include "jointhb/continuation/interface_response.hpp"

#include "../support/stopwatch.hpp"
#include "curve_turns.hpp"
#include "interface_curve_support.hpp"
#include "mode_outputs.hpp"
#include "segmented_curve.hpp"

namespace jointhb::continuation {
namespace {

// Whether the curve at `level` is dense (InterfaceBackboneOptions::dense_below): EPMC unknowns
// (n_s + 3P)(2H + 1) + 2, every harmonic 0..H kept.
bool dense_at(const hb::InterfaceModel& model, const InterfaceBackboneOptions& options, Level level) {
  const Eigen::Index unknowns =
      static_cast<Eigen::Index>(model.num_modes() + 3 * model.num_points()) * (2 * level.harmonics + 1) + 2;
  return unknowns <= options.dense_below;
}

// The options of the curve's EPMC residual at `level`.
hb::InterfaceModeOptions interface_mode_at(const InterfaceBackboneOptions& options, Level level, bool matrix_free) {
  hb::InterfaceModeOptions mode = options.mode;
  mode.balance.harmonics = level.harmonics;
  mode.balance.time_samples = level.time_samples;
  mode.balance.dense_jacobian = !matrix_free;
  return mode;
}

// One continuation run of a damping curve at one level (H, N_t): the EPMC residual, the error
// estimator and the cached last evaluation. `judge` sees every accepted point (built here, with
// its estimates) and returns false to end the run.
class InterfaceBackboneSegment {
 public:
  using Judge = std::function<bool(InterfaceBackbonePoint&, const Point&)>;

  InterfaceBackboneSegment(const hb::InterfaceModel& model, const InterfaceBackboneOptions& options, Level level)
      : options_(options),
        dense_(dense_at(model, options, level)),
        matrix_free_(!dense_ && options.matrix_free && options.continuation.linear_solver == LinearSolver::newton_krylov),
        mode_(interface_mode_at(options, level, matrix_free_)),
        epmc_(model, mode_),
        level_(level) {
    if (options.error_estimate || options.accuracy.active()) estimator_.emplace(model, mode_);
  }

  [[nodiscard]] const hb::InterfaceModeResidual& epmc() const { return epmc_; }

  // The linear limit, or the start's unknowns transferred to this level.
  [[nodiscard]] Eigen::VectorXd start_state(const segment_detail::SegmentStart& from) const {
    const hb::InterfaceBalance& b = epmc_.balance();
    return from.y.size() == 0 ? epmc_.linear_start()
                              : segment_detail::transfer_unknowns(from.y, from.from, b.basis(), b.modes() + 3 * b.points(), 2);
  }
  [[nodiscard]] double error_seconds() const { return error_seconds_; }

  // The options of the run from λ0 (range and scales of this level; steps and budget the caller's).
  [[nodiscard]] Options continuation(double lambda0, double end) const {
    Options c = options_.continuation;
    if (dense_) c.linear_solver = LinearSolver::dense_lu;
    c.parameter_start = lambda0;
    c.parameter_end = end;
    c.direction = end > lambda0 ? 1 : -1;
    c.parameter_scale = std::abs(options_.log10_amplitude_end - options_.log10_amplitude_start);
    const Eigen::Index U = epmc_.balance().unknowns();
    c.state_scale.resize(U + 2);
    c.state_scale.head(U) = interface_detail::arclength_scale(epmc_.balance());
    c.state_scale[U] = epmc_.linear_omega();
    c.state_scale[U + 1] = 0.1 * epmc_.linear_omega();
    c.residual_scale = 1.0;    // rows are in units of the (unit) modal amplitude
    c.outputs = mode_outputs;  // Ω and ζ, for max_output_change
    return c;
  }

  Result run(const Eigen::VectorXd& y0, const Options& c, const Judge& judge,
             const std::function<bool()>& wants_truncation) {
    const ResidualFunction residual = [&](const Eigen::VectorXd& y, double lambda, bool jacobian) {
      return evaluate(y, lambda, jacobian);
    };
    const AcceptCallback accept = [&](const Point& p) {
      InterfaceBackbonePoint b;
      const bool cached = p.lambda == last_lambda_ && p.x.size() == last_y_.size() && p.x == last_y_;
      b.state = epmc_.state(p.x, p.lambda, cached ? &last_ : nullptr);
      b.iterations = p.iterations;
      b.step = p.step;
      b.unknowns = p.x;
      b.harmonics = level_.harmonics;
      b.time_samples = level_.time_samples;
      if (estimator_) {
        const auto estimate_start = support::Clock::now();
        // The corrector's last evaluation is at the point and, matrix-free, keeps its point blocks.
        // The truncation part always where estimates were asked for.
        b.error = estimator_->estimate(epmc_, p.x, p.lambda, cached ? &last_ : nullptr,
                                       options_.error_estimate || wants_truncation());
        error_seconds_ += support::seconds_since(estimate_start);
      }
      return judge(b, p);
    };
    Result r = trace(residual, y0, c, accept);
    add_turns(residual, c, r);
    return r;
  }

  [[nodiscard]] const std::vector<BackboneTurn>& turns() const { return turns_; }

 private:
  // The turns of run r (curve_turns.hpp), refined with the dense Jacobian; matrix-free there is
  // none to refine them with.
  void add_turns(const ResidualFunction& residual, const Options& c, const Result& r) {
    const std::vector<BackboneTurn> turns =
        matrix_free_ ? detail::locate_turns({}, c, r, "not refined: the curve was traced matrix-free")
                     : detail::locate_turns(residual, c, r);
    turns_.insert(turns_.end(), turns.begin(), turns.end());
  }

  Evaluation evaluate(const Eigen::VectorXd& y, double lambda, bool jacobian) {
    last_y_.resize(0);
    epmc_.evaluate(y, lambda, jacobian, last_);
    last_y_ = y;
    last_lambda_ = lambda;
    Evaluation out;
    out.ok = last_.ok;
    out.message = last_.message;
    out.residual = last_.residual;
    if (jacobian && matrix_free_) {
      // The operator keeps its own copy of the point blocks: `last_` is overwritten by the next call.
      auto at = std::make_shared<const hb::InterfaceModeResidual::Evaluation>(last_);
      const hb::InterfaceModeResidual& epmc = epmc_;
      out.d_parameter = last_.d_parameter;
      out.d_state_product = [&epmc, at, y, lambda](const Eigen::VectorXd& v) {
        return epmc.apply_jacobian(*at, y, lambda, v);
      };
      if (options_.mixed_precision)
        out.d_state_product_inner = [&epmc, at, y, lambda](const Eigen::VectorXd& v) {
          return epmc.apply_jacobian(*at, y, lambda, v, true);
        };
      out.make_preconditioner = [&epmc, at, y, lambda, kind = options_.preconditioner]() -> LinearOperator {
        return epmc.preconditioner(*at, y, lambda, kind);
      };
    } else if (jacobian) {
      out.d_state = std::move(last_.d_state);
      out.d_parameter = std::move(last_.d_parameter);
    }
    return out;
  }

  const InterfaceBackboneOptions& options_;
  bool dense_;  // dense Jacobian and dense LU whatever the options say (dense_below)
  bool matrix_free_;
  hb::InterfaceModeOptions mode_;
  hb::InterfaceModeResidual epmc_;
  Level level_;
  std::optional<InterfaceBackboneErrorEstimator> estimator_;
  double error_seconds_ = 0.0;
  hb::InterfaceModeResidual::Evaluation last_;
  Eigen::VectorXd last_y_;
  double last_lambda_ = std::numeric_limits<double>::quiet_NaN();
  std::vector<BackboneTurn> turns_;
};

}  // namespace

std::string InterfaceBackboneOptions::validate(const hb::InterfaceModel& model) const {
  if (std::string msg = mode.validate(model); !msg.empty()) return msg;
  if (!std::isfinite(log10_amplitude_start) || !std::isfinite(log10_amplitude_end))
    return "log10_amplitude: must be finite";
  if (log10_amplitude_start == log10_amplitude_end) return "log10_amplitude: end must differ from start";
  if (dense_below < 0) return fmt::format("dense_below: must be >= 0 (0: never dense), got {}", dense_below);
  if (std::string msg = accuracy.validate({mode.balance.harmonics, mode.balance.time_samples}); !msg.empty()) return msg;
  return {};
}

InterfaceBackbone trace_interface_backbone(const hb::InterfaceModel& model, const InterfaceBackboneOptions& options,
                                           const std::function<bool(const InterfaceBackbonePoint&)>& on_point) {
  const auto start = support::Clock::now();
  if (std::string msg = options.validate(model); !msg.empty()) throw std::invalid_argument(msg);
  InterfaceBackbone curve;
  const auto make_segment = [&](Level level) {
    auto run = std::make_unique<InterfaceBackboneSegment>(model, options, level);
    if (curve.unknowns == 0) {
      curve.linear_omega = run->epmc().linear_omega();
      curve.linear_damping_ratio = run->epmc().linear_damping_ratio();
      curve.unknowns = run->epmc().unknowns();
    }
    return run;
  };
  const std::function<bool(InterfaceBackbonePoint&)> keep = segment_detail::append_to(curve.points, on_point);
  const auto after_run = [&](const InterfaceBackboneSegment& run, const Result& r) {
    curve.newton_iterations += r.corrector_iterations;
    curve.rejected_steps += r.rejected_steps;
    interface_detail::add_curve_timings(curve.timings, run.epmc().balance().timings(), r);
    curve.timings.error_estimate += run.error_seconds();
    const std::vector<BackboneTurn> placed = detail::place_turns(
        run.turns(), r, curve.points, [](const InterfaceBackbonePoint& p) -> const Eigen::VectorXd& { return p.unknowns; });
    curve.turns.insert(curve.turns.end(), placed.begin(), placed.end());
  };
  const segment_detail::SegmentedOutcome outcome = segment_detail::trace_in_segments(
      options.accuracy, {options.mode.balance.harmonics, options.mode.balance.time_samples},
      options.log10_amplitude_start, options.log10_amplitude_end, options.continuation, make_segment, keep, after_run);
  segment_detail::put_outcome(outcome, curve);
  curve.timings.total = support::seconds_since(start);
  return curve;
}

}  // namespace jointhb::continuation
