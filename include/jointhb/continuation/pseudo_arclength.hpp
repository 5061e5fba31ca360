#pragma once
// Pseudo-arclength continuation of the solution branch of R(x, λ) = 0, x ∈ ℝⁿ, λ ∈ ℝ, for any
// residual that comes with its Jacobian (harmonic balance over Ω, EPMC over log-amplitude, ...).
//
// Unknowns are scaled, y = (x ./ x_scale, λ / λ_scale), so that the arclength weighs the state
// against the parameter. From an accepted point y_k with unit tangent τ_k (null vector of
// [R_x D_x, R_λ λ_scale], oriented continuously), the predictor is y_k + s τ_k; the corrector
// solves the bordered system
//   [ R_x D_x      R_λ λ_scale ] Δy = - [ R                        ]
//   [ τ_kᵀ (x part) τ_k (λ)     ]       [ τ_kᵀ (y - y_k) - s        ]
// by Newton's method. The step s adapts to the corrector's iteration count (grows when below the
// target, shrinks when above); a failed corrector halves s; below min_step the run stops with a
// message and keeps every accepted point. Folds (turning points in λ) are passed: nothing in the
// scheme divides by dλ/ds. See docs/theory.md, "Continuation", and docs/continuation.md (the
// method in full: convergence test, step rule, the final point on λ_end, stop reasons).

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "jointhb/contact/termination.hpp"

