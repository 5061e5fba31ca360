#pragma once
// Time-domain reference for the full (uncondensed) finite-element model with its contact
// interfaces, about the preloaded state (docs/time-integration.md §8). With w = u − u_pre:
//   M ẅ + C ẇ + K_L w + Σ_I G_Iᵀ A_I (t_I − t_I,pre) = f_ex(t),   K_L = K_s + Σ_b k_b b_b b_bᵀ  (FE-1)
// (K_s, M: fe/assembly.hpp; the bolts locked at their preload, eq. (B-3); the bolt forces P_b and
// the preloaded contact tractions t_pre cancel the static residual, so w = 0 is an exact
// equilibrium — the preload's residual of ~1e-9 ‖f_bolt‖ is not carried into the dynamics).
// Each point's traction advances by the contact law's exact increment from the last converged
// step, t_{n+1} = ContactPoint::step(t_T,n, g_n, g_{n+1}) (contact_point.hpp), g = g_pre + G w:
// the state per point is (t_T, g). No Fourier series, no AFT: independent of the HB code path.
// Tangential stiffness (`preloaded_tangential_stiffness`, default on, as harmonic balance's eq.
// T-30, docs/theory.md §11): each point steps with ContactPoint::with_constant_stiffness(k_T,p),
// k_T,p = k_T(g_pre,p) = χ λ p_pre,p its preloaded stiffness (the stiffness inside K_t), floored
// at the gapping floor's stiffness for points open in the preload; the slip limit μ p_N(t) still
// follows the instantaneous pressure. Off: k_T = χ λ p_N(t) of the proportional model. Points of
// the constant model are unaffected either way.
//
// Damping: Rayleigh, C = a M + b K_t with K_t the stuck tangent about the preload, eq. (P-2)
// (PreloadResult::dynamic_stiffness). A constant matrix, so a Craig–Bampton model reproduces it
// exactly by projection (C_r = a M_r + b K_t,r). Modal damping is not offered.
//
// Scheme: Newmark average acceleration (β = 1/4, γ = 1/2) or HHT-α, as timeint/newmark.hpp:
//   M a_{n+1} + (1+α)(C v_{n+1} + K_L w_{n+1} + f_c,n+1) − α(C v_n + K_L w_n + f_c,n)
//       = (1+α) f_ex(t_{n+1}) − α f_ex(t_n).
// Newton per step with a lagged (modified-Newton) matrix
//   J̃ = M/(βΔt²) + (1+α)(γ/(βΔt) C + K_L + Σ_I G_Iᵀ A C̃_I G_I),
// C̃ the symmetric PSD part of each point's consistent tangent (as the preload solver), factored
// by CHOLMOD (one symbolic analysis) and refactored only when an iteration reduces the residual
// by less than `refactor_ratio`. J̃ is SPD for a free-free model (M/(βΔt²) > 0).
// Constraints: PreloadModel::constraints hold in the dynamics too; the 3-2-1 support of a
// free-free preload (PreloadResult::support_dofs) is not: the dynamics is free-free.

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/contact/termination.hpp"
#include "jointhb/preload/preload_solver.hpp"

namespace jointhb::timeint {

/// F cos(Ω t) on one DOF of the full vector (DOF 3i + d: node i, axis d).
struct FeHarmonicForce {
  int dof = 0;
  double amplitude = 0.0;  ///< F [N]
};

/// f_ex(t) = static_force + Σ_j F_j cos(Ω t) e_{dof_j}.
struct FeExcitation {
  std::vector<FeHarmonicForce> forces;
  Eigen::VectorXd static_force;  ///< full DOFs, or empty

  [[nodiscard]] Eigen::VectorXd at(double omega, double time, int num_dofs) const;
};

struct FeNewmarkOptions {
  double time_step = 0.0;          ///< Δt [s] > 0 (the steady-state driver sets T/N)
  double alpha = 0.0;              ///< HHT α ∈ [-1/3, 0]; 0: average acceleration
  double mass_damping = 0.0;       ///< a [1/s] ≥ 0 in C = a M + b K_t
  double stiffness_damping = 0.0;  ///< b [s] ≥ 0
  int max_newton_iterations = 40;  ///< ≥ 1 per step
  /// (0, 1e-3]: ‖r‖∞ ≤ tol · (largest force term of the step), or ≤ the round-off floor
  double newton_tolerance = 1e-10;
  /// (0, 1): refactor J̃ with the current tangent when ‖r_{k+1}‖∞ > ratio · ‖r_k‖∞
  double refactor_ratio = 0.2;
  /// Each point's tangential stiffness frozen at its preloaded value k_T(p_pre) (eq. T-30, the
  /// harmonic balance default hb::InterfaceBalanceOptions::preloaded_tangential_stiffness), the
  /// slip limit following p_N(t); false: k_T = χ λ p_N(t) (proportional model).
  bool preloaded_tangential_stiffness = true;

