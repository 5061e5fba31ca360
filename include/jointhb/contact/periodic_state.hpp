#pragma once
// Periodic steady state of a hysteretic tangential law on a prescribed periodic path.
//
// The path is sampled at N instants t_i = iT/N. Step i maps the traction t_i to
//   t_{i+1} = S(t_i, g_{i+1} - g_i, L_{i+1}, k_{i+1})     (indices mod N),
// with S the law's exact increment. The steady state is the solution of the periodicity condition
//   t_0 = Φ_N(t_0)     (Φ_N: one period of steps),
// solved by damped Newton with the exact monodromy matrix M = ∂Φ_N/∂t_0 = A_{N-1}⋯A_0,
// safeguarded by fixed-point steps extrapolated along the drift where Newton does not help or,
// far from the steady state, where the period map does not contract (docs/theory.md §5, creep).
// Cycling alone is not used: at small amplitude each period
// contracts the error only by about (1 - |F_T|/μF_N)^{2n} (docs/theory.md §5).
//
// Uniqueness: where the condition does not fix the state (a Jenkins contact that sticks throughout
// the period, or a path without motion), the state is fixed by the reference (preloaded) state:
// Newton starts at the anchored state t_0 = t_ref + k_0 (g_0 - g_ref) (radially clamped to the
// limit) and corrects it by the minimum-norm step (pseudo-inverse of I - M). A contact that sticks
// throughout therefore behaves as a linear spring about the preloaded state, and one that cannot
// stick there moves to the periodic state closest to it. docs/theory.md, "Periodic steady state".

#include <Eigen/Core>
#include <string>
#include <vector>

#include "jointhb/contact/tangential_law.hpp"
#include "jointhb/contact/termination.hpp"

namespace jointhb::contact {

/// Singular values of I − M (M the period map's monodromy, entries O(1)) below this are round-off:
/// that direction is not fixed by periodicity (the contact sticks) and follows the anchor. Used by
/// the periodic solve and by the harmonic balance's AFT of the same laws.
inline constexpr double kPeriodicSingular = 1.0e-13;

/// A periodic tangential path: slip and law parameters at each sample.
struct PeriodicPath {
  std::vector<Vec2> slip;                ///< g_T(t_i) [m], N ≥ 2 samples
  std::vector<TangentialLimits> limits;  ///< slip limit and stiffness at t_i (size N)
};

struct PeriodicStateOptions {
  double tolerance = 1.0e-15;  ///< (0, 1e-3]: |t_0 - Φ_N(t_0)| ≤ tolerance · max_i |t_i|
  int max_iterations = 200;    ///< ≥ 1: Newton/fixed-point iterations
  Vec2 reference_traction = Vec2::Zero();  ///< t_ref: tangential traction of the reference state
  Vec2 reference_slip = Vec2::Zero();      ///< g_ref: slip of the reference state
  bool keep_step_derivatives = true;       ///< store A_i, B_i, c_i, d_i for sensitivities

  [[nodiscard]] std::string validate() const;
};

struct PeriodicStateResult {
  /// converged: periodicity satisfied to the tolerance; no_convergence: max_iterations reached,
  /// the state is the best found (see `residual`).
  Termination termination = Termination::no_convergence;
  std::string message;  ///< one line; may be empty (status() then states the residual)
  std::vector<Vec2> traction;         ///< t_T(t_i), i = 0..N-1
  double dissipation = 0.0;           ///< Σ of the step dissipations over one period (W_D)
  double loading_slip = 0.0;          ///< slip travelled on non-elastic branches over one period
  bool stuck = true;                  ///< every step elastic (linear about the reference)
  int iterations = 0;                 ///< periods evaluated
  double residual = 0.0;              ///< |t_0 - Φ_N(t_0)| at the returned state
  Mat2 monodromy = Mat2::Identity();  ///< M = ∂Φ_N/∂t_0

  // Step derivatives of step i (t_i → t_{i+1}), kept when requested.
  std::vector<Mat2> d_traction;       ///< A_i = ∂t_{i+1}/∂t_i
  std::vector<Mat2> d_slip;           ///< B_i = ∂t_{i+1}/∂(g_{i+1} - g_i)
  std::vector<Vec2> d_limit;          ///< c_i = ∂t_{i+1}/∂L_{i+1}
  std::vector<Vec2> d_stiffness;      ///< d_i = ∂t_{i+1}/∂k_{i+1}
  Vec2 anchor_offset = Vec2::Zero();  ///< g_0 - g_ref (for the derivative of the anchor)
  double anchor_stiffness = 0.0;      ///< k_0
  /// The status convention (contact/termination.hpp): `termination` with `message`, or with the
  /// iterations and residual when the message is empty (formatted here, not in the solver's loop).
  [[nodiscard]] Status status() const;
};

PeriodicStateResult solve_periodic_state(const TangentialLaw& law, const PeriodicPath& path,
                                         const PeriodicStateOptions& options = {});

/// Linearised response of the periodic state to m simultaneous path perturbations, O(N·m):
///   slip:      2N × m  (rows 2i, 2i+1: δg_x, δg_y at sample i)
///   limit:     N × m or empty (δL_i),   stiffness: N × m or empty (δk_i)
/// returns the 2N × m matrix of δt_i. Requires keep_step_derivatives.
Eigen::MatrixXd periodic_sensitivity(const PeriodicStateResult& state, const Eigen::MatrixXd& slip,
                                     const Eigen::MatrixXd& limit = {},
                                     const Eigen::MatrixXd& stiffness = {});

}  // namespace jointhb::contact
