#pragma once
// Nonlinear frequency response of a discrete system: harmonic balance (hb/harmonic_balance.hpp)
// traced over the excitation frequency Ω by pseudo-arclength continuation
// (continuation/pseudo_arclength.hpp), one curve per excitation level.

#include <Eigen/Core>
#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/continuation/accuracy.hpp"
#include "jointhb/continuation/error_estimate.hpp"
#include "jointhb/continuation/pseudo_arclength.hpp"
#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/hb/harmonic_balance.hpp"
#include "jointhb/hb/hill_stability.hpp"
#include "jointhb/hb/orbit_monodromy.hpp"

namespace jointhb::continuation {

/// The largest turn of the scaled state between two points of an FRF (Options::max_state_turn,
/// set by the discrete and finite-element FRF drivers where their continuation options leave it 0): a resonance turns the phase
/// by π, and a step over a lightly damped peak lands beyond it on the flat branch (ζ = 1e-4: the
/// one-harmonic probe that sets the arclength scale found a peak of 1e-5 where the linear one is
/// 5e-3, and the curve then crawled at 1e-6 per point to max_points; docs/continuation.md).
inline constexpr double kMaxStateTurn = std::numbers::pi / 4.0;

using hb::DiscreteSystem;
using hb::Excitation;
using hb::HarmonicSelection;

/// Whether an FRF computes the stability of its points.
enum class Stability {
  automatic,  ///< when it is cheap: n ≤ kAutomaticStabilityDofs (monodromy), n(2H+1) ≤
              ///< kAutomaticStabilityUnknowns (Hill)
  always,
  never,
};

/// How the stability of a point is computed (docs/stability.md §1–2).
enum class StabilityMethod {
  /// The monodromy of the variational equation along the harmonic-balance orbit with the laws'
  /// increment derivatives (hb/orbit_monodromy.hpp): agrees with shooting; O(N_f n² (2n + n_c))
  monodromy,
  /// Hill's method on the harmonic-balance Jacobian (hb/hill_stability.hpp): exact at folds
  /// (ρ = +1), but the Jacobian freezes the contacts' memory, so the other multipliers of
  /// slipping contacts are wrong (docs/stability.md §2); O((2n(2H+1))³)
  hill,
};

/// "monodromy" or "hill": the value of the case key `stability_method`, as summary.json writes it.
[[nodiscard]] std::string to_string(StabilityMethod method);

/// The largest n for which Stability::automatic computes the monodromy (measured: 3.5 ms per
/// point at n = 1, 0.15 s at n = 30; docs/stability.md §6).
inline constexpr int kAutomaticStabilityDofs = 10;
/// The largest N = n(2H+1) for which Stability::automatic computes Hill's method: 2N = 300 (dgeev
/// with eigenvectors, O((2N)³): a 30-DOF chain at H = 3, 2N = 420, takes 0.12 s per point
/// against 2.4 ms for the harmonic balance itself, docs/stability.md §6; 2N = 300 scales that to
/// ~0.04 s).
inline constexpr int kAutomaticStabilityUnknowns = 150;

struct FrfOptions {
  double omega_start = 0.5;  ///< Ω at the first point [rad/s], > 0
  double omega_end = 2.0;    ///< Ω at the last point [rad/s], > 0, ≠ omega_start
  int harmonics = 7;         ///< H ≥ 1
  int time_samples = 128;    ///< N_t ≥ 2H + 2 (AFT samples per period)
  int output_dof = 0;        ///< DOF reported in the curve
  HarmonicSelection selection = HarmonicSelection::automatic;
  double periodic_tolerance = 1e-14;  ///< contact periodic-state tolerance (relative)
  bool check_jacobian = false;  ///< compare ∂R/∂X, ∂R/∂Ω with central differences at every point
  /// Floquet multipliers of every accepted point by Hill's method (hb/hill_stability.hpp): one
  /// dense eigenproblem of size 2N = 2n(2H+1) per point, O((2N)³) (its cost is
  /// FrfTimings::stability), or by the monodromy along the orbit (stability_method)
  Stability stability = Stability::automatic;
  StabilityMethod stability_method = StabilityMethod::monodromy;
  hb::HillOptions hill;               ///< Hill's method settings
  hb::OrbitMonodromyOptions monodromy;  ///< the monodromy's settings
  /// Folds and the resonance peak located between accepted points (docs/stability.md §3)
  bool refine_extrema = true;
  /// Error estimates of every accepted point (continuation/error_estimate.hpp, docs/theory.md
  /// §13): one Jacobian at H + 2, one at H and a residual at 2 N_t per point
  bool error_estimate = true;
  /// Accuracy on request (accuracy.amplitude; continuation/accuracy.hpp, docs/theory.md §13 T-44):
  /// H and N_t chosen per point from the estimates of amplitude_h1 and amplitude_max, starting from
  /// harmonics/time_samples; stability per point at its level, folds and the peak located within
  /// the stretches of one level.
  Accuracy accuracy;
  Options continuation;         ///< steps, tolerances (start/end/scales set by trace_frf)

