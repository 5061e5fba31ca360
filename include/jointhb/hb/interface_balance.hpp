#pragma once
// Multi-harmonic balance of a preloaded finite-element joint in the modal/interface form of
// hb/interface_model.hpp (docs/theory.md §11, eq. T-26 to T-29).
//
// Unknowns y = [η; δg]: the harmonic coefficients (hb/fourier.hpp, basis with the mean) of the
// n_s kept modal coordinates and of the 3P interface gaps (relative displacements, local frames
// t1, t2, n per point), DOF-major as in hb/harmonic_balance.hpp:
//   y[j·m + c] = coefficient c of η_j,    y[(n_s + 3p + d)·m + c] = coefficient c of δg_{p,d}.
// With N = ΔT(δg) − C_pre δg per point (the contact traction beyond the stuck tangent, by the AFT
// of hb/contact_point_aft.hpp) and the load shape f scaled by the excitation coefficients F_k:
//   modal rows:  D_j(kΩ, ξ) η_jk + (Gφ_j)ᵀ A N_k − (φ_jᵀ f) F_k = 0                       (T-26)
//   gap rows:    δg_k − Σ_j Gφ_j η_jk + R_k(Ω, ξ) A N_k − r_k(Ω, ξ) F_k = 0                (T-27)
// D_j: ω_j² on the mean; [ω_j² − (kΩ)², kΩ(c_j − ξ); −kΩ(c_j − ξ), ω_j² − (kΩ)²] on (a_k, b_k);
// R_k = R0/β − (w/β²) R1 and r_k likewise from the load residuals (eq. T-23): complex numbers act
// on (a_k, b_k) through X = a_k − i b_k. ξ is the EPMC's negative mass-proportional damping
// (0 for forced response). Rigid-body modes (ω_j = 0) have no static equation: their mean is held
// at zero (η_j0 = 0).
//
// Mean tangential traction (T-28): with `static_mean_tangential` (default), the mean of the
// tangential traction follows the preloaded tangent, ΔT_T,0 = C_pre,TT δg_T,0, and only the
// harmonics k ≥ 1 of t_T come from the hysteretic periodic state. The periodic state alone leaves
// the mean undetermined or drifting (Gaul–Mayer relaxes any preloaded t_T to zero, T-21): the
// creep of a joint is a slow process outside a periodic steady state, and this closes the mean
// equation with the static stiffness that holds the joint in place.
//
// Row scaling: modal rows are divided by ω_ref² and gap rows by g_ref (the largest |Gφ| of the
// first elastic kept mode), so that every row is in units of a modal coordinate.
//
// Jacobian (exact): modal/modal D(Ω, ξ); gap/modal −Gφ per coefficient; the contact columns
// B_p = A_p ∂N_p/∂δg_p (3m × 3m per point, harmonics coupled only within the point) enter as
// (Gφ)ᵀ B_p (modal rows) and I + R B_p (gap rows); assembled per point in parallel (OpenMP,
// result independent of the thread count).

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "jointhb/hb/contact_state.hpp"
#include "jointhb/hb/fourier.hpp"
#include "jointhb/hb/interface_local_preconditioner.hpp"
#include "jointhb/hb/interface_model.hpp"

