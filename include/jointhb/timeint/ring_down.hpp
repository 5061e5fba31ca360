#pragma once
// Free decays (ring-downs) of the discrete system and the amplitude-dependent frequency and damping
// read off them, the time-domain route to nonlinear modes / damping curves:
//   x(0) = q0 Φ_m,  ẋ(0) = 0,  M ẍ + C ẋ + K x + f_nl = 0   (Newmark, newmark.hpp)
//   q(t) = Φ_mᵀ M x(t)                                        (modal coordinate, Φ mass-normalised)
// For each cycle between successive maxima q̂_k, q̂_{k+1} of q (located between samples by the
// quartic through 5 samples) with the minimum q̌_k between them, the oscillation centre c solves
// (q̂_k - c)(q̂_{k+1} - c) = (c - q̌_k)² (exact for a geometric decay about any offset), and
//   amplitude  a_k = √((q̂_k - c)(q̂_{k+1} - c)),
//   ω_k        = 2π / (t_{k+1} - t_k),
//   δ_k        = ln((q̂_k - c)/(q̂_{k+1} - c)),   ζ_k = δ_k / √(4π² + δ_k²).
// With α = 0 the scheme maps each continuous eigenvalue λ to z = (1 + λΔt/2)/(1 - λΔt/2); when
// `correct_time_discretisation` is set, the observed discrete λ_h = (-δ_k + 2πi)/(t_{k+1} - t_k) is
// mapped back by λ = (2/Δt) tanh(λ_h Δt/2): exact for linear systems, and it removes the O(Δt²)
// period elongation of the linear part of a nonlinear one.
//
// A centre that drifts during the decay biases ζ_k (the formula assumes a fixed centre). Friction
// laws without reversal memory do this: the Gaul–Mayer law (eq. 10) unloads to F = 0 and reloads
// on the virgin curve, so a decay leaves residual joint forces and the centre ratchets (ζ_k off by
// 28–47 % for a 1-DOF Gaul–Mayer oscillator, validation/hb/README_epmc_ring_down.md).
// two_cycle_estimates() gives the drift-tolerant estimate over two cycles, with the peak-to-trough
// ranges one period apart R_k = q̂_k − q̌_k, U_k = q̂_{k+1} − q̌_k:
//   δ = ½[ln(R_k/R_{k+1}) + ln(U_k/U_{k+1})],  ζ = δ/√(4π² + δ²),  a = ½ (R_k U_k R_{k+1} U_{k+1})^¼,
// in which a centre moving linearly in time cancels to first order; for a linear decay it is the
// logarithmic decrement (without the Δt correction: ≤ 1e-4 at 256 steps per period).

#include <string>
#include <vector>

#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/timeint/newmark.hpp"

namespace jointhb::timeint {

struct RingDownOptions {
  int mode = 1;  ///< ≥ 1: linear mode (1-based, contacts stuck) of the start shape
  double initial_amplitude = 0.0;  ///< q0 > 0 [√kg·m]: x(0) = q0 Φ_mode (mass-normalised), ẋ(0) = 0
  int steps_per_period = 256;  ///< ≥ 16: Δt = T_mode/steps_per_period (stuck linear mode)
  int max_periods = 2000;      ///< ≥ 2: at most max_periods · steps_per_period steps
  double stop_ratio = 1e-3;    ///< (0, 1): stop once a cycle amplitude < stop_ratio · q0
  /// Undo the trapezoidal rule's eigenvalue map λ → z on each cycle (only with integrator.alpha =
  /// 0; ignored otherwise): see the header comment.
  bool correct_time_discretisation = true;
  NewmarkOptions integrator;  ///< scheme and Newton settings (time_step replaced by T_mode/N)

  /// Empty when valid, else "field: constraint, got value" (integrator fields as "integrator.x").
  [[nodiscard]] std::string validate() const;
};

/// One cycle between successive maxima of the modal coordinate q(t) = Φᵀ M x.
struct RingDownCycle {
  double time = 0.0;           ///< [s] mid-time of the cycle, ½(t_k + t_{k+1})
  double amplitude = 0.0;      ///< a_k [√kg·m]: geometric mean of the two peaks about the centre
  double centre = 0.0;         ///< c [√kg·m]: the oscillation centre (0 for a symmetric decay)
  double first_peak = 0.0;     ///< q̂_k [√kg·m]
  double trough = 0.0;         ///< q̌_k [√kg·m]: the minimum between the peaks
  double second_peak = 0.0;    ///< q̂_{k+1} [√kg·m]
  double omega = 0.0;          ///< ω_k [rad/s] (corrected for Δt when requested)
  double damping_ratio = 0.0;  ///< ζ_k (corrected for Δt when requested)
  /// E(t_k) - E(t_{k+1}) [J], E = ½ẋᵀMẋ + ½xᵀKx + Σ_c F_c²/(2 k_T0) at the samples, linearly
  /// interpolated to the peak times (not corrected for Δt).
  double energy_loss = 0.0;
  double peak_energy = 0.0;  ///< [J] ½(E(t_k) + E(t_{k+1}))
};

/// Why a ring-down stopped: more than Termination says (two different failures), so kept as the
/// detail; RingDownResult::status() is its one translation.
enum class RingDownReason {
  decayed,            ///< a cycle amplitude fell below stop_ratio · q0
  max_periods,        ///< max_periods reached first (e.g. a stuck, undamped joint)
  no_oscillation,     ///< no new maximum for 50 T_mode and 4 last cycle periods: motion died out
  integration_failed  ///< Newton failed in a step: `message` says where; cycles so far are kept
};

struct RingDownResult {
  RingDownReason reason = RingDownReason::max_periods;
  std::string message;  ///< one line
  std::vector<RingDownCycle> cycles;
  double linear_omega = 0.0;  ///< ω of the stuck linear mode [rad/s]
  double time_step = 0.0;     ///< Δt [s]
  double seconds = 0.0;       ///< wall time
  long steps = 0;             ///< Newmark steps
  long newton_iterations = 0;
  /// The status convention (contact/termination.hpp), message `message`: decayed → reached_end
  /// (the goal, stop_ratio, was reached); max_periods → no_convergence; no_oscillation (the motion
  /// died out above the stop ratio: more periods would not help) and integration_failed → failed.
  [[nodiscard]] Status status() const;
};

/// The drift-tolerant estimate over cycles k and k+1 (see the header comment).
struct TwoCycleEstimate {
  std::size_t cycle = 0;       ///< k: uses cycles[k] and cycles[k+1]
  double time = 0.0;           ///< [s] ½(t of cycle k + t of cycle k+1)
  double amplitude = 0.0;      ///< a = ½ (R_k U_k R_{k+1} U_{k+1})^¼ [√kg·m]
  double omega = 0.0;          ///< √(ω_k ω_{k+1}) [rad/s] (damped, as observed)
  double damping_ratio = 0.0;  ///< ζ = δ/√(4π² + δ²)
};

/// One estimate per pair of successive cycles whose four ranges are positive (a pair that is not
/// a decaying oscillation is skipped).
[[nodiscard]] std::vector<TwoCycleEstimate> two_cycle_estimates(
    const std::vector<RingDownCycle>& cycles);

/// The ring-down of `options.mode` from modal amplitude q0, without excitation. Throws
/// std::invalid_argument on invalid options or system, or a mode number beyond the DOF count.
RingDownResult ring_down(const hb::DiscreteSystem& system, const RingDownOptions& options);

}  // namespace jointhb::timeint
