#pragma once
// Floquet multipliers of a finite-element joint's harmonic-balance solution (the modal/interface
// model of hb/interface_model.hpp) from the monodromy of its variational equation along the orbit
// (docs/theory.md §12, eqs. T-39a and T-40a; docs/stability.md §7).
//
// As for discrete systems (hb/orbit_monodromy.hpp) the perturbation is followed in time with the
// contact laws' own increment derivatives, not read from the harmonic-balance Jacobian (Hill's
// method freezes the laws' memory). On the orbit sampled at t_i = iT/N_f, per contact point p
// (local frame t1, t2, n; step i lands on sample i + 1):
//   δt_T,i+1 = A_i δt_T,i + B_i (δg_T,i+1 − δg_T,i) + (c_i L'_{i+1} + d_i k'_{i+1}) δg_N,i+1,
//   δt_N,i+1 = t_N'(g_N,i+1) δg_N,i+1,                                                    (T-39a)
// (A_i, B_i, c_i, d_i: contact::PeriodicStateResult; L' and k': the slip limit's and stiffness's
// derivatives by the gap). The structure obeys, with the contact force beyond the stuck tangent
// δF = A (δt − C_pre δg) (areas A, C_pre per point):
//   η̈ + C_m η̇ + Λ η + (GΦ)ᵀ δF = 0,        δg = GΦ η − R0 δF,                           (T-40a)
// the kept modes η exactly and the residual modes quasi-statically: the first term R0 of the
// expansion T-23 (their inertia R1 and their stiffness-proportional damping 1/β are left out —
// corrections of relative order (kΩ)²/μ_r and kΩ b). Per step, with δt = α_i + K_i δg (α_i: the
// force states' part), δF = W_i (Aα_i + D_i GΦ η) where D_i = A (K_i − C_pre) and
// W_i = (I + D_i R0)⁻¹; η by the trapezoidal rule (average acceleration), as in
// hb/orbit_monodromy.hpp, from each unit initial state of z = (η, η̇, δt_T of the points that
// slip or open). ρ = eig(∂z(T)/∂z(0)), without the two trivial multipliers of each rigid-body kept
// mode (it does not move the interface: 1 and its damped velocity). A point that sticks during
// the whole period with a constant tangential stiffness is that spring (no force state, no
// neutral multiplier).
//
// Cost: N_f steps, each an LU of the 3P × 3P matrix I + D_i R0 where D_i changed (every step when
// a normal law's stiffness varies along the orbit) and n_s × n_s solves on 2n_s + 2P_s columns:
// O(N_f ((3P)³ + n_s²(2n_s + 2P_s))) — seconds for tens of points, not for hundreds.

#include <Eigen/Core>

#include "jointhb/hb/hill_stability.hpp"
#include "jointhb/hb/interface_balance.hpp"
#include "jointhb/hb/orbit_monodromy.hpp"

namespace jointhb::hb {

/// The multipliers of the orbit of y (the balance's unknowns: modal and gap coefficients) at Ω
/// (forced response, ξ = 0), as a FloquetResult (exponents λ = log ρ / T; kept_centre and
/// rejected_centre unused); ok = false with a message when a point's periodic state does not
/// converge or the monodromy is not finite. Throws std::invalid_argument on invalid options or a
/// vector of the wrong size.
FloquetResult interface_orbit_floquet(const InterfaceBalance& balance, const Eigen::VectorXd& y,
                                      double omega, const OrbitMonodromyOptions& options = {});

}  // namespace jointhb::hb
