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

#include "jointhb/continuation/interface_error_estimate.hpp"

#include "../support/stopwatch.hpp"
#include "interface_curve_support.hpp"

namespace jointhb::continuation {

std::string InterfaceTimings::breakdown() const {
  const double other = std::max(total - aft - assembly - linear_solve - error_estimate, 0.0);
  // The estimates' own evaluations and solves are counted in error_estimate only, except the
  // AFT of their evaluation at the point on the curve's balance (in aft).
  const std::string estimates =
      error_estimate > 0.0 ? fmt::format(", error estimates {:.3g} s", error_estimate) : std::string();
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
  return balance.validate();
}

InterfaceFrf trace_interface_frf(const hb::InterfaceModel& model, const InterfaceFrfOptions& options,
                                 const std::function<bool(const InterfaceFrfPoint&)>& on_point) {
  const auto start = support::Clock::now();
  if (std::string msg = options.validate(model); !msg.empty()) throw std::invalid_argument(msg);
  const bool matrix_free =
      options.matrix_free && options.continuation.linear_solver == LinearSolver::newton_krylov;
  hb::InterfaceBalanceOptions balance_options = options.balance;
  if (matrix_free) balance_options.dense_jacobian = false;
  const hb::InterfaceBalance balance(model, balance_options);
  const Eigen::VectorXd load = balance.cosine_load(options.load_amplitude);
  InterfaceFrf curve;
  curve.unknowns = balance.unknowns();

  Options c = options.continuation;
  c.parameter_start = options.omega_start;
  c.parameter_end = options.omega_end;
  c.direction = options.omega_end > options.omega_start ? 1 : -1;
  c.parameter_scale = std::abs(options.omega_end - options.omega_start);
  // Scales: the static modal response |φᵀf| F / ω_ref² (rows and η), g_ref per unit η for gaps.
  const double w2 = balance.reference_omega() * balance.reference_omega();
  const double eta = std::abs(options.load_amplitude) *
                     std::max(model.load_modal.lpNorm<Eigen::Infinity>(), 1e-300) / w2;
  // Near resonance the response is the static one amplified by about 1/(2ζ) of the first elastic
  // mode: scale the state by that, so that the arclength is not dominated by it.
  const int elastic = model.rigid_modes;
  const double zeta = std::max(
      (model.rayleigh_mass + model.rayleigh_stiffness * model.omega2[elastic]) / (2.0 * std::sqrt(model.omega2[elastic])), 1e-4);
  c.state_scale = eta / (2.0 * zeta) * interface_detail::arclength_scale(balance);
  c.residual_scale = eta;

  std::optional<InterfaceFrfErrorEstimator> estimator;
  if (options.error_estimate) estimator.emplace(model, balance_options, options.load_amplitude, options.output);
  double error_seconds = 0.0;

  hb::InterfaceBalanceEvaluation last;
  Eigen::VectorXd last_x;
  double last_omega = std::numeric_limits<double>::quiet_NaN();
  const ResidualFunction residual = [&](const Eigen::VectorXd& x, double omega, bool jacobian) {
    last_x.resize(0);
    balance.evaluate(x, omega, 0.0, load, jacobian, last);
    last_x = x;
    last_omega = omega;
    Evaluation e;
    e.ok = last.ok;
    e.message = last.message;
    e.residual = last.residual;
    if (jacobian && matrix_free) {
      auto at = std::make_shared<const hb::InterfaceBalanceEvaluation>(last);
      e.d_parameter = last.d_omega;
      e.d_state_product = [&balance, at, omega](const Eigen::VectorXd& v) {
        return balance.apply_jacobian(*at, omega, 0.0, v);
      };
      if (options.mixed_precision)
        e.d_state_product_inner = [&balance, at, omega](const Eigen::VectorXd& v) {
          return balance.apply_jacobian(*at, omega, 0.0, v, true);
        };
      e.make_preconditioner = [&balance, at, omega, kind = options.preconditioner]() -> LinearOperator {
        return balance.preconditioner(*at, omega, 0.0, kind);
      };
    } else if (jacobian) {
      e.d_state = std::move(last.jacobian);
      e.d_parameter = last.d_omega;
    }
    return e;
  };
  const AcceptCallback accept = [&](const Point& p) {
    if (p.lambda != last_omega || p.x.size() != last_x.size() || p.x != last_x)
      balance.evaluate(p.x, p.lambda, 0.0, load, false, last);
    InterfaceFrfPoint f;
    f.omega = p.lambda;
    const Eigen::VectorXd u = balance.output_coefficients(options.output, p.x, p.lambda, 0.0, load, last.contact_force);
    const int a1 = balance.basis().cosine_index(1);
    f.amplitude_h1 = std::hypot(u[a1], u[a1 + 1]);
    f.amplitude_max = balance.basis().peak_magnitude(u);
    f.dissipation = last.dissipation;
    f.open_points = last.open_points;
    f.slipping_points = last.slipping_points;
    f.states = last.states;
    f.iterations = p.iterations;
    f.unknowns = p.x;
    if (estimator) {
      const auto estimate_start = support::Clock::now();
      f.error = estimator->estimate(balance, p.x, p.lambda, &last);  // `last` is at the point (above)
      error_seconds += support::seconds_since(estimate_start);
    }
    curve.points.push_back(f);
    return on_point ? on_point(f) : true;
  };
  const Result r = trace(residual, balance.linear_solution(options.omega_start, load), c, accept);
  curve.reason = r.reason;
  curve.message = r.message;
  curve.newton_iterations = r.corrector_iterations;
  curve.rejected_steps = r.rejected_steps;
  interface_detail::add_curve_timings(curve.timings, balance.timings(), r);
  curve.timings.total = support::seconds_since(start);
  curve.timings.error_estimate = error_seconds;
  return curve;
}

}  // namespace jointhb::continuation
