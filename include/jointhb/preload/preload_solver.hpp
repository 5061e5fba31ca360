#pragma once
// The preloaded static state of a bolted assembly (docs/bolts-and-preload.md):
//   r(u) = K_s u + Σ_I G_Iᵀ A_I t_I(G_I u) − s (f_bolt + f_static) = 0,
//   f_bolt = −Σ_b P_b b_b                                                                   (P-1)
// (K_s: structure, eq. (1) of fe/assembly.hpp; t_I: the contact laws of interface I at every
// integration point, the static convention of fe/interface.hpp; bolts under force control, eq.
// (B-2); f_static: nodal forces and surface pressures, fe/static_load.hpp, ramped with the bolts),
// solved by Newton–Raphson with load stepping in s = 1/n, 2/n, …, 1 and a backtracking
// line search on ‖r‖, the tangent K_s + Σ_I G_Iᵀ A C_I G_I factored by CHOLMOD (analysed once;
// in the quadratic phase the factor is reused for chord steps, PreloadOptions::reuse_factor_ratio).
//
// Rigid-body motion: an assembly held only by its bolts is free-free. The bolt forces are
// self-equilibrated, so a statically determinate (3-2-1) support carries no load: it removes the
// six rigid-body motions without constraining the joint. Static loads on a free-free model must be
// self-equilibrated too (resultant force and moment below 1e-9 of Σ|f_i|, else an error). The support reactions are computed and
// reported (they are round-off). With user constraints no support is added.
//
// The dynamic tangent about the preloaded state (for modes and condensation) is
//   K_t = K_s + Σ_I G_Iᵀ A C_stuck G_I + Σ_b k_b b_b b_bᵀ,   C_stuck = diag(k_T, k_T, λ p_N)  (P-2)
// with k_T(p_N) the sticking tangential stiffness of the law (small vibrations about the preload
// load and unload the tangential law elastically) and λ p_N the normal stiffness, eq. (6).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/contact/termination.hpp"
#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/interface.hpp"
#include "jointhb/fe/mesh.hpp"
#include "jointhb/fe/sparse_cholesky.hpp"
#include "jointhb/fe/static_load.hpp"
#include "jointhb/fe/tie.hpp"
#include "jointhb/preload/bolt.hpp"

namespace jointhb::preload {

/// One zero-thickness interface with its contact law (the same at every point).
struct ContactInterface {
  fe::Interface geometry;
  contact::ContactPoint law;
};

/// Everything the preload needs; built by the case reader or by hand.
struct PreloadModel {
  const fe::Mesh* mesh = nullptr;
  fe::StructuralMatrices structure;      ///< K_s, M (full DOFs)
  std::vector<ContactInterface> interfaces;
  std::vector<Bolt> bolts;
  std::vector<fe::FixedNodes> constraints;  ///< user supports; empty = free-free (3-2-1 added)
  fe::StaticLoads loads;                    ///< f_static of eq. (P-1): forces and pressures
  /// Bonded surfaces (fe/tie.hpp). Their stiffness K_tie is part of `structure.stiffness`
  /// (pipeline::preload_model adds it; the solver does not): listed here for the connectivity
  /// check, which counts the parts they join as connected.
  std::vector<fe::Tie> ties;
};

struct PreloadOptions {
  int load_steps = 4;                  ///< ≥ 1: s = k / load_steps
  int max_iterations = 40;             ///< ≥ 1: Newton iterations per load step
  double residual_tolerance = 1e-9;    ///< (0, 1): ‖r_free‖ ≤ tol · ‖f_bolt‖ (s = 1)
  int max_line_search = 12;            ///< ≥ 0: halvings of the Newton step
  /// Modified Newton: after an iteration that reduced the residual by at least this factor
  /// (a full step, the quadratic phase), the next iteration first tries the step with the
  /// factor it already has (a chord step: one solve, no assembly or factorisation); the chord
  /// step is kept when it decreases ‖r‖, otherwise the tangent is refactored at the same state.
  /// This also carries the last factor of a converged load step into the first iteration of the
  /// next. The convergence test (residual_tolerance on the exact residual) is unchanged.
  /// 0 = plain Newton (a factorisation every iteration); in [0, 1).
  double reuse_factor_ratio = 0.1;
  /// [0, 1): a point counts as closed when p_N ≥ this fraction of the interface's mean pressure
  /// (clamping force / area).
  double closed_pressure_fraction = 0.01;
  /// Who factors the Newton matrix: CHOLMOD, or MUMPS across MPI ranks (fe/petsc_solvers.hpp).
  fe::LinearSolver linear_solver = fe::LinearSolver::cholmod;
  /// linear_solver = cg: its preconditioner and tolerance (the rigid-body modes of the mesh are
  /// its near-null space unless given).
  fe::IterativeSettings iterative = {};
  /// Called after every Newton iteration (load step, iteration, relative residual).
  std::function<void(int, int, double)> progress;

