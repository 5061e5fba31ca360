// Damping curves by EPMC continued over log10 q (continuation/backbone.hpp).
#include "jointhb/continuation/backbone.hpp"

#include "../support/stopwatch.hpp"
#include "linear_limits.hpp"
#include "mode_outputs.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include "jointhb/contact/harmonic_loop.hpp"

namespace jointhb::continuation {
namespace {

// Why a damping curve that did not reach its end stopped, in physical terms, or empty: a harmonic
// k Ω of the last point (k ≥ 2 among the kept orders) within 2 % of a natural frequency ω_j of the
// stuck or the contact-free linear system. There the followed mode exchanges energy with mode j
// (a k:1 internal resonance): the EPMC curve turns back in amplitude and can meet non-smooth
// points of the friction laws it does not pass.
std::string internal_resonance(const hb::DiscreteSystem& system, const hb::FourierBasis& basis,
                               double omega) {
  std::vector<int> harmonics;
  for (const int k : basis.orders())
    if (k >= 2) harmonics.push_back(k);
  const std::optional<detail::NearResonance> best =
      detail::nearest_resonance(system, omega, harmonics, 0.02, std::numeric_limits<double>::infinity());
  if (!best) return {};
  return fmt::format(
      "{} Ω = {:.6g} rad/s is within {:.2g} % of mode {} of the {} system ({:.6g} rad/s): the curve "
      "runs through a {}:1 internal resonance, where a damping curve turns back in amplitude and "
      "can meet non-smooth points of the friction laws; harmonics below {} leave that interaction "
      "out, or trace the curve in pieces on either side of it",
      best->harmonic, best->harmonic * omega, 100.0 * best->distance, best->mode,
      best->stuck ? "stuck" : "contact-free", best->omega, best->harmonic, best->harmonic);
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
  return {};
}

BackboneCurve trace_backbone(const hb::DiscreteSystem& system, const BackboneOptions& options,
                             const std::function<bool(const BackbonePoint&)>& on_point) {
  const auto start_time = support::Clock::now();
  if (auto msg = options.validate(system.dofs()); !msg.empty()) throw std::invalid_argument(msg);
  const hb::NonlinearModeResidual epmc(system, options.mode);
  BackboneCurve curve;
  curve.linear_omega = epmc.linear_omega();
  curve.linear_damping_ratio = epmc.linear_damping_ratio();

  Options c = options.continuation;
  c.parameter_start = options.log10_amplitude_start;
  c.parameter_end = options.log10_amplitude_end;
  c.direction = c.parameter_end > c.parameter_start ? 1 : -1;
  c.parameter_scale = std::abs(c.parameter_end - c.parameter_start);
  // X̂ is O(1) by construction; Ω against its linear value; ξ against a small fraction of ω.
  c.state_scale = Eigen::VectorXd::Ones(epmc.unknowns());
  c.state_scale[epmc.unknowns() - 2] = epmc.linear_omega();
  c.state_scale[epmc.unknowns() - 1] = 0.1 * epmc.linear_omega();

  // The finer residuals of the error estimates (error_estimate.hpp); none when the H + 2 basis
  // cannot be built (the points then carry error.known = false).
  std::optional<BackboneErrorEstimator> estimator;
  if (options.error_estimate) {
    try {
      estimator.emplace(system, options.mode);
    } catch (const std::invalid_argument&) {
      estimator.reset();
    }
  }

  // The last evaluation's contact results are kept so that an accepted point's diagnostics cost
  // no extra evaluation when the corrector ended on it (as in trace_frf).
  hb::NonlinearModeResidual::Evaluation last;
  Eigen::VectorXd last_y;
  double last_lambda = std::numeric_limits<double>::quiet_NaN();
  const ResidualFunction residual = [&](const Eigen::VectorXd& y, double lambda, bool jacobian) {
    last_y.resize(0);  // an evaluation that throws leaves no valid cache behind
    epmc.evaluate(y, lambda, jacobian, last);
    last_y = y;
    last_lambda = lambda;
    Evaluation out;
    out.ok = last.ok;
    out.message = last.message;
    out.residual = std::move(last.residual);
    out.d_state = std::move(last.d_state);
    out.d_parameter = std::move(last.d_parameter);
    return out;
  };
  // R̂'s scale: the stiffness seen by the mode, ω² (mass-normalised shape).
  c.residual_scale = epmc.linear_omega() * epmc.linear_omega();
  c.outputs = mode_outputs;  // Ω and ζ, for max_output_change

  // λ of a converged point whose outputs are not finite or whose contacts slip beyond the range
  // the laws are computed in.
  std::optional<double> overflow_at;
  const AcceptCallback accept = [&](const Point& p) {
    BackbonePoint b;
    const bool cached = p.lambda == last_lambda && p.x.size() == last_y.size() && p.x == last_y;
    b.state = epmc.state(p.x, p.lambda, cached ? &last : nullptr);
    const Eigen::VectorXd x_hat = p.x.head(epmc.balance().unknowns());  // x = q X̂
    if (!finite_outputs(b.state) ||
        !(epmc.balance().max_slip_ratio(b.state.amplitude * x_hat) <= contact::kMaxSlipRatio)) {
      overflow_at = p.lambda;
      return false;
    }
    b.output_amplitude = b.state.amplitude * epmc.balance().fundamental_amplitude(x_hat, options.output_dof);
    b.iterations = p.iterations;
    b.step = p.step;
    b.unknowns = p.x;
    if (estimator) {
      const auto estimate_start = support::Clock::now();
      b.error = estimator->estimate(epmc, p.x, p.lambda);
      curve.error_seconds += support::seconds_since(estimate_start);
    }
    curve.points.push_back(b);
    return on_point ? on_point(b) : true;
  };
  const Result r = trace(residual, epmc.linear_start(), c, accept);
  curve.reason = r.reason;
  curve.message = r.message;
  if (overflow_at) {
    curve.reason = StopReason::out_of_range;
    curve.message = fmt::format(
        "at log10 q = {:.4g} the contacts slip more than {:g} times their stick range μF_N/k_T0, "
        "or an output overflows (W_D or the energies exceed the range of doubles); the curve ends "
        "on the last point before: narrow log10_amplitude",
        *overflow_at, contact::kMaxSlipRatio);
  }
  if (!r.completed() && !overflow_at && r.reason != StopReason::stopped_by_user && !curve.points.empty()) {
    const std::string why = internal_resonance(system, epmc.balance().basis(), curve.points.back().state.omega);
    if (!why.empty()) curve.message += ". " + why;
  }
  curve.newton_iterations = r.corrector_iterations;
  curve.rejected_steps = r.rejected_steps;
  curve.seconds = support::seconds_since(start_time);
  return curve;
}

}  // namespace jointhb::continuation
