#pragma once
// Point-local preconditioner of the interface harmonic balance (docs/theory.md §11, eq. T-34).
//
// The Jacobian of eq. (T-26, T-27) is (T-32a)
//   J = [ D            (Gφ)ᵀ B   ]      B = blockdiag_p B_p (3m × 3m, harmonics coupled in a point),
//       [ −Gφ ⊗ I_m    I + R B   ],     R = the residual flexibility, dense over the points.
// It is approximated by keeping, of R, only the 3 × 3 blocks of each point with itself (R_pp per
// harmonic, the complex combination of eq. T-23), and everything else exactly: the kept modes, the
// contact blocks with all their harmonic couplings, the EPMC's Ω, ξ columns (by the caller):
//   J_loc = [ D          (Gφ)ᵀ B            ]
//           [ −Gφ ⊗ I_m  I + blockdiag R_pp B_p ].
// Its inverse is exact by block elimination onto the kept modes (a Schur complement of ns·m
// unknowns, m = 2H + 1):
//   E_p = I + R_pp B_p,   X_p = B_p E_p⁻¹,   S = D + Σ_p Φ_pᵀ X_p Φ_p   (Φ_p = Gφ_p ⊗ I_m),
//   t_p = E_p⁻¹ r_g,p,   η = S⁻¹ (r_η − Σ_p Φ_pᵀ X_p r_g,p),   g_p = t_p + E_p⁻¹ Φ_p η.
// Cost: building O(P (3m)³ + P m² ns² · 3), applying O(P (3m)² + 3P ns m) — linear in P, against
// the O(H (n_s + 3P)³) build and O(H (n_s + 3P)²) application of the harmonic block-Jacobi
// preconditioner (T-32c), which is exact where B = 0 but ignores B's harmonic couplings. J_loc is
// exact at the stuck limit (B = 0) and wherever the contact points do not interact through the
// residual flexibility; what it drops is R's coupling between different points.

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace jointhb::hb {

class InterfaceBalance;

/// Which approximate inverse of the interface Jacobian preconditions GMRES.
enum class InterfacePreconditioner {
  point_local,      ///< InterfaceLocalPreconditioner (T-34): O(P) build and application (default)
  harmonic_blocks,  ///< InterfaceHarmonicPreconditioner (T-32c): H + 1 dense LUs of (n_s + 3P)·d_k
};
struct InterfaceBalanceEvaluation;

class InterfaceLocalPreconditioner {
 public:
  /// From the point blocks of `at` (an evaluation with the Jacobian) at (Ω, ξ). Throws
  /// std::invalid_argument when `at` has no point blocks. The per-point factorisations run in
  /// parallel (OpenMP); the result does not depend on the thread count.
  /// group_size ≥ 1: R is kept within groups of up to this many points that it couples most
  /// strongly (neighbourhoods; 1: each point alone, eq. T-34).
  InterfaceLocalPreconditioner(const InterfaceBalance& balance, const InterfaceBalanceEvaluation& at,
                               double omega, double xi, int group_size = 1);
  ~InterfaceLocalPreconditioner();

  /// J_loc⁻¹ v (size U, scaled rows as InterfaceBalance::evaluate).
  [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& v) const;
  /// Points whose E_p was numerically singular and left out (E_p = I taken instead).
  [[nodiscard]] int singular_points() const;
  [[nodiscard]] int groups() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace jointhb::hb
