#pragma once
// Periodic orbit and Floquet multipliers of the discrete system of hb/discrete_system.hpp by
// shooting on the Newmark period map (docs/time-integration.md §9): the time-domain reference for
// the stability that Hill's method reads from the harmonic-balance Jacobian. It shares the model
// and the integrator (timeint/newmark.hpp) and nothing else — no Fourier basis, no AFT, no
// periodic-state solver.
//
// State (the integrator's own state at a period start, t = 0):
//   z = (x, ẋ, F_c) ∈ R^{2n + n_c};  the acceleration is recomputed from the equation of motion.
// Period map, T = 2π/Ω, N = steps_per_period Newmark steps of Δt = T/N from t = 0 (`integrate`):
//   P(z) = z(T; z(0) = z)                                                              (TI-22)
// Newton on the periodicity condition, with the monodromy Φ ≈ ∂P/∂z by central differences:
//   (Φ(z_k) − I) δ = −(P(z_k) − z_k),   z_{k+1} = z_k + λ δ,
//   Φ e_j ≈ [P(z + h_j e_j) − P(z − h_j e_j)] / (2 h_j)                                  (TI-23)
// (λ = 1, halved until the residual falls; with no decrease in 12 halvings and the residual above
// 1e-6, i.e. far from the orbit, whole periods z ← P(z) until the residual halves)
// with h_j = perturbation · (X, V or μF_N of the contact) for an x, ẋ or F component (X, V: the
// largest |x|, |ẋ| over the period; X = V/Ω, or μF_N/k_T0, or 1 when there is no motion), and
// one-sided differences where z ± h_j e_j would put a contact force beyond its slip limit μF_N.
// Converged when max(‖Δx‖∞/X, ‖Δẋ‖∞/V, ‖ΔF‖∞/F) ≤ tolerance, Δ = P(z) − z, as forced_steady_state
// measures the change over a period (TI-9). Then Φ is evaluated again at the converged orbit and
//   ρ = eig(Φ(T)),   the orbit is asymptotically stable iff max|ρ| < 1.                   (TI-24)
//
// Contacts that stick during the whole period (a Jenkins contact whose every step of the orbit
// stayed on the elastic branch, zero dissipation): F_c − k_T0 g_c (the slider) is then constant,
// and every slider position gives another periodic orbit — an exactly neutral multiplier 1 that
// harmonic balance, which fixes the contact's reference state, does not have. Such a contact's
// force is eliminated from the state: a perturbation keeps its slider fixed,
//   F_c = F_c(orbit) + k_T0 (g_c − g_c(orbit)),                                            (TI-25)
// so Φ acts on z_r = (x, ẋ, F_slipping) (size 2n + n_slipping), the Newton step keeps the sliders
// of the guess, and `stuck_contacts` lists the contacts so treated (re-classified at every Newton
// iterate). The perturbed periods keep them on their linear branch (slip limit raised): on an
// orbit that touches the limit (after a shakedown; `stuck_margins` ≈ 0) a perturbation of one sign
// would otherwise slip and spoil Φ. A slipping contact's force is a genuine state: for Jenkins its
// multiplier is 0 (a contact slipping at T has forgotten its force), for Gaul–Mayer it is the slow
// relaxation of the mean force (close to 1 at small amplitude; theory.md §5). Hill's method on the
// 2n-dimensional first-order system has neither: compare its 2n multipliers with the others.
//
// Accuracy: the trapezoidal rule (α = 0) has the phase error of (TI-8), so a linear system's
// multipliers are ((1 + λΔt/2)/(1 − λΔt/2))^N = e^{λT}(1 + λ³TΔt²/12 + …): O(Δt²). Stick/slip
// switches fall between samples, which the exact contact increments capture in the force but not
// in the scheme's acceleration: with slipping Jenkins contacts the multipliers converge like 1/N
// only, with a coefficient that scatters with the switches' positions in their steps (≈ 5/N in
// the 1-DOF case of docs/time-integration.md §9: use N ≥ 16384 for 1e-4). The period map is only
// piecewise smooth (a step's force has a kink where its trial force meets μF_N); a difference
// straddling a kink averages the two sides. With HHT (α < 0) the integrator's a_n does not satisfy
// the equation of motion, so the map with a recomputed acceleration differs from the integrator's
// continued run by O(α); use α = 0 to compare with forced_steady_state. The differences need P(z)
// to round-off, hence the tighter Newton tolerance of the integrator by default (1e-13; the
// integrator's own default is 1e-10).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "jointhb/contact/termination.hpp"
#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/timeint/newmark.hpp"

