// Damping curves and FRFs of a preloaded FE joint (interface_response.hpp).
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
#include "mode_outputs.hpp"

namespace jointhb::continuation {
namespace {

// The arclength counts the interface gaps as if there were at most this many contact points:
// their share of ‖Δy‖ grows like √P (every point's gaps change with the amplitude), so without
// this a fine interface would take steps √(P / 100) times shorter in amplitude or frequency for
// the same accuracy of the predictor (1600 points: 43 instead of ~15 points per damping curve).
// Curves of up to 100 points are unchanged.
constexpr double kArclengthPoints = 100.0;

// unknown_scale() with the gap unknowns weighted for kArclengthPoints (above).
Eigen::VectorXd arclength_scale(const hb::InterfaceBalance& balance) {
  Eigen::VectorXd s = balance.unknown_scale();
  const double factor = std::sqrt(std::max(1.0, balance.points() / kArclengthPoints));
  const Eigen::Index gaps = static_cast<Eigen::Index>(3) * balance.points() * balance.basis().size();
  s.tail(gaps) *= factor;
  return s;
}

InterfaceTimings curve_timings(const hb::InterfaceBalanceTimings& t, const Result& r, double total) {
  InterfaceTimings c;
  c.aft = t.aft;
  c.assembly = t.assembly;
  c.linear_solve = r.linear_solve_seconds;
  c.total = total;
  c.evaluations = t.evaluations;
  c.jacobians = t.jacobians;
  c.factorisations = r.factorisations;
  c.krylov_iterations = r.krylov_iterations;
  c.products = t.products;
  c.preconditioner = t.preconditioner;
  c.preconditioner_apply = t.preconditioner_apply;
  c.product_calls = t.product_calls;
  c.preconditioner_calls = t.preconditioner_calls;
  return c;
}

}  // namespace

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

std::string InterfaceBackboneOptions::validate(const hb::InterfaceModel& model) const {
  if (std::string msg = mode.validate(model); !msg.empty()) return msg;
  if (!std::isfinite(log10_amplitude_start) || !std::isfinite(log10_amplitude_end))
    return "log10_amplitude: must be finite";
  if (log10_amplitude_start == log10_amplitude_end) return "log10_amplitude: end must differ from start";
  return {};
}

InterfaceBackbone trace_interface_backbone(
    const hb::InterfaceModel& model, const InterfaceBackboneOptions& options,
    const std::function<bool(const InterfaceBackbonePoint&)>& on_point) {
  const auto start = support::Clock::now();
  if (std::string msg = options.validate(model); !msg.empty()) throw std::invalid_argument(msg);
  const bool matrix_free =
      options.matrix_free && options.continuation.linear_solver == LinearSolver::newton_krylov;
  hb::InterfaceModeOptions mode = options.mode;
  if (matrix_free) mode.balance.dense_jacobian = false;
  const hb::InterfaceModeResidual epmc(model, mode);
  InterfaceBackbone curve;
  curve.linear_omega = epmc.linear_omega();
  curve.linear_damping_ratio = epmc.linear_damping_ratio();
  curve.unknowns = epmc.unknowns();

  Options c = options.continuation;
  c.parameter_start = options.log10_amplitude_start;
  c.parameter_end = options.log10_amplitude_end;
  c.direction = c.parameter_end > c.parameter_start ? 1 : -1;
  c.parameter_scale = std::abs(c.parameter_end - c.parameter_start);
  const Eigen::Index U = epmc.balance().unknowns();
  c.state_scale.resize(U + 2);
  c.state_scale.head(U) = arclength_scale(epmc.balance());
  c.state_scale[U] = epmc.linear_omega();
  c.state_scale[U + 1] = 0.1 * epmc.linear_omega();
  c.residual_scale = 1.0;  // rows are in units of the (unit) modal amplitude
  c.outputs = mode_outputs;  // Ω and ζ, for max_output_change

  std::optional<InterfaceBackboneErrorEstimator> estimator;
  if (options.error_estimate) estimator.emplace(model, mode);
  double error_seconds = 0.0;

  hb::InterfaceModeResidual::Evaluation last;
  Eigen::VectorXd last_y;
  double last_lambda = std::numeric_limits<double>::quiet_NaN();
  const ResidualFunction residual = [&](const Eigen::VectorXd& y, double lambda, bool jacobian) {
    last_y.resize(0);
    epmc.evaluate(y, lambda, jacobian, last);
    last_y = y;
    last_lambda = lambda;
    Evaluation out;
    out.ok = last.ok;
    out.message = last.message;
    out.residual = last.residual;
    if (jacobian && matrix_free) {
      // The operator keeps its own copy of the point blocks: `last` is overwritten by the next call.
      auto at = std::make_shared<const hb::InterfaceModeResidual::Evaluation>(last);
      out.d_parameter = last.d_parameter;
      out.d_state_product = [&epmc, at, y, lambda](const Eigen::VectorXd& v) {
        return epmc.apply_jacobian(*at, y, lambda, v);
      };
      if (options.mixed_precision)
        out.d_state_product_inner = [&epmc, at, y, lambda](const Eigen::VectorXd& v) {
          return epmc.apply_jacobian(*at, y, lambda, v, true);
        };
      out.make_preconditioner = [&epmc, at, y, lambda, kind = options.preconditioner]() -> LinearOperator {
        return epmc.preconditioner(*at, y, lambda, kind);
      };
    } else if (jacobian) {
      out.d_state = std::move(last.d_state);
      out.d_parameter = std::move(last.d_parameter);
    }
    return out;
  };
  const AcceptCallback accept = [&](const Point& p) {
    InterfaceBackbonePoint b;
    const bool cached = p.lambda == last_lambda && p.x.size() == last_y.size() && p.x == last_y;
    b.state = epmc.state(p.x, p.lambda, cached ? &last : nullptr);
    b.iterations = p.iterations;
    b.step = p.step;
    b.unknowns = p.x;
    if (estimator) {
      const auto estimate_start = support::Clock::now();
      // The corrector's last evaluation is at the point and, matrix-free, keeps its point blocks.
      b.error = estimator->estimate(epmc, p.x, p.lambda, cached ? &last : nullptr);
      error_seconds += support::seconds_since(estimate_start);
    }
    curve.points.push_back(b);
    return on_point ? on_point(b) : true;
  };
  const Result r = trace(residual, epmc.linear_start(), c, accept);
  curve.reason = r.reason;
  curve.message = r.message;
  curve.newton_iterations = r.corrector_iterations;
  curve.rejected_steps = r.rejected_steps;
  const hb::InterfaceBalanceTimings t = epmc.balance().timings();
  curve.timings = curve_timings(t, r, support::seconds_since(start));
  curve.timings.error_estimate = error_seconds;
  return curve;
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
  c.state_scale = eta / (2.0 * zeta) * arclength_scale(balance);
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
  const hb::InterfaceBalanceTimings t = balance.timings();
  curve.timings = curve_timings(t, r, support::seconds_since(start));
  curve.timings.error_estimate = error_seconds;
  return curve;
}

}  // namespace jointhb::continuation