  [[nodiscard]] std::string validate() const;
};

struct PreloadStep {
  double load_factor = 0.0;
  int iterations = 0;      ///< accepted iterations (Newton and chord)
  int factorizations = 0;  ///< of the tangent (≤ iterations + rejected chord steps)
  int chord_iterations = 0;  ///< accepted iterations that reused the previous factor
  int line_search_cuts = 0;
  double residual = 0.0;  ///< relative, at the end of the step
  /// converged: the residual met residual_tolerance; no_convergence: max_iterations used first;
  /// failed: the tangent could not be factored or the line search found no decrease.
  Termination termination = Termination::failed;
  std::string message;  ///< why the step did not converge (empty when it did)

  /// The status convention (contact/termination.hpp): `termination` with `message`.
  [[nodiscard]] Status status() const { return {termination, message}; }
};

/// The contact state of one interface at the preloaded state.
struct InterfaceResult {
  std::string name;
  fe::InterfaceContactState state;  ///< gaps, tractions, pressure, open flags per point
  double clamping_force = 0.0;      ///< Σ a_p p_N,p [N]
  double closed_area = 0.0;         ///< [m²]: points with p_N ≥ closed_pressure_fraction · mean
  double closed_area_fraction = 0.0;
  double max_pressure = 0.0;  ///< [Pa]
  double mean_pressure = 0.0; ///< clamping force / total area [Pa]
  double max_gap = 0.0;       ///< [m] largest normal gap
  double min_gap = 0.0;       ///< [m]
};

struct PreloadResult {
  /// converged: every load step converged; otherwise the termination of the first load step that
  /// did not (no_convergence: it used all max_iterations; failed: a tangent that could not be
  /// factored or a line search without decrease).
  Termination termination = Termination::failed;
  std::string message;  ///< one line: the totals when converged, else the failed step and why
  std::vector<PreloadStep> steps;
  Eigen::VectorXd displacement;  ///< u (full DOFs) at the last converged load step
  double load_factor = 0.0;      ///< s of that step (1 when converged)
  std::vector<InterfaceResult> interfaces;
  std::vector<double> bolt_forces;  ///< s P_b
  std::vector<int> support_dofs;    ///< DOFs of the 3-2-1 support (empty with user constraints)
  double support_reaction = 0.0;    ///< max |reaction| at the support / max P (should be ~ε)
  fe::DofMap dofs;                  ///< free DOFs of the preload solve
  Eigen::SparseMatrix<double> dynamic_stiffness;  ///< K_t, eq. (P-2), full DOFs
  std::string factor_statistics;    ///< CHOLMOD's one-line statistics
  fe::SparseCholeskyStatistics factor;  ///< the same as numbers; factorizations = Σ steps' factorizations
  int total_iterations = 0;
  double assembly_seconds = 0.0, contact_seconds = 0.0, factor_seconds = 0.0, seconds = 0.0;

  /// The status convention (contact/termination.hpp): `termination` with `message`.
  [[nodiscard]] Status status() const { return {termination, message}; }
};

/// Throws std::invalid_argument naming a part that is neither constrained nor joined (through
/// interfaces, ties and bolts) to a constrained part; without constraints, naming a part outside
/// the group of the first part (a free-free model must be one group). solve_preload calls it; the
/// case reader calls it to report the problem against the case file.
void check_connectivity(const fe::Mesh& mesh, std::span<const ContactInterface> interfaces,
                        std::span<const Bolt> bolts, std::span<const fe::FixedNodes> constraints,
                        std::span<const fe::Tie> ties = {});

/// Solves eq. (P-1). Throws std::invalid_argument on invalid options or a model whose parts are
/// not all connected (by interfaces, ties and bolts) or constrained (naming the part). Numerical
/// failures (no convergence, a singular tangent) end with a termination other than converged, a
/// message, and the last converged step kept.
[[nodiscard]] PreloadResult solve_preload(const PreloadModel& model, const PreloadOptions& options);

/// The DOFs of a statically determinate 3-2-1 support of the mesh (nodes A, B, C far apart):
/// A fixed in x, y, z; B in the two axes across AB's dominant axis; C in the axis that stops the
/// rotation about AB. Throws std::invalid_argument when the nodes are collinear.
[[nodiscard]] std::vector<int> statically_determinate_support(const fe::Mesh& mesh);

/// The stuck tangent C_p = diag(k_T, k_T, λ p_N) of eq. (P-2) at every point of an interface,
/// for its gaps (3P, local frames, as fe::gaps returns them).
[[nodiscard]] std::vector<Eigen::Matrix3d> stuck_tangents(const ContactInterface& interface,
                                                          const Eigen::VectorXd& gaps);

/// The stuck dynamic tangent of eq. (P-2), full DOFs.
[[nodiscard]] Eigen::SparseMatrix<double> dynamic_stiffness(const PreloadModel& model,
                                                             const Eigen::VectorXd& displacement);

}  // namespace jointhb::preload
