#pragma once
// Hill's method for a finite-element joint's harmonic-balance solution (the modal/interface model
// of hb/interface_model.hpp; docs/theory.md §12, eq. T-36a; docs/stability.md §7).
//
// A perturbation e^{λt} p(t) of the orbit, p T-periodic with coefficients (P_η, P_g) of the kept
// modal coordinates and of the gaps, satisfies the linearised balance (T-26, T-27) with d/dt
// replaced by λ + D_Ω on the modal rows (as eq. T-35 for discrete systems):
//   modal rows:  (J_ηη + λ Δ₁ + λ² I) P_η + J_ηg P_g = 0,   Δ₁ = diag(c_j) ⊗ I + 2 I ⊗ D_Ω,
//   gap rows:     J_gη P_η + J_gg P_g = 0,                   J_gη = −Gφ ⊗ I,  J_gg = I + R B,
// with J the balance's Jacobian at the solution (unscaled rows; c_j = a + b ω_j², B the contacts'
// ∂(A N)/∂δg through the periodic-state sensitivity). The contact DOFs carry no mass — the gap
// rows hold no λ, so Δ₂ is singular on them and the companion form of T-36 does not exist. They are
// eliminated instead (a Schur complement, exact):
//   (S + λ Δ₁ + λ² I) P_η = 0,   S = J_ηη − J_ηg J_gg⁻¹ J_gη,                          (T-36a)
// a quadratic eigenvalue problem in the elastic kept modes alone, solved in companion form and the
// 2(n_s − n_rigid) most centred exponents kept (T-37, T-38), as for discrete systems.
//
// Two approximations besides those of the discrete method (the frozen memory of hysteretic laws,
// hb/hill_stability.hpp): the residual modes respond at each harmonic's frequency kΩ (R_k of
// eq. T-23, not at kΩ − iλ): a relative error O(|λ|/(kΩ)) on their first-order dynamic
// correction, itself O((kΩ)²/μ_r) of their quasi-static response (exact at λ = 0, so folds,
// ρ = +1, are located exactly); and with static_mean_tangential (T-28) the mean of a perturbation
// meets the preloaded stiffness C_pre at every point, as the balance's equations say (a slow drift
// of the joint is held by its static stiffness), where the laws in time would slip.
// Rigid-body kept modes do not move the interface (Gφ_j = 0): their trivial exponents (0 and −a,
// multipliers 1 and e^{−aT}) are left out, so a free-free structure's max |ρ| says something.
//
// Cost: the Jacobian (dense, or U products of apply_jacobian when the balance is matrix-free), an
// LU of the 3Pm × 3Pm block J_gg and n_s m solves with it: O((3Pm)³); the eigenproblem is
// 2(n_s − n_rigid)m square. Against the monodromy's O(N_f (3P)³) (hb/interface_orbit_monodromy.hpp)
// it was 10–70 times cheaper per point at N_f = 1024, H = 3 on the lap at P = 24–192
// (validation/fe/README_interface_stability.md), but its multipliers of slipping contacts are
// wrong away from folds (docs/stability.md §2).

#include <Eigen/Core>

#include "jointhb/hb/hill_stability.hpp"
#include "jointhb/hb/interface_balance.hpp"

namespace jointhb::hb {

/// The Floquet multipliers of the solution y (the balance's unknowns) at Ω (forced response,
/// ξ = 0) by Hill's method (T-36a): 2 (n_s − rigid modes) exponents and multipliers, kept_centre and
/// rejected_centre as for discrete systems. ok = false with a message when a point's periodic
/// state does not converge, J_gg is singular or the eigensolver fails. Throws
/// std::invalid_argument on invalid options or a vector of the wrong size.
FloquetResult interface_hill_floquet(const InterfaceBalance& balance, const Eigen::VectorXd& y,
                                     double omega, const HillOptions& options = {});

}  // namespace jointhb::hb
