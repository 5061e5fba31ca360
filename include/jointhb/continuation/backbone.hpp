#pragma once
// Damping curves: the nonlinear mode (EPMC, hb/nonlinear_mode.hpp) traced over λ = log10 q by
// pseudo-arclength continuation, from the linear limit through microslip to gross slip.

#include <functional>
#include <string>
#include <vector>

#include "jointhb/continuation/accuracy.hpp"
#include "jointhb/continuation/curve_turn.hpp"
#include "jointhb/continuation/error_estimate.hpp"
#include "jointhb/continuation/pseudo_arclength.hpp"
#include "jointhb/hb/nonlinear_mode.hpp"

namespace jointhb::continuation {

struct BackboneOptions {
  hb::NonlinearModeOptions mode;        ///< mode number, H, N_t
  double log10_amplitude_start = -7.0;  ///< λ of the first point (should be in the linear range)
  double log10_amplitude_end = -3.0;    ///< λ of the last point, ≠ start
  int output_dof = 0;  ///< DOF whose |fundamental| each point reports (BackbonePoint::output_amplitude)
  /// ≥ 0; 0 (default): none. The curve ends (reached_end, with a message saying so) at the first
  /// point whose damping ratio ζ reaches this; 1 ends it where the mode becomes overdamped, where
  /// it does not vibrate freely and a damping ratio of the extended periodic motion no longer
  /// describes a decay (docs/continuation.md, "Where a damping curve ends").
  double max_damping_ratio = 0.0;
  /// Steps and tolerances (range and scales are set by trace_backbone). The residual tolerance
  /// defaults to 1e-12 (not 1e-10): the energy balance injected = viscous + ΣW_D then holds to
  /// ~1e-10 at every point (at 1e-10 it drifts to ~2e-8; validation/hb/README_epmc_convergence.md).
  /// max_points bounds each run: the one from λ_start and, where it stops short, the one from
  /// λ_end that completes the curve (docs/continuation.md, "A curve traced from both ends"); 2000
  /// by default, as the run from λ_end through the 7:1 internal resonance of the 30-DOF chain of
  /// tests/unit/hb/test_nonlinear_mode.cpp takes 1162 points.
  Options continuation = [] {
    Options o;
    o.max_points = 2000;
    o.residual_tolerance = 1e-12;
    return o;
  }();
  /// Error estimates of every accepted point (continuation/error_estimate.hpp, docs/theory.md
  /// §13): one Jacobian at H + 2, one at H and a residual at 2 N_t per point
  bool error_estimate = true;
  /// Accuracy on request (continuation/accuracy.hpp, docs/theory.md §13 eq. T-44): when active, H
  /// and N_t are chosen per point from the point's estimates (computed whatever error_estimate
  /// says), starting from mode's, which must lie in the request's range.
  Accuracy accuracy;
  [[nodiscard]] std::string validate(int dofs) const;
};

/// One accepted point: hb::NonlinearModeState plus the continuation's record.
struct BackbonePoint {
  hb::NonlinearModeState state;
  double output_amplitude = 0.0;  ///< |fundamental| of options.output_dof: q √(â₁² + b̂₁²) [m]
  int iterations = 0;
  double step = 0.0;
  BackboneError error;       ///< estimated relative errors of Ω and ζ (with error_estimate)
  Eigen::VectorXd unknowns;  ///< (X̂, Ω, ξ) in the basis of (harmonics, time_samples)
  int harmonics = 0, time_samples = 0;  ///< the level the point was computed at
};

struct BackboneCurve {
  std::vector<BackbonePoint> points;
  std::vector<BackboneTurn> turns;  ///< every turn of λ along the kept runs, in order
  StopReason reason = StopReason::start_failed;
  std::string message;
  int newton_iterations = 0;
  int rejected_steps = 0;
  double linear_omega = 0.0;          ///< ω of the followed linear mode (contacts stuck)
  double linear_damping_ratio = 0.0;  ///< φᵀCφ / (2ω)
  double seconds = 0.0;
  double error_seconds = 0.0;  ///< of the error estimates (included in seconds)
  int level_changes = 0;       ///< restarts at another H or N_t (options.accuracy)
  int short_of_accuracy = 0;   ///< points kept above the request at the largest level allowed
  [[nodiscard]] bool completed() const { return reason == StopReason::reached_end; }
  /// {termination(reason), message} (pseudo_arclength.hpp).
  [[nodiscard]] Status status() const { return {termination(reason), message}; }
};

/// Throws std::invalid_argument on invalid options or system; numerical failures end the curve
/// with a message, keeping every accepted point.
BackboneCurve trace_backbone(const hb::DiscreteSystem& system, const BackboneOptions& options,
                             const std::function<bool(const BackbonePoint&)>& on_point = {});

}  // namespace jointhb::continuation
