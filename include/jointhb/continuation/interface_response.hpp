#pragma once
// Damping curves and frequency responses of a preloaded FE joint (hb/interface_mode.hpp,
// hb/interface_balance.hpp) by pseudo-arclength continuation (continuation/pseudo_arclength.hpp):
// the backbone over λ = log10 q, the FRF over Ω at a fixed load amplitude.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/continuation/accuracy.hpp"
#include "jointhb/continuation/curve_turn.hpp"
#include "jointhb/continuation/error_estimate.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/continuation/pseudo_arclength.hpp"
#include "jointhb/hb/interface_mode.hpp"
#include "jointhb/hb/interface_hill_stability.hpp"
#include "jointhb/hb/interface_orbit_monodromy.hpp"

namespace jointhb::continuation {

struct InterfaceTimings {
  double aft = 0.0;           ///< contact AFT and its Jacobian [s]
  double assembly = 0.0;      ///< residual and Jacobian assembly [s]
  double linear_solve = 0.0;  ///< LU factorisations, GMRES and solves [s]
  double total = 0.0;
  int evaluations = 0, jacobians = 0;
  int factorisations = 0;     ///< LU factorisations of bordered matrices
  int krylov_iterations = 0;  ///< GMRES iterations (LinearSolver::newton_krylov)
  double products = 0.0;        ///< matrix-free Jacobian-vector products [s]
  double preconditioner = 0.0;  ///< building preconditioners [s]
  double preconditioner_apply = 0.0;  ///< applying preconditioners (inside the linear solves) [s]
  int product_calls = 0, preconditioner_calls = 0;
  double error_estimate = 0.0;  ///< error estimates of the accepted points [s] (included in total)
  double stability = 0.0;       ///< Floquet multipliers of the accepted points [s] (included in total)
  double refinement = 0.0;      ///< FRF folds and peak located between points [s] (included in total)
  /// One line: where the time went (AFT; residual assembly; linear solves with their GMRES
  /// iterations and preconditioner builds and applications; Jacobian products, inside the
  /// solves and for the EPMC's ∂R/∂λ; other).
  [[nodiscard]] std::string breakdown() const;
};

struct InterfaceBackboneOptions {
  hb::InterfaceModeOptions mode;
  double log10_amplitude_start = -6.0;  ///< λ of the first point (linear range)
  double log10_amplitude_end = -3.0;    ///< ≠ start
  /// With continuation.linear_solver = newton_krylov: matrix-free Jacobian
  /// (InterfaceModeResidual::apply_jacobian from the point blocks) and the harmonic block-Jacobi
  /// preconditioner (eq. T-32c), no U × U matrix formed (docs/performance.md: 3–30× faster than
  /// the dense Jacobian on the lap, the same points to 1e-14); false: the dense Jacobian with the
  /// lagged LU. dense_lu always uses the dense Jacobian.
  bool matrix_free = true;
  /// The approximate inverse that preconditions GMRES (matrix-free only): the point-local J_loc
  /// (eq. T-34, O(P) to build and apply, rebuilt at every new Jacobian) or the harmonic
  /// block-Jacobi J̃ (T-32c, O(H P³) to build).
  hb::InterfacePreconditioner preconditioner = hb::InterfacePreconditioner::point_local;
  /// Matrix-free only: inside GMRES cycles, R0 and R1 applied in single precision (half the
  /// memory traffic); every cycle ends on the double-precision true residual, so the accepted
  /// Newton steps, hence the curve, are unchanged (mixed-precision iterative refinement).
  bool mixed_precision = true;
  /// Curves with at most this many unknowns ((n_s + 3P)(2H + 1) + 2) use the dense Jacobian and
  /// the dense LU whatever matrix_free and continuation.linear_solver say (0: never). The dense LU
  /// carries the orientation sign det [J; τᵀ] that takes the curve through folds at kinks
  /// (docs/continuation.md, "Crossing a corner"), which GMRES does not: a 2-DOF joint at a 3:1
  /// internal resonance (test InterfaceBackbone.TurnsAtAnInternalResonanceAreExtremaOfTheAmplitude)
  /// loops at such a fold at log10 q = −0.82 with GMRES and passes it with the dense LU. Cost,
  /// dense against matrix-free (one thread): 0.85–1.22× on synthetic joints of 68–786 unknowns,
  /// but 1.66× on case 08 (629 unknowns, 2.72 s against 1.64 s for the whole run): hence 300.
  /// Turns are refined only with a dense Jacobian (matrix-free: reported at the point after them).
  Eigen::Index dense_below = 300;
  Options continuation = [] {
    Options o;
    o.residual_tolerance = 1e-10;
    o.initial_step = 0.05;
    o.max_step = 0.3;
    // GMRES, matrix-free or with the lagged LU (docs/continuation.md §2): the same points as
    // dense_lu to the Newton tolerance, a fraction of the cost.
    o.linear_solver = LinearSolver::newton_krylov;
    o.krylov_max_iterations = 100;  // per GMRES cycle: the preconditioner is approximate
    // Newton steps to 1e-8 (relative residual of the linear solve) instead of 1e-11: the converged
    // points still pass residual_tolerance; on P400_H3 26 % fewer GMRES steps, the same iteration
    // counts, f and ζ within 2e-12 and 6e-11 of the 1e-11 curve (docs/performance.md).
    o.krylov_tolerance = 1e-8;
    return o;
  }();
  /// Error estimates of every accepted point (continuation/interface_error_estimate.hpp,
  /// docs/theory.md §13): per point Newton's method at H + 2 (1–3 Jacobian evaluations), a
  /// residual at 2 N_t and a linear solve at H. Off by default: on the default case (lap, H = 1)
  /// they cost 1.8× the curve itself (discrete curves, where one Newton step suffices: ~1×).
  bool error_estimate = false;
  /// Accuracy on request (continuation/accuracy.hpp, docs/theory.md §13 eq. T-44): when active, H
  /// and N_t are chosen per point from the point's estimates (computed whatever error_estimate
  /// says), starting from mode.balance's, which must lie in the request's range.
  Accuracy accuracy;
  [[nodiscard]] std::string validate(const hb::InterfaceModel& model) const;
};

struct InterfaceBackbonePoint {
  hb::InterfaceModeState state;
  int iterations = 0;
  double step = 0.0;  ///< arclength step that reached the point
  BackboneError error;  ///< estimated relative errors of Ω and ζ (with error_estimate)
  Eigen::VectorXd unknowns;  ///< Ŷ = (ŷ, Ω, ξ) in the basis of (harmonics, time_samples)
  int harmonics = 0, time_samples = 0;  ///< the level the point was computed at
};

struct InterfaceBackbone {
  std::vector<InterfaceBackbonePoint> points;
  /// Every turn of λ along the kept runs, in order (docs/stability.md §7): refined where the
  /// Jacobian is dense (InterfaceBackboneOptions::dense_below), matrix-free reported at the
  /// accepted point after the turn, bounded by |Δλ|.
  std::vector<BackboneTurn> turns;
  StopReason reason = StopReason::start_failed;
  std::string message;
  int newton_iterations = 0, rejected_steps = 0;
  double linear_omega = 0.0, linear_damping_ratio = 0.0;
  Eigen::Index unknowns = 0;  ///< of the first point's level
  InterfaceTimings timings;
  int level_changes = 0;      ///< restarts at another H or N_t (options.accuracy)
  int short_of_accuracy = 0;  ///< points kept above the request at the largest level allowed
  [[nodiscard]] bool completed() const { return reason == StopReason::reached_end; }
  /// {termination(reason), message} (pseudo_arclength.hpp).
  [[nodiscard]] Status status() const { return {termination(reason), message}; }
};

/// Throws std::invalid_argument on invalid options or model; numerical failures end the curve
/// with a message, keeping every accepted point.
InterfaceBackbone trace_interface_backbone(
    const hb::InterfaceModel& model, const InterfaceBackboneOptions& options,
    const std::function<bool(const InterfaceBackbonePoint&)>& on_point = {});

/// The largest number of contact points for which Stability::automatic computes the Floquet
/// multipliers of an FE FRF (measured: 0.03 s per point at 10 points with N_f = 1024, H = 3;
/// docs/stability.md §7).
inline constexpr int kAutomaticInterfaceStabilityPoints = 10;
/// The largest 3P(2H + 1) for which Stability::automatic computes Hill's method for an FE FRF
/// (its LU of J_gg is O((3P(2H+1))³): 0.26 s per point at P = 96, H = 3, i.e. 2016;
/// validation/fe/README_interface_stability.md).
inline constexpr int kAutomaticInterfaceHillGapUnknowns = 2100;

struct InterfaceFrfOptions {
  double omega_start = 0.0, omega_end = 0.0;  ///< [rad/s], > 0, different
  double load_amplitude = 1.0;                 ///< F(t) = amplitude · cos Ωt times the load shape
  int output = 0;                              ///< index into model.outputs
  /// As InterfaceBackboneOptions::matrix_free (InterfaceBalance::apply_jacobian and
  /// harmonic_preconditioner).
  bool matrix_free = true;
  /// As InterfaceBackboneOptions::preconditioner.
  hb::InterfacePreconditioner preconditioner = hb::InterfacePreconditioner::point_local;
  bool mixed_precision = true;  ///< as InterfaceBackboneOptions::mixed_precision
  hb::InterfaceBalanceOptions balance;
  Options continuation = [] {
    Options o;
    o.residual_tolerance = 1e-10;
    o.linear_solver = LinearSolver::newton_krylov;
    o.krylov_max_iterations = 100;  // per GMRES cycle: the preconditioner is approximate
    o.krylov_tolerance = 1e-8;      // as InterfaceBackboneOptions
    return o;
  }();
  /// As InterfaceBackboneOptions::error_estimate (one or two more evaluations per point for the
  /// outputs); off by default.
  bool error_estimate = false;
  /// Accuracy on request (accuracy.amplitude: amplitude_h1 and amplitude_max): H and N_t chosen per
  /// point, as InterfaceBackboneOptions::accuracy.
  Accuracy accuracy;
  /// Floquet multipliers of every accepted point, by the monodromy of the reduced model along
  /// the orbit (hb/interface_orbit_monodromy.hpp: kept modes exactly, residual modes
  /// quasi-statically; O(N_f (3P)³) per point) or by Hill's method (stability_method; O((3Pm)³)):
  /// automatic as computes_interface_stability says.
  Stability stability = Stability::automatic;
  /// monodromy (default; right for slipping contacts) or Hill's method on the balance's Jacobian
  /// (hb/interface_hill_stability.hpp, eq. T-36a: exact at folds, the memory of slipping
  /// contacts frozen; docs/stability.md §2 and §7)
  StabilityMethod stability_method = StabilityMethod::monodromy;
  hb::OrbitMonodromyOptions monodromy;  ///< the monodromy's settings
  hb::HillOptions hill;                 ///< Hill's method settings
  /// Locate the folds and the resonance peak between accepted points (as FrfOptions::
  /// refine_extrema), by bordered Newton on the run's Jacobian: dense, or matrix-free with GMRES
  /// and the run's preconditioner (continuation/curve_refinement.hpp).
  bool refine_extrema = true;
  [[nodiscard]] std::string validate(const hb::InterfaceModel& model) const;
};

struct InterfaceFrfPoint {
  double omega = 0.0;
  double amplitude_h1 = 0.0;   ///< |fundamental| of the output
  double amplitude_max = 0.0;  ///< max_t |u_o(t)|
  double dissipation = 0.0;    ///< Σ A_p W_D [J]
  int open_points = 0, slipping_points = 0, iterations = 0;
  hb::ContactStateCounts states;  ///< points per contact state (hb/contact_state.hpp)
  FrfError error;  ///< estimated relative errors of amplitude_h1 and amplitude_max (error_estimate)
  Eigen::VectorXd unknowns;  ///< in the basis of (harmonics, time_samples)
  int harmonics = 0, time_samples = 0;  ///< the level the point was computed at
  bool fold = false;           ///< Ω turned between the previous point of its run and this one
  // Stability (options.stability): as FrfPoint's.
  bool stability_known = false;  ///< the multipliers were computed
  bool stable = true;
  double max_multiplier = 0.0;   ///< max |ρ|
  int unstable_multipliers = 0;  ///< |ρ| > 1 + tolerance
  Eigen::VectorXcd multipliers;  ///< by |ρ| descending
  /// Against the previous point: fold where Ω turned, else from the change of the multipliers
  /// (hb::classify_bifurcation); none at the first point of a run.
  hb::Bifurcation bifurcation = hb::Bifurcation::none;
};

/// Whether trace_interface_frf with InterfaceFrfOptions::stability = `stability` computes the
/// stability of the points of a joint of `points` contact points by `method` at H = `harmonics`:
/// automatic — the monodromy up to kAutomaticInterfaceStabilityPoints points, Hill's method up to
/// kAutomaticInterfaceHillGapUnknowns gap unknowns 3P(2H + 1).
[[nodiscard]] bool computes_interface_stability(Stability stability, int points,
                                                StabilityMethod method = StabilityMethod::monodromy,
                                                int harmonics = 1);

struct InterfaceFrf {
  std::vector<InterfaceFrfPoint> points;
  StopReason reason = StopReason::start_failed;
  std::string message;
  int newton_iterations = 0, rejected_steps = 0;
  Eigen::Index unknowns = 0;  ///< of the first point's level
  InterfaceTimings timings;
  int level_changes = 0;      ///< restarts at another H or N_t (options.accuracy)
  int short_of_accuracy = 0;  ///< points kept above the request at the largest level allowed
  std::vector<FrfExtremum> folds;   ///< one per turn of Ω (not a reversal), as FrfCurve's
  std::optional<FrfExtremum> peak;  ///< the largest amplitude_h1, as FrfCurve's (coefficients: ŷ)
  [[nodiscard]] bool completed() const { return reason == StopReason::reached_end; }
  /// {termination(reason), message} (pseudo_arclength.hpp).
  [[nodiscard]] Status status() const { return {termination(reason), message}; }
};

InterfaceFrf trace_interface_frf(const hb::InterfaceModel& model, const InterfaceFrfOptions& options,
                                 const std::function<bool(const InterfaceFrfPoint&)>& on_point = {});

}  // namespace jointhb::continuation
