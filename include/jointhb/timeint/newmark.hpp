#pragma once
// Time-domain reference for the discrete system of hb/discrete_system.hpp:
//   M ẍ + C ẋ + K x + f_nl = f_ex(t),   f_nl = Σ_c F_c (e_a - e_b),   g_c = x_a - x_b,
// integrated by the Newmark average-acceleration rule (β = 1/4, γ = 1/2), optionally with the
// Hilber–Hughes–Taylor α modification (α ∈ [-1/3, 0], β = (1-α)²/4, γ = (1-2α)/2):
//   x_{n+1} = x_n + Δt v_n + Δt² [(½ - β) a_n + β a_{n+1}]
//   v_{n+1} = v_n + Δt [(1 - γ) a_n + γ a_{n+1}]
//   M a_{n+1} + (1+α)(C v_{n+1} + K x_{n+1} + f_nl,n+1) - α (C v_n + K x_n + f_nl,n)
//       = (1+α) f_ex(t_{n+1}) - α f_ex(t_n).
// Each contact's state is its force: F_{n+1} = S(F_n, g_{n+1} - g_n), the law's exact increment
// (contact::TangentialLaw::scalar_step), so the contact forces are exact for the sampled gaps.
// The step equation is solved for x_{n+1} by Newton's method with a line search (docs/
// time-integration.md): the residual is the gradient of a strictly convex function (the laws are
// monotone in the increment), so the line search along the Newton direction never cycles at
// stick/slip transitions. Non-convergence is a status, never an abort.
//
// With α = 0 the scheme is the trapezoidal rule: energy-conserving for linear undamped systems
// and, in steady state under e^{iΩt}, exact for the "warped" frequency (2/Δt) tan(ΩΔt/2) — the
// phase error that makes the harmonic amplitudes converge like Δt².

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/contact/termination.hpp"

namespace jointhb::timeint {

struct NewmarkOptions {
  double time_step = 0.0;          ///< Δt [s] > 0 (forced_steady_state sets it to T/N itself)
  double alpha = 0.0;              ///< HHT α ∈ [-1/3, 0]; 0: average acceleration (trapezoidal)
  int max_newton_iterations = 50;  ///< ≥ 1: Newton iterations per step
  /// (0, 1e-3]: ‖r‖∞ ≤ tol · (largest force term of the step), or ≤ the round-off floor
  /// 8ε(largest term + ‖J‖∞‖x‖∞) that stiff contacts and small Δt raise
  double newton_tolerance = 1e-10;
  int max_line_search = 30;  ///< ≥ 1: residual evaluations per line search

  /// Empty when valid, else "field: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

/// The state at one instant. Empty `acceleration` is completed from the equation of motion and
/// empty `contact_forces` from the reference state (F = F_ref + k_T0 (g - g_ref), clamped to μF_N).
struct State {
  Eigen::VectorXd displacement;        ///< x [m], size n
  Eigen::VectorXd velocity;            ///< ẋ [m/s], size n
  Eigen::VectorXd acceleration;        ///< ẍ [m/s²], size n or empty
  std::vector<double> contact_forces;  ///< F_c [N], one per contact, or empty
  double time = 0.0;                   ///< t [s]
};

/// The system at rest at x = 0 (contact forces from the reference state).
State rest_state(const hb::DiscreteSystem& system, double time = 0.0);

/// The steady state of the linear system with every contact stuck (K + k_T0 terms) under the
/// excitation, at `time`: x = K_s⁻¹ f_static' + Σ_j Re[(K_s - (h_jΩ)² M + i h_jΩ C)⁻¹ f_j e^{i h_j
/// Ω t}], with f_static' including the contacts' reference force and slip. Contact forces follow
/// from the reference state. std::nullopt when one of the linear systems is singular.
std::optional<State> stuck_linear_state(const hb::DiscreteSystem& system,
                                        const hb::Excitation& excitation, double omega,
                                        double time = 0.0);

struct TransientResult {
  /// reached_end: all steps taken; failed: Newton failed in a step, stopped there (final_state is
  /// the last good state) — the same event SteadyStateResult calls failed.
  Termination termination = Termination::reached_end;
  std::string message;                      ///< one line (empty when all steps were taken)
  State final_state;                        ///< the state after the last completed step
  int steps = 0;                            ///< completed steps
  long newton_iterations = 0;               ///< Newton iterations over all steps
  int max_step_iterations = 0;              ///< the most Newton iterations one step needed
  long line_searches = 0;                   ///< steps in which the full Newton step was cut back
  std::vector<double> contact_dissipation;  ///< Σ of the exact step dissipations per contact [J]
  double external_work = 0.0;               ///< Σ ½(f_n + f_{n+1})·(x_{n+1} - x_n) [J]
  double viscous_dissipation = 0.0;         ///< Σ ½(v_n + v_{n+1})ᵀ C (x_{n+1} - x_n) [J]
  double seconds = 0.0;                     ///< wall time
  /// The status convention (contact/termination.hpp): `termination` with `message`, or with
  /// "N steps" when that is empty.
  [[nodiscard]] Status status() const;
};

/// `steps` steps of size options.time_step from `initial` under f_ex(t) at fundamental frequency
/// `omega` (any value when the excitation has no harmonic terms: free decays). `on_step` is called
/// with the new state after every completed step. Throws std::invalid_argument on invalid options,
/// an inconsistent system, or sizes that do not match it.
TransientResult integrate(const hb::DiscreteSystem& system, const hb::Excitation& excitation,
                          double omega, State initial, int steps, const NewmarkOptions& options,
                          const std::function<void(const State&)>& on_step = {});

struct SteadyStateOptions {
  int steps_per_period = 512;  ///< N ≥ 2·harmonics + 2: Δt = T/N, T = 2π/Ω
  int max_periods = 2000;      ///< ≥ 1
  double tolerance = 1e-9;     ///< (0, 1e-2]: relative change of (x, ẋ, F) over one period
  int harmonics = 7;           ///< H ≥ 1: coefficients reported per DOF
  NewmarkOptions integrator;   ///< scheme and Newton settings (its time_step is replaced by T/N)

