#pragma once
// Crossing a resonance at fixed phase (internal to the continuation layer; docs/continuation.md,
// "Crossing a resonance at fixed phase"; docs/theory.md §8, T-45, T-46). Where a lightly damped or
// undamped system's response is bounded only by slip, the FRF branch turns by ~90° at the stuck
// resonance onto the "friction cap": |X₁| stays within πF/(4μF_N) of the slip amplitude while the
// phase of the response turns by π at nearly constant Ω (one-harmonic energy balance π F |X₁| sin θ
// = 4 μF_N (|X₁| − X_s), T-46). Neither an arclength hyperplane nor a fixed Ω cuts that cap
// robustly at its corners; a fixed phase θ of the fundamental of one DOF does. The bridge steps θ
// from the phase of the last point of a stopped run and solves, in (x, Ω),
//   R(x, Ω) = 0,   g(x; θ) = −sin θ a₁ + cos θ b₁ = 0          (T-45)
// (a₁, b₁: the fundamental of that DOF, so that x₁(t) = |X₁| cos(Ωt − θ)) by Newton's method with
// a backtracking line search, from the predictor that delays the previous point by Δθ/Ω (harmonic
// h turned by hΔθ). It ends where the branch is no longer phase-dominated (a step that moves Ω,
// scaled, more than the state) or where no point is found even at the smallest phase step.

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "jointhb/continuation/pseudo_arclength.hpp"

namespace jointhb::continuation::detail {

/// x delayed by a phase φ of the fundamental: harmonic h of every signal turned by hφ.
using PhaseRotation = std::function<Eigen::VectorXd(const Eigen::VectorXd& x, double phi)>;

struct PhaseBridgeOptions {
  Eigen::Index phase_cosine = 0;  ///< index of a₁ of the DOF that carries the phase (b₁ follows)
  int direction = 1;  ///< sign of the phase change (+1: lag grows, Ω rising through a resonance)
  double omega_low = 0.0;  ///< the bridge ends before leaving [omega_low, omega_high]
  double omega_high = 0.0;
  double residual_tolerance = 1e-10;  ///< ‖R‖_∞ / residual_scale at convergence (or 10³ times it
                                      ///< after a step below step_tolerance, as in trace())
  double step_tolerance = 1e-10;  ///< scaled by state_scale and parameter_scale
  double residual_scale = 1.0;
  double state_scale = 1.0;  ///< the arclength's scales (the exit test)
  double parameter_scale = 1.0;
  int max_points = 1000;                     ///< points of the bridge
  double initial_step = 0.0490873852123405;  ///< Δθ = π/64
  double min_step = 1.9174759848570515e-4;   ///< π/16384
  double max_step = 0.19634954084936207;     ///< π/16
  int max_iterations = 20;
};

struct PhaseBridgePoint {
  Eigen::VectorXd x;
  double omega = 0.0;
  double theta = 0.0;
  double step = 0.0;  ///< |Δθ| that led to it
  int iterations = 0;
  Eigen::VectorXd tangent;  ///< (dx, dΩ) along the bridge (unscaled, not normalised)
};

struct PhaseBridge {
  enum class End {
    no_point,         ///< not even the smallest phase step found a point
    omega_dominated,  ///< the last step moved Ω more than the state (scaled): arclength takes over
    range,            ///< the next point would leave [omega_low, omega_high]
    turned,           ///< the phase turned by π
    budget,           ///< max_points
    stopped,          ///< the callback returned false
  };
  std::vector<PhaseBridgePoint> points;
  End end = End::no_point;
  int iterations = 0;
  int rejected_steps = 0;
  std::string message;  ///< the last corrector failure (End::no_point)
};

/// The phase of the fundamental at a₁ (index `cosine`): atan2(b₁, a₁).
double fundamental_phase(const Eigen::VectorXd& x, Eigen::Index cosine);

/// Steps θ from the phase of (x0, Ω0) (a converged point, not repeated) in `direction`; each new
/// point goes to `on_point` (false: stop). The residual must give dense Jacobians (d_state).
PhaseBridge bridge_by_phase(const ResidualFunction& residual, const PhaseRotation& rotate,
                            const Eigen::VectorXd& x0, double omega0,
                            const PhaseBridgeOptions& options,
                            const std::function<bool(const PhaseBridgePoint&)>& on_point);

/// Newton's method at fixed Ω from x0 with a backtracking line search on ‖R‖_∞ (the restart after
/// a crossing), converged as the crossing's points are (the tolerances and scales of `options`).
struct FixedOmegaSolve {
  bool converged = false;
  Eigen::VectorXd x;
  int iterations = 0;
};
FixedOmegaSolve solve_at_omega(const ResidualFunction& residual, const Eigen::VectorXd& x0,
                               double omega, const PhaseBridgeOptions& options);

}  // namespace jointhb::continuation::detail
