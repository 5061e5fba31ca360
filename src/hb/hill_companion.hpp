#pragma once
// What Hill's method does once the quadratic eigenvalue problem Δ(λ) P = 0 is in companion form
// (docs/theory.md §12, eqs. T-36 to T-38), shared by discrete systems (hb/hill_stability.hpp) and
// the modal/interface model of finite-element joints (hb/interface_hill_stability.hpp)
// (internal header).
#include <Eigen/Core>

#include "jointhb/hb/fourier.hpp"
#include "jointhb/hb/hill_stability.hpp"

namespace jointhb::hb::detail {

/// The time derivative D_Ω of one signal's coefficients: harmonic h, (a, b) ↦ (hΩ b, −hΩ a).
[[nodiscard]] Eigen::MatrixXd time_derivative(const FourierBasis& basis, double omega);

/// The Floquet exponents and multipliers from the companion matrix (2N × 2N, N = dofs · m, its
/// first N rows of an eigenvector being P in `basis`, DOF-major): the 2·dofs eigenvalues whose
/// eigenvectors are most centred in the harmonics (eq. T-37) and ρ = e^{λT} (eq. T-38), by |ρ|
/// descending. ok = false with a message when the eigensolver fails or the matrix is not finite.
[[nodiscard]] FloquetResult floquet_from_companion(const Eigen::MatrixXd& companion,
                                                   const FourierBasis& basis, int dofs,
                                                   double omega, const HillOptions& options);

}  // namespace jointhb::hb::detail