  /// Empty when valid, else "field: constraint, got value" (integrator fields as "integrator.x").
  [[nodiscard]] std::string validate() const;
};

struct SteadyStateResult {
  /// converged: the period-start state repeats to the tolerance; no_convergence: max_periods
  /// reached, the last period is reported (see `change`); failed: Newton failed in a step,
  /// `message` says where, no period data (empty matrices).
  Termination termination = Termination::no_convergence;
  std::string message;      ///< one line
  int periods = 0;          ///< periods integrated
  double change = 0.0;      ///< relative change of the period-start state over the last period
  double period = 0.0;      ///< T = 2π/Ω [s]
  double time_step = 0.0;   ///< Δt = T/N [s]
  double start_time = 0.0;  ///< t of the first sample of the last period [s]
  State final_state;        ///< the state at the end of the last period (start of the next)

  // The last period, sampled at t_j = start_time + jΔt, j = 0..N-1.
  Eigen::MatrixXd samples;                ///< n × N: x_i(t_j)
  Eigen::MatrixXd contact_force_samples;  ///< contacts × N: F_c(t_j)
  /// n × (2H+1): [x0, a1, b1, ..., aH, bH] with x(t) = x0 + Σ a_k cos kΩt + b_k sin kΩt in the
  /// absolute time t (the phase of the excitation), by the direct sums
  /// x0 = (1/N) Σ_j x_j, a_k = (2/N) Σ_j x_j cos kΩt_j, b_k = (2/N) Σ_j x_j sin kΩt_j.
  Eigen::MatrixXd coefficients;
  Eigen::VectorXd amplitude_max;            ///< n: max_j |x_i(t_j)| (at the samples)
  std::vector<double> contact_dissipation;  ///< per contact, over the last period [J]
  double external_work = 0.0;               ///< over the last period [J]
  double viscous_dissipation = 0.0;         ///< over the last period [J]

  long steps = 0;              ///< steps over all periods
  long newton_iterations = 0;  ///< over all steps
  double seconds = 0.0;        ///< wall time
  /// The status convention (contact/termination.hpp): `termination` with `message`.
  [[nodiscard]] Status status() const { return {termination, message}; }
};

/// Periodic steady state under f_ex(t) at Ω by integrating whole periods until the state at the
/// start of a period repeats: max(‖Δx‖∞/X, ‖Δẋ‖∞/V, ‖ΔF‖∞/F) ≤ tolerance, where X, V, F are the
/// largest |x|, |ẋ|, |F| over the period (groups without motion are skipped). Starts from `initial`
/// or else from stuck_linear_state (rest_state when that is singular). Throws
/// std::invalid_argument on invalid options, system or sizes, and for Ω ≤ 0.
SteadyStateResult forced_steady_state(const hb::DiscreteSystem& system,
                                      const hb::Excitation& excitation, double omega,
                                      const SteadyStateOptions& options,
                                      std::optional<State> initial = {});

}  // namespace jointhb::timeint