namespace jointhb::hb {

struct InterfaceBalanceOptions {
  int harmonics = 3;                  ///< H ≥ 1 (all harmonics 0..H are kept: the mean is needed)
  int time_samples = 64;              ///< N_t ≥ 2H + 2
  double periodic_tolerance = 1e-12;  ///< (0, 1e-3]: contact periodic-state tolerance
  int max_periodic_iterations = 400;  ///< ≥ 1 (normal-dominated motion with little slip contracts slowly: ~200 periods seen)
  bool static_mean_tangential = true; ///< eq. (T-28)
  /// Tangential stiffness of the hysteretic law during the vibration (eq. T-30): frozen per point
  /// at its preloaded value k_T(p_pre) (the stiffness inside K_t) — the slip limit μ p_N(t) still
  /// follows the pressure, so opening still frees the point — or, when false, following the
  /// instantaneous pressure k_T = χ λ p_N(t) of the proportional model, whose elastic increments
  /// do not telescope and ratchet the mean traction under out-of-phase normal motion (T-21): no
  /// periodic state at low-pressure points. Points of the constant model are unaffected.
  bool preloaded_tangential_stiffness = true;
  /// Accept a point without a periodic state (the T-21 ratchet) when its drift per period is below
  /// drift_tolerance × (μ max p_pre of its interface) + drift_ratio × its loop amplitude
  /// (ContactPointAftOptions::drift_limit/drift_ratio; counted in drifting_points).
  double drift_tolerance = 1e-6;
  double drift_ratio = 1e-3;
  /// Assemble the dense U × U Jacobian when a Jacobian is requested (true), or only the point
  /// blocks B_p (InterfaceBalanceEvaluation::point_blocks) for apply_jacobian (false): the dense
  /// matrix needs 8U² bytes (42 GB at 1600 points, H = 7).
  bool dense_jacobian = true;
  [[nodiscard]] std::string validate() const;  ///< empty when valid; names the field
};

struct InterfaceBalanceEvaluation {
  Eigen::VectorXd residual;   ///< scaled residual (size unknowns())
  Eigen::MatrixXd jacobian;   ///< ∂residual/∂y (when requested and options().dense_jacobian)
  /// B_p = A_p ∂N_p/∂δg_p per point (3m × 3m, rows/columns component-major d·m + c), when a
  /// Jacobian was requested: with Ω, ξ all that apply_jacobian needs.
  std::vector<Eigen::MatrixXd> point_blocks;
  Eigen::VectorXd d_omega;    ///< ∂residual/∂Ω (when requested)
  Eigen::VectorXd d_xi;       ///< ∂residual/∂ξ (when requested)
  Eigen::MatrixXd contact_force;  ///< A N: m × 3P (coefficients of the force beyond stuck)
  double dissipation = 0.0;   ///< Σ_p A_p W_D,p over one period [J] (sampled path, exact)
  /// The work of the truncated contact forces, π Σ_p Σ_k k (a_k^F b_k^g − b_k^F a_k^g)
  /// (docs/theory.md §7): what harmonic balance balances; → dissipation as H grows.
  double fourier_dissipation = 0.0;
  int open_points = 0;        ///< points open throughout the period
  int slipping_points = 0;    ///< points in microslip or gross slip (states.slipping())
  ContactStateCounts states;  ///< points per state (hb/contact_state.hpp)
  int drifting_points = 0;    ///< points accepted with a drift below drift_tolerance
  bool ok = true;             ///< false: a contact's periodic state did not converge
  std::string message;
};

/// What one contact point does over the period of a solution (InterfaceBalance::point_summaries),
/// for output: where the joint slips, opens and dissipates.
struct InterfacePointSummary {
  double dissipation = 0.0;        ///< W_D,p = ∮ t_T·dg_T over one period, per unit area [J/m²]
  double tangential_motion = 0.0;  ///< max_t |δg_T(t) − mean| [m]: the tangential vibration amplitude
  double normal_motion = 0.0;      ///< max_t |δg_N(t) − mean| [m]
  double pressure_min = 0.0;       ///< min_t p_N(t) = −t_N [Pa] (0 while open)
  double pressure_max = 0.0;       ///< max_t p_N(t) [Pa]
  double open_fraction = 0.0;      ///< share of the period below the gapping floor
  bool stuck = true;               ///< no slip and never open
  bool open = false;               ///< open throughout
  ContactState state = ContactState::stuck;  ///< hb/contact_state.hpp
  double limit_ratio = 0.0;        ///< max_t |t_T|/(μ p_N) over the closed samples
  double limit_share = 0.0;        ///< share of the period at the slip limit
};

struct InterfaceBalanceTimings {
  double aft = 0.0, assembly = 0.0, products = 0.0;  ///< [s]; products: apply_jacobian
  double preconditioner = 0.0;  ///< [s]: building preconditioners (factorisations)
  double preconditioner_apply = 0.0;  ///< [s]: applying preconditioners (preconditioner())
  int evaluations = 0, jacobians = 0, product_calls = 0, preconditioners = 0, preconditioner_calls = 0;
};

/// Block-Jacobi preconditioner over harmonics (docs/theory.md §11, eq. T-32c): the inverse of J̃,
/// the Jacobian with every coupling between different harmonics dropped. Since D_j, Gφ and R_k
/// are harmonic-diagonal, J̃ is the Jacobian with each point block B_p replaced by its
/// harmonic-diagonal part, and falls apart into H + 1 dense systems of (n_s + 3P)·d_k unknowns
/// (d_0 = 1 for the mean, d_k = 2 for (a_k, b_k)), each factorised by LAPACK: O(H (n_s + 3P)³)
/// instead of O(((n_s + 3P)(2H + 1))³), and no U × U matrix. Exact where no B_p couples
/// harmonics (the stuck linear limit, B_p = 0); an approximation of J elsewhere.
class InterfaceHarmonicPreconditioner {
 public:
  InterfaceHarmonicPreconditioner();
  ~InterfaceHarmonicPreconditioner();
  /// J̃⁻¹ v (size U).
  [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& v) const;
  /// Smallest reciprocal condition estimate over the harmonic blocks (0: one is singular).
  [[nodiscard]] double rcond() const;
  /// The dense block of harmonic k (0 … H), for tests: rows/columns η_j then δg_i, each with its
  /// d_k coefficients (a_k, b_k) innermost.
  [[nodiscard]] const Eigen::MatrixXd& block(int k) const;
  /// Global unknown index of local index `local` of harmonic k's block.
  [[nodiscard]] Eigen::Index global_index(int k, Eigen::Index local) const;