namespace jointhb::continuation {

/// A linear map v ↦ A v (size n → n): matrix-free Jacobians and preconditioners.
using LinearOperator = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

/// What the residual function returns at (x, λ).
struct Evaluation {
  Eigen::VectorXd residual;     ///< R (size n)
  Eigen::MatrixXd d_state;      ///< ∂R/∂x (n × n), filled when the Jacobian was requested
                                ///< (unless d_state_product is given)
  Eigen::VectorXd d_parameter;  ///< ∂R/∂λ (size n), filled when the Jacobian was requested
  /// Matrix-free alternative to d_state (LinearSolver::newton_krylov only): v ↦ ∂R/∂x v. With it,
  /// d_state stays empty, and the bordered systems are solved by GMRES preconditioned with
  /// make_preconditioner's approximate inverse of ∂R/∂x (docs/continuation.md §2).
  LinearOperator d_state_product;
  /// With d_state_product: builds an approximate inverse v ↦ M⁻¹ v of ∂R/∂x at this point (kept
  /// for later solves as Options::preconditioner_refresh says); empty: no preconditioner.
  std::function<LinearOperator()> make_preconditioner;
  /// Optional, with d_state_product: a cheaper approximation of it (e.g. in single precision),
  /// accurate to inner_product_accuracy relative, used inside GMRES cycles; each cycle's solution
  /// is checked on the true residual with d_state_product, so the accepted solution is the same
  /// (mixed-precision iterative refinement: docs/continuation.md §2).
  LinearOperator d_state_product_inner;
  double inner_product_accuracy = 1e-6;  ///< relative accuracy of d_state_product_inner
  bool ok = true;               ///< false: the point cannot be evaluated (the step is rejected)
  std::string message;          ///< why not, when !ok
};

/// R(x, λ), with the Jacobian when `jacobian` is true.
using ResidualFunction =
    std::function<Evaluation(const Eigen::VectorXd& x, double lambda, bool jacobian)>;

/// How the bordered Newton systems are solved (docs/continuation.md §2).
enum class LinearSolver {
  dense_lu,       ///< one LU (LAPACK dgetrf) per system: the reference
  newton_krylov,  ///< GMRES preconditioned by the LU of an earlier bordered matrix, refactored
                  ///< only when GMRES does not converge in krylov_max_iterations
};

/// When a matrix-free solve rebuilds its preconditioner (Evaluation::make_preconditioner).
enum class PreconditionerRefresh {
  on_failure,      ///< only when GMRES fails with the lagged one (for an expensive preconditioner)
  every_jacobian,  ///< at the first solve with each new Jacobian, so that it follows the state
                   ///< (for a cheap one: the FE drivers' point-local T-34); the tangent at a
                   ///< converged point reuses the last corrector's
};

struct Options {
  double initial_step = 1e-2;    ///< s₀ > 0, in scaled arclength
  double min_step = 1e-8;        ///< (0, initial_step]: stop when a halved step falls below it
  double max_step = 1e-1;        ///< ≥ initial_step
  /// ≥ 0, in units of λ; 0: none. Caps the step so that the predictor advances λ by at most this
  /// (s |τ_λ| λ_scale ≤ max_parameter_step): a lower bound on the points per unit of λ where the
  /// branch advances in λ (`points_per_decade` of a damping curve, λ = log10 q). The corrector may
  /// move λ a little beyond the predictor's; folds, where τ_λ → 0, are not constrained.
  double max_parameter_step = 0.0;
  /// ≥ 0; 0: none. Largest relative change |o_i − o_i,prev| / |o_i,prev| of any output of
  /// `outputs` between two accepted points: a converged step that changes an output by more is
  /// rejected and halved, and the next step is sized from the change observed, so that a curve
  /// resolves where its outputs change fast (ζ at the onset of slip) and not only where it bends
  /// in the scaled unknowns. Never a reason to stop: steps below 10⁻³ max_step are accepted
  /// whatever they change (a jump of an output is then resolved to that step).
  double max_output_change = 0.0;
  /// The outputs of a converged point (x, λ) that max_output_change limits (e.g. Ω and ζ of a
  /// damping curve); empty: none.
  std::function<Eigen::VectorXd(const Eigen::VectorXd&, double)> outputs;
  /// [0, π], radians; 0: none. Largest angle between the scaled states x_k ./ x_scale and
  /// x_{k+1} ./ x_scale of two accepted points (as vectors): a converged step that turns the state
  /// by more is rejected and halved, as for max_output_change, down to 10⁻³ max_step (then
  /// accepted). A forced response turns its phase by π through each resonance; a step that jumps
  /// over a peak narrower than the step (ζ = 1e-4: 2·10⁻⁴ ω wide) lands on the flat branch beyond
  /// it with the phase turned by about π and a tangent that hardly changed, so that nothing else
  /// notices (docs/continuation.md §5, rule 8; the FRF drivers set kMaxStateTurn, frf.hpp).
  double max_state_turn = 0.0;
  int max_points = 1000;         ///< ≥ 1: accepted points (including the start) before stopping
  double parameter_start = 0.0;  ///< λ of the first point
  double parameter_end = 1.0;    ///< the run stops at the first accepted point beyond it
  ///< (the last point is placed on λ = parameter_end exactly by a final corrector at fixed λ)
  int direction = +1;  ///< initial sign of dλ/ds (±1); ≠ sign(end - start) is an error
  int max_corrector_iterations = 12;  ///< ≥ 1
  int max_start_iterations = 50;  ///< ≥ 1: Newton iterations of the first point (fixed λ, from x0)
  int target_corrector_iterations =
      4;                              ///< [1, max_corrector_iterations]: count keeping s unchanged
  double step_growth = 2.0;           ///< > 1: largest factor by which s grows after a step
  double residual_tolerance = 1e-10;  ///< > 0: ‖R‖_∞ / residual_scale at convergence
  double residual_scale = 1.0;        ///< > 0: force scale of R (e.g. ‖f_ex‖)
  double step_tolerance = 1e-10;      ///< > 0: ‖Δy‖_∞ at convergence (scaled unknowns)
  Eigen::VectorXd state_scale;        ///< x_scale (size n, > 0) or empty: all ones
  double parameter_scale = 1.0;       ///< λ_scale > 0
  LinearSolver linear_solver = LinearSolver::dense_lu;
  /// newton_krylov: [1, 1000] GMRES iterations with one preconditioner before it is refactored
  /// from the current matrix (the system is then solved by that LU, as dense_lu would).
  /// Matrix-free Jacobians (Evaluation::d_state_product): up to 4 restarted GMRES cycles of this
  /// length on the true residual; the preconditioner is rebuilt once when they fail, and the
  /// Newton iteration fails when GMRES fails with a fresh one.
  int krylov_max_iterations = 20;
  /// newton_krylov: (0, 1e-6] relative residual ‖b − A z‖₂ / ‖b‖₂ of an accepted GMRES solution
  /// (the true residual, recomputed after GMRES).
  double krylov_tolerance = 1e-11;
  /// A run that continues from a point of a branch traced before (with other scales, or after a
  /// crossing at fixed phase: docs/continuation.md, "Crossing a resonance at fixed phase"): x0
  /// lies on the branch at λ = lambda and the run leaves it along `tangent` ((dx, dλ), unscaled,
  /// size n + 1). The start is corrected on the hyperplane through it normal to that tangent — not
  /// at fixed λ, which is singular where the branch runs vertical in λ (an undamped resonance) —
  /// and its tangent is oriented along it; parameter_start stays the bound behind which the run
  /// ends (left_range).
  struct Continued {
    double lambda = 0.0;
    Eigen::VectorXd tangent;
  };
  std::optional<Continued> continued;
  /// newton_krylov with matrix-free Jacobians: when the preconditioner is rebuilt.
  PreconditionerRefresh preconditioner_refresh = PreconditionerRefresh::every_jacobian;