  [[nodiscard]] std::string validate(int dofs) const;  ///< empty when valid
};

/// Whether trace_frf computes the stability of the points of a system with `dofs` DOFs.
[[nodiscard]] bool computes_stability(const FrfOptions& options, int dofs);

/// One accepted point of an FRF curve.
struct FrfPoint {
  double omega = 0.0;          ///< Ω [rad/s]
  double amplitude_h1 = 0.0;   ///< |fundamental| of the output DOF: √(a₁² + b₁²)
  double amplitude_max = 0.0;  ///< max_t |x_out(t)| over the period (FourierBasis::peak_magnitude)
  double dissipation = 0.0;    ///< Σ contact W_D over the period [J]
  int iterations = 0;          ///< corrector iterations
  double step = 0.0;           ///< arclength step
  bool fold = false;           ///< Ω turned between the previous point and this one
  /// With FrfOptions::stability: the Floquet multipliers by Hill's method
  bool stability_known = false;  ///< false: not computed (or Hill's method failed at the point)
  bool stable = true;            ///< every |ρ| ≤ 1 + tolerance
  double max_multiplier = 0.0;   ///< max |ρ|
  int unstable_multipliers = 0;  ///< count of |ρ| > 1 + tolerance
  /// What happened between the previous point and this one (fold from the turn of Ω, else from the
  /// multiplier that crossed the unit circle)
  hb::Bifurcation bifurcation = hb::Bifurcation::none;
  Eigen::VectorXcd multipliers;  ///< the 2n multipliers, |ρ| descending (empty when not known)
  FrfError error;  ///< estimated relative errors of amplitude_h1 and amplitude_max (error_estimate)
  Eigen::VectorXd coefficients;  ///< X: harmonic coefficients of all DOFs (hb/fourier.hpp order)
  int harmonics = 0, time_samples = 0;  ///< the level of the point (of `coefficients`)
};

/// An extremum located between accepted points (continuation/curve_refinement.hpp): a fold of
/// the curve (extremum of Ω) or its resonance peak (extremum of amplitude_h1).
struct FrfExtremum {
  double omega = 0.0;         ///< Ω at the extremum [rad/s]
  double amplitude_h1 = 0.0;  ///< |fundamental| of the output DOF there
  /// Bound on the error of the located value: of Ω for a fold, of amplitude_h1 for a peak
  double value_bound = 0.0;
  double omega_bracket = 0.0;  ///< width in Ω of the final bracket
  bool refined = false;        ///< false: the accepted point is reported (see message)
  std::string message;         ///< why it was not refined, or where refinement stopped early
  int points = 0;              ///< points corrected during refinement
  /// Stability change across a fold (from the accepted points on either side)
  hb::Bifurcation bifurcation = hb::Bifurcation::none;
  Eigen::VectorXd coefficients;  ///< X at the located point (of the accepted point when !refined)
};

struct FrfTimings {
  double aft = 0.0;           ///< contact forces and their sensitivities [s]
  double assembly = 0.0;      ///< linear part and Jacobian assembly [s]
  double linear_solve = 0.0;  ///< factorisations and solves [s]
  double stability = 0.0;     ///< Hill's method at the accepted points [s]
  double refinement = 0.0;    ///< location of folds and the peak [s]
  double error_estimate = 0.0;  ///< error estimates of the accepted points [s] (their AFT included)
  double total = 0.0;
};

struct FrfCurve {
  std::vector<FrfPoint> points;
  StopReason reason = StopReason::start_failed;
  std::string message;
  int newton_iterations = 0;
  int rejected_steps = 0;
  std::vector<int> kept_harmonics;  ///< the harmonic orders used (of the first level)
  /// With check_jacobian: the largest relative discrepancy between the analytic Jacobian and
  /// central differences over the points (hb/jacobian_check.hpp), and where it occurred.
  double jacobian_check_error = 0.0;
  double jacobian_check_omega = 0.0;
  std::vector<FrfExtremum> folds;  ///< one per turn of Ω, refined
  /// The resonance peak: the largest amplitude_h1, refined when it lies between two points (not
  /// at an end of the range)
  std::optional<FrfExtremum> peak;
  /// Why stability was not computed (Stability::automatic on a large problem), else empty
  std::string stability_note;
  FrfTimings timings;
  int level_changes = 0;      ///< restarts at another H or N_t (options.accuracy)
  int short_of_accuracy = 0;  ///< points kept above the request at the largest level allowed
  [[nodiscard]] bool completed() const { return reason == StopReason::reached_end; }
  /// {termination(reason), message} (pseudo_arclength.hpp).
  [[nodiscard]] Status status() const { return {termination(reason), message}; }
};

/// Traces one FRF curve for one excitation level; `on_point` sees each accepted point (for flushed
/// output and progress) and may return false to stop. Throws std::invalid_argument on invalid
/// options or system; numerical failures end the curve with a message, keeping accepted points.
FrfCurve trace_frf(const DiscreteSystem& system, const Excitation& excitation,
                   const FrfOptions& options,
                   const std::function<bool(const FrfPoint&)>& on_point = {});

}  // namespace jointhb::continuation