 private:
  friend class InterfaceBalance;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class InterfaceBalance {
 public:
  /// Throws std::invalid_argument on an invalid model or options (the message names the field).
  InterfaceBalance(InterfaceModel model, InterfaceBalanceOptions options);
  ~InterfaceBalance();
  InterfaceBalance(InterfaceBalance&&) noexcept;
  InterfaceBalance& operator=(InterfaceBalance&&) noexcept;

  [[nodiscard]] const InterfaceModel& model() const;
  [[nodiscard]] const FourierBasis& basis() const;
  [[nodiscard]] const InterfaceBalanceOptions& options() const;
  [[nodiscard]] int modes() const;
  [[nodiscard]] int points() const;
  /// The law of point p as the balance evaluates it: its group's, or with the tangential
  /// stiffness frozen at the preloaded pressure (preloaded_tangential_stiffness, eq. T-30).
  [[nodiscard]] const contact::ContactPoint& point_law(int p) const;
  [[nodiscard]] Eigen::Index unknowns() const;  ///< (n_s + 3P)·m
  [[nodiscard]] Eigen::Index modal_index(int mode, int coefficient) const;
  [[nodiscard]] Eigen::Index gap_index(int point, int component, int coefficient) const;
  /// ω_ref (first elastic kept mode) and g_ref (largest |Gφ| of it): the row scales.
  [[nodiscard]] double reference_omega() const;
  [[nodiscard]] double reference_gap() const;
  /// Typical magnitude of each unknown per unit modal coordinate (1 for η, g_ref for δg).
  [[nodiscard]] Eigen::VectorXd unknown_scale() const;

  /// Residual at (y, Ω, ξ) with the load coefficients F (size m, or empty: no load).
  void evaluate(const Eigen::VectorXd& y, double omega, double xi, const Eigen::VectorXd& load,
                bool jacobian, InterfaceBalanceEvaluation& out) const;

  /// ∂residual/∂y · v without the U × U matrix (Jacobian-vector product), from the point blocks
  /// of an evaluation `at` (with a Jacobian) at (Ω, ξ): the linear part of eq. (T-26, T-27) with
  /// A N replaced by its directional derivative B v (per point). Cost O(ns·3P·m + (3P)²·m +
  /// 9P·m²) instead of O(U²) = O((3P)²·m²). Equals jacobian · v to round-off.
  /// single_precision: R0 and R1 applied from single-precision copies (made at the first such
  /// call; sgemm, half the memory traffic): a product accurate to ~1e-7 relative, for the inner
  /// iterations of a solve whose residual is checked with the double-precision product.
  [[nodiscard]] Eigen::VectorXd apply_jacobian(const InterfaceBalanceEvaluation& at, double omega,
                                               double xi, const Eigen::VectorXd& v,
                                               bool single_precision = false) const;

  /// The harmonic block-Jacobi preconditioner (InterfaceHarmonicPreconditioner) at the point
  /// blocks of `at` (an evaluation with the Jacobian) and (Ω, ξ). Factorises the H + 1 blocks in
  /// parallel (OpenMP over harmonics; the result does not depend on the thread count).
  [[nodiscard]] std::shared_ptr<const InterfaceHarmonicPreconditioner> harmonic_preconditioner(
      const InterfaceBalanceEvaluation& at, double omega, double xi) const;

  /// An approximate inverse v ↦ J⁻¹ v of the Jacobian at the point blocks of `at` (an evaluation
  /// with the Jacobian) and (Ω, ξ): the point-local J_loc (T-34, InterfaceLocalPreconditioner) or
  /// the harmonic block-Jacobi J̃ (T-32c). Building and applying it are timed (timings()).
  [[nodiscard]] std::function<Eigen::VectorXd(const Eigen::VectorXd&)> preconditioner(
      const InterfaceBalanceEvaluation& at, double omega, double xi, InterfacePreconditioner kind) const;

  /// Per contact point (P): what it does over the period at the solution y (the same periodic
  /// states the residual uses, with the traction and gap samples reduced to the fields of
  /// InterfacePointSummary). Throws std::invalid_argument on a wrong size.
  [[nodiscard]] std::vector<InterfacePointSummary> point_summaries(const Eigen::VectorXd& y) const;

  /// The stuck linear solution (N ≡ 0) for the load F at Ω (ξ = 0).
  [[nodiscard]] Eigen::VectorXd linear_solution(double omega, const Eigen::VectorXd& load) const;

  /// Coefficients (m) of output o at the solution y, with `contact_force` the A N of an evaluation
  /// at y (eq. T-25 with the output's residual parts).
  [[nodiscard]] Eigen::VectorXd output_coefficients(int output, const Eigen::VectorXd& y,
                                                    double omega, double xi,
                                                    const Eigen::VectorXd& load,
                                                    const Eigen::MatrixXd& contact_force) const;

  /// Load coefficients (m) of F(t) = amplitude · cos Ωt.
  [[nodiscard]] Eigen::VectorXd cosine_load(double amplitude) const;

  [[nodiscard]] InterfaceBalanceTimings timings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace jointhb::hb