  /// Empty when valid, else "field: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

/// The contact law each point of each interface steps with under `options` (per interface, one
/// ContactPoint per point): the interface's law, or with preloaded_tangential_stiffness its
/// constant-stiffness copy at k_T(g_pre,p) (eq. T-30), floored at χ λ ε_gap p_N0.
std::vector<std::vector<contact::ContactPoint>> fe_point_laws(const preload::PreloadModel& model,
                                                             const preload::PreloadResult& preload,
                                                             const FeNewmarkOptions& options);

/// The state at one instant; w = u − u_pre.
struct FeState {
  Eigen::VectorXd displacement;  ///< w [m], full DOFs
  Eigen::VectorXd velocity;      ///< ẇ [m/s]
  Eigen::VectorXd acceleration;  ///< ẅ [m/s²]; empty: from the equation of motion
  std::vector<Eigen::VectorXd> traction;  ///< per interface, 3P (t_Tx, t_Ty, t_N) local frames
  std::vector<Eigen::VectorXd> gap;       ///< per interface, 3P: the gaps these tractions belong to
  double time = 0.0;                      ///< t [s]
};

/// The preloaded state at rest (w = 0, contact states of the preload).
FeState preloaded_state(const preload::PreloadModel& model, const preload::PreloadResult& preload,
                        double time = 0.0);

/// Steady state of the stuck linearisation at `time`: w = Re[(K_t − Ω²M + iΩC)⁻¹ F e^{iΩt}] +
/// K_t⁻¹ f_static (the static part only with constraints, else ignored), tractions by the exact
/// increment from the preload. std::nullopt when the complex system is singular.
std::optional<FeState> stuck_linear_fe_state(const preload::PreloadModel& model,
                                             const preload::PreloadResult& preload,
                                             const FeExcitation& excitation, double omega,
                                             const FeNewmarkOptions& options, double time = 0.0);

struct FeTransientResult {
  /// reached_end: all steps taken; failed: Newton failed in a step (final_state is the last good
  /// state).
  Termination termination = Termination::reached_end;
  std::string message;  ///< empty when all steps were taken
  FeState final_state;
  int steps = 0;
  long newton_iterations = 0;
  int max_step_iterations = 0;
  long line_search_cuts = 0;  ///< halvings of a Newton step (a step that increased ‖r‖∞)
  int factorizations = 0;     ///< of J̃ (one symbolic analysis)
  std::vector<double> contact_dissipation;  ///< per interface: Σ_steps Σ_p a_p D_p [J]
  double contact_work = 0.0;     ///< Σ ½(f_c,n + f_c,n+1)·Δw, the scheme's contact work [J]
  double external_work = 0.0;    ///< Σ ½(f_n + f_{n+1})·Δw [J]
  double viscous_dissipation = 0.0;  ///< Σ ½(v_n + v_{n+1})ᵀ C Δw [J]
  double seconds = 0.0;
  /// The status convention (contact/termination.hpp): `termination` with `message`, or with
  /// "N steps" when that is empty.
  [[nodiscard]] Status status() const;
};

/// `steps` steps from `initial`. Throws std::invalid_argument on invalid options, excitation or
/// state sizes (naming the field).
FeTransientResult integrate_fe(const preload::PreloadModel& model,
                               const preload::PreloadResult& preload,
                               const FeExcitation& excitation, double omega, FeState initial,
                               int steps, const FeNewmarkOptions& options,
                               const std::function<void(const FeState&)>& on_step = {});

struct FeSteadyStateOptions {
  int steps_per_period = 256;  ///< N ≥ 2H + 2
  int max_periods = 500;       ///< ≥ 1
  double tolerance = 1e-7;     ///< (0, 1e-2]: relative change of (w, ẇ) over one period
  int harmonics = 5;           ///< H ≥ 1
  std::vector<int> output_dofs;  ///< DOFs sampled and projected (full numbering)
  FeNewmarkOptions integrator;   ///< its time_step is replaced by T/N
  /// Called after every period: (period, relative change).
  std::function<void(int, double)> progress;

  [[nodiscard]] std::string validate() const;
};

struct FeSteadyStateResult {
  /// converged: (w, ẇ) repeat over a period to the tolerance; no_convergence: max_periods
  /// reached, the last period is reported (see `change`); failed: Newton failed in a step,
  /// `message` says where, no period data.
  Termination termination = Termination::no_convergence;
  std::string message;
  int periods = 0;
  double change = 0.0;  ///< relative change of (w, ẇ) over the last period
  double period = 0.0, time_step = 0.0, start_time = 0.0;
  FeState final_state;
  Eigen::MatrixXd samples;       ///< outputs × N: w at t_j = start_time + jΔt
  /// outputs × (2H+1): [w0, a1, b1, ...], w(t) = w0 + Σ a_k cos kΩt + b_k sin kΩt (absolute t)
  Eigen::MatrixXd coefficients;
  // Energy over the last period [J]: external_work = viscous_dissipation + contact_work exactly
  // for the scheme (up to the periodicity change); contact_work ≈ Σ contact_dissipation (the
  // exact increments' dissipation) up to the trapezoidal rule's O(Δt²).
  // With the change ΔE of ½ẇᵀMẇ + ½wᵀK_L w over the period, W_ext = ΔE + W_visc + W_c holds
  // step by step (α = 0), also when the period has not repeated yet.
  double external_work = 0.0, viscous_dissipation = 0.0, contact_work = 0.0;
  double stored_energy_change = 0.0;
  std::vector<double> contact_dissipation;  ///< per interface
  long steps = 0;
  long newton_iterations = 0;
  int max_step_iterations = 0;
  long line_search_cuts = 0;
  int factorizations = 0;
  double seconds = 0.0;
  double seconds_per_step = 0.0;
  /// The status convention (contact/termination.hpp): `termination` with `message`.
  [[nodiscard]] Status status() const { return {termination, message}; }
};

/// Integrates whole periods from `initial` (default: stuck_linear_fe_state, else the preloaded
/// state) until max(‖Δw‖∞/W, ‖Δẇ‖∞/V) ≤ tolerance over one period (W, V: largest |w|, |ẇ| at the
/// period's samples). Throws std::invalid_argument on invalid options/excitation/Ω ≤ 0.
FeSteadyStateResult fe_forced_steady_state(const preload::PreloadModel& model,
                                           const preload::PreloadResult& preload,
                                           const FeExcitation& excitation, double omega,
                                           const FeSteadyStateOptions& options,
                                           std::optional<FeState> initial = {});

}  // namespace jointhb::timeint