namespace jointhb::timeint {

struct ShootingOptions {
  int steps_per_period = 2048;     ///< N ≥ 4: Δt = T/N, T = 2π/Ω
  int max_newton_iterations = 30;  ///< ≥ 0: Newton steps tried (0: only the monodromy of the guess)
  double tolerance = 1e-10;  ///< (0, 1e-2]: relative ‖P(z) − z‖ (groups x, ẋ, F as TI-9)
  /// (0, 1e-2]: relative finite-difference step h_j (TI-23). Not smaller: the period map carries
  /// round-off that grows faster than N, which the differences divide by h (1e-7 left errors of
  /// 3e-5 in linear multipliers at N = 2048, 1e-5 leaves 1.6e-7; docs/time-integration.md §9).
  /// Larger steps straddle more stick/slip kinks; smooth stiff cases may take 1e-4.
  double perturbation = 1e-5;
  /// ≥ 0: periods of plain integration, z ← P(z), allowed in all when a Newton step finds no
  /// decrease in 12 halvings with the residual above 1e-6 (far from the orbit); each such round
  /// runs until the residual halves. 0: such a Newton step is a failure.
  int max_cycled_periods = 500;
  /// Scheme and Newton settings of the period map (its time_step is replaced by T/N); the Newton
  /// tolerance is tightened to 1e-13 by default so that differences of P see no solver noise.
  NewmarkOptions integrator = [] {
    NewmarkOptions o;
    o.newton_tolerance = 1e-13;
    return o;
  }();

  /// Empty when valid, else "field: constraint, got value" (integrator fields as "integrator.x").
  [[nodiscard]] std::string validate() const;
};

struct ShootingResult {
  /// converged: ‖P(z) − z‖ ≤ tolerance, monodromy at the orbit; no_convergence:
  /// max_newton_iterations or max_cycled_periods used, or a Newton step found no decrease with the
  /// residual already ≤ 1e-6 (the round-off of the period map, which grows with N: a tolerance of
  /// 1e-10 is out of reach at N = 65536, docs/time-integration.md §9); failed: Φ − I was singular
  /// (a multiplier at 1: the orbit is not isolated), a Newton step found no decrease far from the
  /// orbit with max_cycled_periods = 0, or a period integration failed — `message` says which.
  /// orbit_start is always the last iterate, with its monodromy and multipliers except when a
  /// period integration failed (then empty).
  Termination termination = Termination::no_convergence;
  std::string message;  ///< one line
  /// z at t = 0: displacement, velocity, contact_forces (all contacts, stuck ones included) and
  /// the acceleration from the equation of motion.
  State orbit_start;
  /// Φ = ∂P/∂z_r in the units of z_r (m, m/s, N): rows and columns named by `components`.
  Eigen::MatrixXd monodromy;
  /// ρ = eigenvalues of Φ, by modulus descending (then imaginary part descending).
  Eigen::VectorXcd multipliers;
  double spectral_radius = 0.0;         ///< max|ρ| (0 when there is no monodromy)
  std::vector<std::string> components;  ///< "x[i]", "v[i]", "F[c]" per row of the monodromy
  std::vector<int> stuck_contacts;      ///< contacts eliminated by TI-25 (ascending)
  /// Per stuck contact: 1 − max|F_c|/μF_N over the orbit. ≈ 0: the orbit touches the slip limit
  /// (typical after a shakedown); the monodromy is still that of the linear branch (TI-25).
  std::vector<double> stuck_margins;
  int newton_iterations = 0;  ///< Newton steps taken (accepted)
  int cycled_periods = 0;     ///< periods integrated when Newton steps did not decrease
  double residual = 0.0;      ///< relative ‖P(z) − z‖ at orbit_start
  double period = 0.0;        ///< T = 2π/Ω [s]
  double time_step = 0.0;     ///< Δt = T/N [s]
  long period_maps = 0;       ///< one-period integrations (nominal and perturbed)
  double seconds = 0.0;       ///< wall time
  /// The status convention (contact/termination.hpp): `termination` with `message`.
  [[nodiscard]] Status status() const { return {termination, message}; }
};

/// The T-periodic orbit through t = 0 near `initial` and its monodromy and Floquet multipliers
/// (TI-22..25). `initial` is the guess for the state at t = 0 (its time is not used;
/// forced_steady_state's final_state or stuck_linear_state(system, excitation, Ω) are good
/// guesses); empty contact_forces are taken from the reference state, and the guess's sliders of
/// contacts that stick are kept (TI-25). Throws std::invalid_argument on invalid options, an
/// inconsistent system or excitation, a state whose sizes do not match, and for Ω ≤ 0; numerical
/// failure is a status.
ShootingResult periodic_orbit_by_shooting(const hb::DiscreteSystem& system,
                                          const hb::Excitation& excitation, double omega,
                                          State initial, const ShootingOptions& options);

}  // namespace jointhb::timeint
