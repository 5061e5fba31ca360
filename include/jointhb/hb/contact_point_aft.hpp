#pragma once
// Alternating frequency/time (AFT) evaluation of one 3D contact point of a finite-element
// interface, and of a whole interface (docs/theory.md §10, eq. T-17 to T-21).
//
// Each interface point p moves about its preloaded reference state (g_ref, t_ref) (the preload
// solve's gap and traction, fe::InterfaceContactState): g(t) = g_ref + δg(t), g = (g_T1, g_T2, g_N)
// in the point's local frame. The harmonic-balance unknowns are the coefficients δG (m × 3, one
// column per component, coefficients [x0, a1, b1, ...] of hb/fourier.hpp); the residual needs
//   ΔT = coefficients of Δt(t) = t(g_ref + δg(t)) − t_ref,                                  (T-17)
// t from the contact point's periodic steady state on the sampled path (ContactPoint::periodic,
// anchored at t_ref), and the Jacobian
//   ∂ΔT/∂δG = A · ∂t(t_i)/∂g(t_j) · E     (3m × 3m, E: synthesis, A: analysis),           (T-18)
// the middle factor from the periodic-state sensitivity along the 3m basis functions at once.
// Jacobian ordering (component-major, = vec of the m × 3 coefficient matrices):
//   row    c·m + j : coefficient j of Δt_c,   column d·m + l : coefficient l of δg_d,
//   c, d ∈ {0: T1, 1: T2, 2: N}.
// Nonlinear terms couple harmonics only within one point: the interface Jacobian is
// block-diagonal with one such block per point.
//
// The mean must be kept: the exponential normal law rectifies (even harmonics and a mean shift,
// T-19), so odd-only bases are rejected.
//
// Exact shortcuts (same result as the periodic solve to round-off, tested):
//   * open throughout (every sample below the gapping floor): t_T ≡ 0, so Δt_T = −t_ref,T;
//   * a law exactly linear below its limit (Jenkins) with a stiffness that does not depend on the
//     gap (constant model) whose elastic trial t_ref,T + k (g_T,i − g_ref,T) stays within μ p_N,i
//     at every sample: Δt_T = k δg_T.
// With the proportional stiffness model (k = χ λ p_N) a sticking point is not a spring: its elastic
// steps Σ k_{i+1} Δg_i do not telescope when the pressure moves, so it goes through the periodic
// solve. Gaul–Mayer has no elastic range and always does.
//
// Units: tractions and W_D per unit area (or per force unit in force mode, as the law is). The
// interface function leaves the area scaling of ΔT and of the Jacobian blocks to the caller
// (G^T A ΔT); only its total dissipation is area-weighted when areas are given.

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/hb/contact_state.hpp"
#include "jointhb/hb/fourier.hpp"

namespace jointhb::hb {

/// The preloaded reference state of one contact point (what the dynamics perturbs).
struct ContactPointReference {
  Eigen::Vector3d gap = Eigen::Vector3d::Zero();       ///< g_ref = (g_T1, g_T2, g_N) [m]
  Eigen::Vector3d traction = Eigen::Vector3d::Zero();  ///< t_ref = (t_T1, t_T2, t_N = −p_N)
};

/// References of P points from the 3P gap and traction vectors of fe::InterfaceContactState.
/// Throws std::invalid_argument unless both have the same size, a multiple of 3.
std::vector<ContactPointReference> contact_point_references(const Eigen::VectorXd& gap,
                                                            const Eigen::VectorXd& traction);

struct ContactPointAftOptions {
  double periodic_tolerance = 1e-14;  ///< (0, 1e-3]: periodicity tolerance (PeriodicStateOptions)
  int max_iterations = 200;           ///< ≥ 1: periods of the periodic solve
  bool use_shortcuts = true;  ///< the exact shortcuts above (open; Jenkins stuck, constant k)
  /// A periodic solve that does not converge within max_iterations is accepted when its drift per
  /// period |t_0 − Φ_N(t_0)| is at most drift_limit + drift_ratio · max_i |t_T,i − t̄_T| (traction
  /// units; the second term relative to the loop's own amplitude): the ratchet of T-21 under
  /// out-of-phase normal motion, a creep far slower than the vibration whose mean the caller
  /// closes otherwise (hb/interface_balance.hpp, T-28). The traction is then the best state's, its
  /// harmonics in error by about the drift (`drift` reports it). 0 and 0: never accepted.
  double drift_limit = 0.0;
  double drift_ratio = 0.0;
  bool jacobian = false;      ///< compute ∂ΔT/∂δG
  ContactStateOptions states;  ///< the classification of the point's state (hb/contact_state.hpp)