  [[nodiscard]] std::string validate(Eigen::Index n) const;  ///< empty when valid
};

/// One accepted point of the branch.
struct Point {
  Eigen::VectorXd x;
  double lambda = 0.0;
  Eigen::VectorXd tangent;  ///< unit tangent (scaled unknowns, size n+1; last entry: λ part)
  double step = 0.0;        ///< arclength step that led to this point (0 for the start)
  int iterations = 0;       ///< corrector iterations
  double residual = 0.0;    ///< ‖R‖_∞ / residual_scale at acceptance
  bool fold = false;        ///< dλ/ds changed sign between the previous point and this one
};

enum class StopReason {
  reached_end,      ///< λ crossed parameter_end (last point on it)
  max_points,       ///< max_points accepted
  min_step,         ///< the step fell below min_step: see message
  start_failed,     ///< the corrector at λ = parameter_start did not converge
  stopped_by_user,  ///< the accept callback returned false
  left_range,       ///< the branch turned back across parameter_start (last point on it)
  /// A converged point whose reported outputs (energies, amplitudes) are not finite: it overflowed
  /// doubles (e.g. W_D ∝ q² beyond q ≈ 1e154); the curve ends on the last finite point.
  out_of_range,
  /// An exception ended the curve (set by the callers of the curve drivers, e.g. when writing an
  /// accepted point failed); the points accepted before it are kept where the caller can.
  error,
};

/// The enumerator's name ("reached_end", "min_step", ...), as written to summary files.
[[nodiscard]] std::string_view to_string(StopReason reason);

/// The status convention (contact/termination.hpp) for a continuation's stop reason: the one
/// translation used by every curve of this layer (Result, FrfCurve, BackboneCurve,
/// InterfaceBackbone, InterfaceFrf):
///   reached_end → reached_end;  stopped_by_user → stopped_by_user;
///   max_points → no_convergence (the point budget ran out before the end);
///   min_step, start_failed, left_range, out_of_range, error → failed (the corrector broke down, the start did not
///   converge, the branch turned back across the start: more points would not reach the end).
[[nodiscard]] Termination termination(StopReason reason);

struct Result {
  std::vector<Point> points;
  StopReason reason = StopReason::start_failed;
  std::string message;              ///< one line: why the run ended (always set)
  int rejected_steps = 0;           ///< corrector failures (each halved the step)
  int corrector_iterations = 0;     ///< total over the run (accepted and rejected)
  int evaluations = 0;              ///< calls of the residual function
  double evaluation_seconds = 0.0;  ///< wall time inside the residual function
  double linear_solve_seconds =
      0.0;  ///< wall time in factorisations and solves (tangent, corrector)
  int factorisations = 0;     ///< LU factorisations of bordered matrices, or preconditioner builds
                              ///< (matrix-free Jacobians)
  int krylov_iterations = 0;  ///< GMRES iterations (newton_krylov), failed runs included
  [[nodiscard]] bool completed() const { return reason == StopReason::reached_end; }
  /// {termination(reason), message}.
  [[nodiscard]] Status status() const { return {termination(reason), message}; }
};

/// Called for every accepted point (the start included) in order; return false to stop the run.
using AcceptCallback = std::function<bool(const Point&)>;

/// Traces the branch from the initial guess x0 at λ = options.parameter_start (corrected at fixed
/// λ first). Throws std::invalid_argument on invalid options; never throws for a numerical
/// failure (it is reported in the result). Non-finite residuals, and exceptions thrown by the
/// residual function, count as a failed evaluation (the step is rejected).
Result trace(const ResidualFunction& residual, const Eigen::VectorXd& x0, const Options& options,
             const AcceptCallback& on_accept = {});

}  // namespace jointhb::continuation
