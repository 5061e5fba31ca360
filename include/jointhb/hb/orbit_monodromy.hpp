#pragma once
// Floquet multipliers of a harmonic-balance solution from the monodromy of its variational
// equation along the orbit (docs/theory.md §12, eqs. T-39 and T-40; docs/stability.md §2).
//
// Hill's method (hb/hill_stability.hpp) reads the exponents from the harmonic-balance Jacobian,
// whose contact blocks are the sensitivity to *periodic* perturbations: for the hysteretic laws of
// jointhb that freezes the law's memory and misplaces every exponent but λ = 0 (a slipping Jenkins
// contact offers no stiffness to a periodic shift, so Hill finds an exponent damped only by C).
// Here the perturbation is followed in time instead, with the law's own increment derivatives:
// on the orbit x*(t) of the coefficients X, sampled at t_j = jT/N_f (N_f = samples),
//   δF_{j+1} = a_j δF_j + b_j (δg_{j+1} − δg_j),   a_j = ∂F_{j+1}/∂F_j, b_j = ∂F_{j+1}/∂Δg_j   (T-39)
// for each contact on its periodic state (contact::solve_periodic_state on the fine samples), and
//   M δẍ + C δẋ + K δx + Σ_c δF_c (e_a − e_b) = 0
// by the trapezoidal rule (average acceleration) from t = 0 to T for each unit initial state of
// z = (δx, δẋ, δF_slipping); the monodromy Φ = ∂z(T)/∂z(0) gives
//   ρ = eig(Φ),   stable ⇔ max |ρ| ≤ 1 + tol.                                            (T-40)
// A contact that sticks during the whole period is the spring k_T0 about the reference state, as
// in harmonic balance: its force is not a state (no neutral slider multiplier). A slipping Jenkins
// contact's force state has multiplier 0; a Gaul–Mayer contact's, the slow relaxation of its mean
// force (close to 1 at small amplitude) — both are multipliers of the real system.
//
// Accuracy: O(Δt²) on smooth stretches (the trapezoidal phase error, as in timeint/newmark.hpp)
// and O(Δt) from stick/slip switches that fall between samples; the default N_f = 4096 gives
// ~1e-3 on the 1-DOF Jenkins oscillator (docs/stability.md §2). Cost: N_f steps, each a solve with
// an n × n Cholesky factor refactored only where a contact's b_j changes, on 2n + n_slipping
// columns: O(N_f n² (2n + n_c)).

#include <Eigen/Core>
#include <string>

#include "jointhb/hb/harmonic_balance.hpp"
#include "jointhb/hb/hill_stability.hpp"

namespace jointhb::hb {

struct OrbitMonodromyOptions {
  int samples = 4096;  ///< N_f ≥ 64: time steps per period of the variational equation
  double unstable_tolerance = 1e-6;  ///< (0, 1e-2]: |ρ| > 1 + tol counts as unstable
  [[nodiscard]] std::string validate() const;  ///< empty when valid; names the field
};

/// The multipliers of the orbit of X (in `balance`'s basis) at Ω, as a FloquetResult (exponents
/// λ = log ρ / T; kept_centre and rejected_centre unused). Throws std::invalid_argument on
/// invalid options or a coefficient vector of the wrong size.
FloquetResult orbit_floquet(const HarmonicBalance& balance, const Eigen::VectorXd& coefficients,
                            double omega, const OrbitMonodromyOptions& options = {});

/// The multipliers ρ = eig(Φ) of a monodromy Φ over `period` (by |ρ| descending, exponents
/// log ρ / T, |ρ| > 1 + unstable_tolerance counted unstable); ok = false when Φ is not finite or
/// the eigensolver fails. Shared by the discrete and the finite-element monodromies. The
/// eigenvalues are those of the balanced matrix (LAPACK dgeev): Φ's blocks carry the units of the
/// state (coordinates, velocities, tractions in Pa) and span up to 27 orders of magnitude, where
/// unbalanced QR returns |ρ| ~ 1e4 for multipliers at 1 (docs/stability.md §7).
FloquetResult floquet_from_monodromy(const Eigen::MatrixXd& monodromy, double period,
                                     double unstable_tolerance);

}  // namespace jointhb::hb
