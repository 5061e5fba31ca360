#pragma once
// Stability of a periodic solution of harmonic balance by Hill's method (docs/theory.md §12,
// eqs. T-35 to T-38).
//
// A perturbation y(t) = e^{λt} p(t) of the periodic solution, p T-periodic with coefficients P in
// the real Fourier basis (hb/fourier.hpp, DOF-major), satisfies the linearised equation of motion
// when (eq. T-35)
//   Δ(λ) P = (J + λ Δ₁ + λ² Δ₂) P = 0,   Δ₁ = C ⊗ I + 2 M ⊗ D_Ω,   Δ₂ = M ⊗ I,
// where J = ∂R/∂X is the harmonic-balance Jacobian at the solution (the linear part S(Ω) and the
// contacts' ∂F_nl/∂X through the periodic-state sensitivity) and D_Ω differentiates a coefficient
// vector in time (harmonic k: (a, b) ↦ (kΩ b, −kΩ a)). The quadratic eigenvalue problem is solved
// in its companion form (eq. T-36)
//   [ 0            I          ] [P ]     [P ]
//   [ −Δ₂⁻¹ J     −Δ₂⁻¹ Δ₁    ] [λP] = λ [λP]     (2N × 2N, N = n (2H + 1)).
// Each Floquet exponent appears 2H + 1 times, shifted by i k Ω, with its eigenvector shifted by k
// harmonics; the truncation spoils the copies near the basis edge. Of the 2N eigenvalues the 2n
// whose eigenvectors are most centred in the harmonics are kept (Lazarus & Thomas, C. R. Mécanique
// 338 (2010) 510–517): the weighted mean harmonic index of P in the complex basis e^{ikΩt},
// k̄ = Σ_k k |c_k|² / Σ_k |c_k|², c_{±k} = (a_k ∓ i b_k)/2 summed over the DOFs, smallest |k̄|
// (eq. T-37). The Floquet multipliers are ρ = e^{λT}, T = 2π/Ω (eq. T-38); the solution is stable
// when every |ρ| ≤ 1 + tolerance.
//
// Hysteretic contacts: J holds the sensitivity of the contact forces to periodic perturbations of
// the gaps. A perturbation e^{λt}p(t) meets the history of the law with weights e^{λ(t' − t)} that
// J sets to 1 (the "frozen" kernel): exact at λ = 0, so that folds (ρ = +1) are located exactly,
// and an approximation of O(|λ|·(t − t')) for the other exponents, where t − t' is the law's
// memory (for a Jenkins element, the time since the last reversal). docs/stability.md compares
// the multipliers with shooting on the time integrator (timeint/shooting.hpp).
//
// The Jacobian must be taken on the full basis 0, 1, ..., H: perturbations need not share the
// solution's symmetry (an odd-harmonic solution can lose stability to an even perturbation).
// HillStability builds that basis when the balance keeps odd harmonics only.

#include <Eigen/Core>
#include <complex>
#include <memory>
#include <optional>
#include <string>

#include "jointhb/hb/harmonic_balance.hpp"

namespace jointhb::hb {

struct HillOptions {
  /// (0, 1e-2]: a multiplier counts as unstable when |ρ| > 1 + unstable_tolerance (the marginal
  /// |ρ| = 1 of an undamped linear system is met to round-off, far below the default)
  double unstable_tolerance = 1e-6;
  [[nodiscard]] std::string validate() const;  ///< empty when valid; names the field
};

/// The kind of loss (or gain) of stability between two points of a curve.
enum class Bifurcation {
  none,
  fold,             ///< a real multiplier crosses +1 where the curve turns in the parameter
  branch_point,     ///< a real multiplier crosses +1 without a turn (a symmetry-breaking branch)
  period_doubling,  ///< a real multiplier crosses −1
  neimark_sacker,   ///< a complex pair crosses the unit circle
  /// the curve's parameter turned but no multiplier crossed +1 (both points known, the same count
  /// of unstable multipliers): not a fold of the branch but the continuation reversing along it at
  /// a kink (docs/stability.md §1)
  reversal,
};

/// "none", "fold", "branch_point", "period_doubling", "neimark_sacker", "reversal".
[[nodiscard]] std::string to_string(Bifurcation b);

struct FloquetResult {
  Eigen::VectorXcd exponents;    ///< the 2n selected λ [1/s], in the order of `multipliers`
  Eigen::VectorXcd multipliers;  ///< ρ = e^{λT}, by |ρ| descending
  double max_multiplier = 0.0;   ///< max |ρ|
  int unstable = 0;              ///< count of |ρ| > 1 + unstable_tolerance
  /// The largest |k̄| kept and the smallest |k̄| rejected (eq. T-37): a clear gap (e.g. 0.2 against
  /// 0.8) says the selection is unambiguous; close values say H is too small for the exponents.
  double kept_centre = 0.0;
  double rejected_centre = 0.0;
  bool ok = false;       ///< false: the eigensolver failed or the matrices were not finite
  std::string message;   ///< why not, when !ok
  [[nodiscard]] bool stable() const { return ok && unstable == 0; }
};

/// Hill's method on a given Jacobian J = ∂R/∂X (basis `basis`, which must hold every harmonic
/// 0..H) of the discrete system at Ω. Throws std::invalid_argument on inconsistent sizes.
FloquetResult hill_floquet(const DiscreteSystem& system, const FourierBasis& basis,
                           const Eigen::MatrixXd& jacobian, double omega,
                           const HillOptions& options = {});

/// The classification of what happened between two stability results of neighbouring points
/// (eq. T-38 and docs/stability.md): when the count of unstable multipliers changes, the
/// multiplier that crossed is the one outside the unit circle closest to it in the less stable
/// point; its argument tells +1 (fold when `turned`, the curve's parameter turned between the
/// points, else branch point), −1 (period doubling) or a complex pair (Neimark–Sacker). A turn
/// without a change of the count is a reversal when both results are known, else a fold.
[[nodiscard]] Bifurcation classify_bifurcation(const FloquetResult& before,
                                               const FloquetResult& after, bool turned);

/// Hill's method for the solutions of one HarmonicBalance: evaluates J on the full basis (a second
/// balance with every harmonic when `balance` keeps odd ones only) and calls hill_floquet.
class HillStability {
 public:
  /// Keeps a reference to `balance` (which must outlive this object).
  explicit HillStability(const HarmonicBalance& balance, HillOptions options = {});
  ~HillStability();
  HillStability(HillStability&&) noexcept;
  HillStability& operator=(HillStability&&) noexcept = delete;

  /// The multipliers of the solution X (in `balance`'s basis) at Ω.
  [[nodiscard]] FloquetResult evaluate(const Eigen::VectorXd& coefficients, double omega) const;

 private:
  const HarmonicBalance& balance_;
  HillOptions options_;
  std::unique_ptr<HarmonicBalance> full_;  ///< every harmonic, when balance_ keeps odd ones only
};

}  // namespace jointhb::hb
