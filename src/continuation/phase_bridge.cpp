// Crossing a resonance at fixed phase (phase_bridge.hpp).
#include "phase_bridge.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>

namespace jointhb::continuation::detail {
namespace {

using Eigen::Index;
using Eigen::VectorXd;

constexpr double kPi = std::numbers::pi;
// |g| / |X₁| at convergence: the phase condition to round-off of the fundamental's angle.
constexpr double kPhaseTolerance = 1e-12;
// Steps that converge in at most this many iterations double Δθ; more than kSlowIterations halve
// it.
constexpr int kQuickIterations = 3;
constexpr int kSlowIterations = 8;
// Relative amplitude changes of the predictor tried in turn (phase_bridge.hpp: the first is the
// turned point itself).
constexpr double kAmplitudePushes[] = {0.0, 1e-8, -1e-8, 1e-6, -1e-6, 1e-4, -1e-4, 1e-2, -1e-2};

// R at (x, Ω) with the Jacobian or not; nullopt when the evaluation fails or is not finite.
std::optional<Evaluation> evaluate(const ResidualFunction& residual, const VectorXd& x,
                                   double omega, bool jacobian) {
  if (!x.allFinite() || !std::isfinite(omega)) return std::nullopt;
  try {
    Evaluation e = residual(x, omega, jacobian);
    if (!e.ok || !e.residual.allFinite()) return std::nullopt;
    if (jacobian &&
        (e.d_state.rows() != x.size() || !e.d_state.allFinite() || !e.d_parameter.allFinite()))
      return std::nullopt;
    return e;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// g(x; θ) = −sin θ a₁ + cos θ b₁ (T-45).
double phase_condition(const VectorXd& x, Index cosine, double theta) {
  return -std::sin(theta) * x[cosine] + std::cos(theta) * x[cosine + 1];
}

// Converged as trace() converges (pseudo_arclength.cpp): ‖R‖_∞ ≤ tol r_s, or within kFloorFactor of
// it after a last step below step_tolerance (scaled unknowns): the round-off floor of R, e.g. a
// force scale of 10⁻⁶ against stiffness terms of order 1.
constexpr double kFloorFactor = 1e3;
bool converged(const PhaseBridgeOptions& o, double residual, double last_step) {
  const double tolerance = o.residual_tolerance * o.residual_scale;
  return residual <= tolerance ||
         (residual <= kFloorFactor * tolerance && last_step <= o.step_tolerance);
}

struct Corrected {
  bool converged = false;
  int iterations = 0;
  VectorXd tangent;  ///< (dx/dθ, dΩ/dθ) at the converged point, unscaled
};

// Newton on [R(x, Ω); g(x; θ)] in (x, Ω) with a backtracking line search on the merit
// max(‖R‖_∞ / residual_scale, |g| / amplitude).
Corrected correct_at_phase(const ResidualFunction& residual, double theta, double amplitude,
                           const PhaseBridgeOptions& o, VectorXd& x, double& omega) {
  const Index n = x.size();
  const Index a1 = o.phase_cosine;
  Corrected out;
  // [R_x R_Ω; g_x 0] at the evaluation e.
  const auto bordered = [&](const Evaluation& e) {
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n + 1, n + 1);
    j.topLeftCorner(n, n) = e.d_state;
    j.topRightCorner(n, 1) = e.d_parameter;
    j(n, a1) = -std::sin(theta);
    j(n, a1 + 1) = std::cos(theta);
    return j;
  };
  const auto merit = [&](const Evaluation& e, const VectorXd& xt) {
    return std::max(e.residual.lpNorm<Eigen::Infinity>() / o.residual_scale,
                    std::abs(phase_condition(xt, a1, theta)) / amplitude);
  };
  double last_step = std::numeric_limits<double>::infinity();
  for (int it = 0; it < o.max_iterations; ++it) {
    const std::optional<Evaluation> e = evaluate(residual, x, omega, true);
    if (!e) return out;
    const double r = merit(*e, x);
    if (converged(o, e->residual.lpNorm<Eigen::Infinity>(), last_step) &&
        std::abs(phase_condition(x, a1, theta)) <= kPhaseTolerance * amplitude) {
      // The branch's tangent: d/dθ of [R; g] = 0, [R_x R_Ω; g_x 0] (dx, dΩ) = (0, −∂g/∂θ).
      VectorXd dg = VectorXd::Zero(n + 1);
      dg[n] = std::cos(theta) * x[a1] + std::sin(theta) * x[a1 + 1];
      out.tangent = bordered(*e).partialPivLu().solve(dg);
      out.converged = out.tangent.allFinite();
      return out;
    }
    const Eigen::MatrixXd j = bordered(*e);
    VectorXd rhs(n + 1);
    rhs.head(n) = e->residual;
    rhs[n] = phase_condition(x, a1, theta);
    const VectorXd d = j.partialPivLu().solve(rhs);
    ++out.iterations;
    if (!d.allFinite()) return out;
    bool moved = false;
    for (double alpha = 1.0; alpha > 1e-6 && !moved; alpha *= 0.5) {
      const VectorXd xt = x - alpha * d.head(n);
      const double wt = omega - alpha * d[n];
      const std::optional<Evaluation> et = evaluate(residual, xt, wt, false);
      if (et && merit(*et, xt) < (1.0 - 1e-4 * alpha) * r) {
        x = xt;
        omega = wt;
        moved = true;
        last_step = alpha * std::max(d.head(n).lpNorm<Eigen::Infinity>() / o.state_scale,
                                     std::abs(d[n]) / o.parameter_scale);
      }
    }
    if (!moved) return out;
  }
  return out;
}

}  // namespace

double fundamental_phase(const VectorXd& x, Index cosine) {
  return std::atan2(x[cosine + 1], x[cosine]);
}

PhaseBridge bridge_by_phase(const ResidualFunction& residual, const PhaseRotation& rotate,
                            const VectorXd& x0, double omega0, const PhaseBridgeOptions& o,
                            const std::function<bool(const PhaseBridgePoint&)>& on_point) {
  PhaseBridge out;
  const double amplitude = std::hypot(x0[o.phase_cosine], x0[o.phase_cosine + 1]);
  if (!(amplitude > 0.0) || !std::isfinite(amplitude)) {
    out.message = "the fundamental that would carry the phase is zero";
    return out;
  }
  VectorXd x = x0;
  double omega = omega0;
  double theta = fundamental_phase(x0, o.phase_cosine);
  double turned = 0.0;
  double step = o.initial_step;
  while (static_cast<int>(out.points.size()) < o.max_points) {
    step = std::min(step, kPi - turned);
    if (step < o.min_step) {
      out.end = PhaseBridge::End::turned;
      return out;
    }
    const double next_theta = theta + o.direction * step;
    // The predictor: the last point turned by Δθ, then, where Newton fails from it (the first step
    // off a stuck leg: the stuck Jacobian has no solution at a phase other than 0 or π, and the
    // Newton step overshoots the kink at slip onset), turned and scaled by 1 ± ε
    // (kAmplitudePushes).
    const VectorXd turned_x = rotate(x, o.direction * step);
    VectorXd xt;
    double wt = omega;
    Corrected c;
    for (const double push : kAmplitudePushes) {
      xt = (1.0 + push) * turned_x;
      wt = omega;
      c = correct_at_phase(residual, next_theta, amplitude, o, xt, wt);
      out.iterations += c.iterations;
      if (c.converged) break;
    }
    if (!c.converged) {
      ++out.rejected_steps;
      step *= 0.5;
      if (step < o.min_step) {
        out.end = PhaseBridge::End::no_point;
        out.message = "no point at fixed phase even with Δθ below " + std::to_string(o.min_step);
        return out;
      }
      continue;
    }
    if (wt < o.omega_low || wt > o.omega_high) {
      out.end = PhaseBridge::End::range;
      return out;
    }
    // The exit test: a step that moves Ω (scaled) more than the state has left the phase-dominated
    // part of the branch.
    const bool omega_dominated = std::abs(wt - omega) / o.parameter_scale >
                                 (xt - x).lpNorm<Eigen::Infinity>() / o.state_scale;
    PhaseBridgePoint p{xt, wt, next_theta, step, c.iterations, o.direction * c.tangent};
    out.points.push_back(p);
    x = std::move(xt);
    omega = wt;
    theta = next_theta;
    turned += step;
    if (on_point && !on_point(out.points.back())) {
      out.end = PhaseBridge::End::stopped;
      return out;
    }
    if (omega_dominated) {
      out.end = PhaseBridge::End::omega_dominated;
      return out;
    }
    if (c.iterations <= kQuickIterations)
      step = std::min(2.0 * step, o.max_step);
    else if (c.iterations > kSlowIterations)
      step *= 0.5;
  }
  out.end = PhaseBridge::End::budget;
  return out;
}

FixedOmegaSolve solve_at_omega(const ResidualFunction& residual, const VectorXd& x0, double omega,
                               const PhaseBridgeOptions& o) {
  FixedOmegaSolve out;
  out.x = x0;
  double last_step = std::numeric_limits<double>::infinity();
  for (int it = 0; it < o.max_iterations; ++it) {
    const std::optional<Evaluation> e = evaluate(residual, out.x, omega, true);
    if (!e) return out;
    const double r = e->residual.lpNorm<Eigen::Infinity>();
    if (converged(o, r, last_step)) {
      out.converged = true;
      return out;
    }
    const VectorXd d = e->d_state.partialPivLu().solve(e->residual);
    ++out.iterations;
    if (!d.allFinite()) return out;
    bool moved = false;
    for (double alpha = 1.0; alpha > 1e-6 && !moved; alpha *= 0.5) {
      const VectorXd xt = out.x - alpha * d;
      const std::optional<Evaluation> et = evaluate(residual, xt, omega, false);
      if (et && et->residual.lpNorm<Eigen::Infinity>() < (1.0 - 1e-4 * alpha) * r) {
        out.x = xt;
        moved = true;
        last_step = alpha * d.lpNorm<Eigen::Infinity>() / o.state_scale;
      }
    }
    if (!moved) return out;
  }
  return out;
}

}  // namespace jointhb::continuation::detail