  /// Empty when valid, otherwise the field and the violated constraint.
  [[nodiscard]] std::string validate() const;
};

enum class ContactPointShortcut {
  none,   ///< full periodic solve
  open,   ///< open at every sample
  stuck,  ///< Jenkins elastic throughout (constant stiffness)
};

struct ContactPointAftResult {
  Eigen::MatrixXd traction;          ///< ΔT (m × 3): coefficients of Δt_T1, Δt_T2, Δt_N (T-17)
  Eigen::MatrixXd traction_samples;  ///< Δt(t_i) (N × 3)
  Eigen::MatrixXd jacobian;          ///< ∂ΔT/∂δG (3m × 3m, component-major) when requested
  double dissipation = 0.0;          ///< W_D over one period = ∮ t_T·dg_T on the sampled path
  double open_fraction = 0.0;        ///< share of samples below the gapping floor
  bool stuck = true;                 ///< every tangential step elastic (no slip, never open)
  double limit_share = 0.0;          ///< share of the samples with |t_T| at the slip limit μ p_N
  double limit_ratio = 0.0;          ///< max over the closed samples of |t_T|/(μ p_N)
  ContactState state = ContactState::stuck;  ///< from the above (hb/contact_state.hpp)
  ContactPointShortcut shortcut = ContactPointShortcut::none;
  /// Periodic state converged (always true for a shortcut). One per point per evaluation in the
  /// OpenMP loop over points: a bool, not a Status (contact/termination.hpp), to keep the hot loop
  /// free of allocations; `message` is written only when it is false.
  bool converged = true;
  double drift = 0.0;     ///< |t_0 − Φ_N(t_0)| of the returned state, per unit area
  bool drifting = false;  ///< not periodic, accepted by drift_tolerance
  int iterations = 0;     ///< periods evaluated by the periodic solve
  std::string message;    ///< why not converged
};

/// AFT of one point. `delta_g`: δG (m × 3). Throws std::invalid_argument naming the field on an
/// odd-only basis, wrong sizes, non-finite input or invalid options. Thread-safe (the basis's
/// FFTW plans are made under a lock and executed on private buffers).
ContactPointAftResult evaluate_contact_point(const contact::ContactPoint& point,
                                             const ContactPointReference& reference,
                                             const FourierBasis& basis,
                                             const Eigen::Ref<const Eigen::MatrixXd>& delta_g,
                                             const ContactPointAftOptions& options = {});

struct InterfaceAftResult {
  std::vector<ContactPointAftResult> points;  ///< per point: ΔT_p, Jacobian block, W_D, flags
  Eigen::MatrixXd traction;                   ///< ΔT of all points (m × 3P, columns 3p + c)
  double dissipation = 0.0;  ///< Σ_p a_p W_D,p (a_p = 1 without areas), summed in point order
  int open_points = 0;       ///< points open throughout
  int stuck_points = 0;      ///< points that stick throughout
  ContactStateCounts states;  ///< points per state (hb/contact_state.hpp)
  /// Every point converged: a validity flag of one evaluation (as ContactPointAftResult's), not
  /// how a computation ended; the continuation turns a false one into its StopReason.
  bool converged = true;
  std::string message;       ///< the first point that did not, and why
};

/// AFT of P points in parallel (OpenMP over points; results do not depend on the thread count).
///   points:      one ContactPoint for the whole interface (size 1) or one per point (size P)
///   references:  size P;   delta_g: m × 3P (columns 3p + c, the layout of G u);
///   areas:       empty (unit weights) or P integration weights a_p > 0 for the total W_D.
InterfaceAftResult evaluate_interface_aft(std::span<const contact::ContactPoint> points,
                                          std::span<const ContactPointReference> references,
                                          const FourierBasis& basis,
                                          const Eigen::Ref<const Eigen::MatrixXd>& delta_g,
                                          const ContactPointAftOptions& options = {},
                                          std::span<const double> areas = {});

}  // namespace jointhb::hb
