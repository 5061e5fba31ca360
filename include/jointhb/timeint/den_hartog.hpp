#pragma once
// Den Hartog's exact steady state of the forced oscillator with Coulomb friction
//   m ẍ + k x + F_f sgn(ẋ) = P cos ωt
// (J. P. Den Hartog, "Forced vibrations with combined viscous and Coulomb damping", Phil. Mag.
// (7) 9 (1930) 801–817; "Forced vibrations with combined Coulomb and viscous friction", Trans.
// ASME APM-53-9 (1931) 107–115), for the continuous ("non-stop") motion with two instantaneous
// stops per cycle. With β = ω/ω_n, ω_n = √(k/m), x_st = P/k, r = F_f/P,
//   V = 1/(1 - β²),   U = sin(π/β) / (β (1 + cos(π/β))),
//   X0/x_st = √(V² - (rU)²),   cos φ = (X0/x_st)/V,   sin φ = -rU/V,
// where X0 is the peak displacement, reached at ωt = φ (mod 2π): the displacement peak lags the
// force peak by φ. Over the half period σ = ωt - φ ∈ [0, π] (ẋ ≤ 0):
//   x/x_st = r (1 - cos(σ/β)) - β r U sin(σ/β) + (X0/x_st) cos σ + r U sin σ,
// and x(σ + π) = -x(σ). docs/time-integration.md derives it and states how it was verified (an
// event-driven exact Coulomb integration and the Newmark integrator with a stiff Jenkins contact).
//
// The form is a solution only where the motion has no stick phase: the mass must leave each stop
// at once (X0/x_st > r/β², i.e. r < |V| / √(U² + β⁻⁴), which tends to Den Hartog's π/4 at
// resonance) and must not reverse in between (checked on the exact velocity). Elsewhere the
// result says which condition fails; it never returns NaN.

#include <Eigen/Core>
#include <string>

namespace jointhb::timeint {

enum class DenHartogRegime {
  non_stop,           ///< continuous motion, two instantaneous stops per cycle: the form holds
  sticks_at_stops,    ///< X0/x_st ≤ r/β²: at the stop the spring and force cannot beat friction
  extra_stops,        ///< the form's velocity changes sign inside a half period
  no_real_amplitude,  ///< V² ≤ (rU)²: no non-stop motion of this form
  singular_frequency,  ///< β = 1, or cos(π/β) = -1 (β = 1/3, 1/5, ...) with r > 0: no finite form
};

struct DenHartogResult {
  DenHartogRegime regime = DenHartogRegime::no_real_amplitude;
  bool non_stop = false;  ///< regime == non_stop: the fields below describe the exact motion
  std::string message;    ///< one line

  double natural_frequency = 0.0;  ///< ω_n = √(k/m) [rad/s]
  double omega = 0.0;              ///< ω [rad/s]
  double frequency_ratio = 0.0;    ///< β = ω/ω_n
  double static_deflection = 0.0;  ///< x_st = P/k [m]
  double friction_ratio = 0.0;     ///< r = F_f/P
  double magnification = 0.0;      ///< V = 1/(1 - β²) (0 at β = 1)
  double friction_function = 0.0;  ///< U (0 where singular)
  /// r < |V|/√(U² + β⁻⁴): the stop condition; the largest r of the non-stop form at this β
  /// (the velocity check can fail below it at low β). 0 where singular.
  double boundary_friction_ratio = 0.0;
  double formula_amplitude = 0.0;  ///< x_st √(V² - (rU)²) when real, whatever the regime [m]

  // The exact steady motion (zero unless non_stop).
  double amplitude = 0.0;                 ///< X0 = max |x(t)| [m]
  double phase = 0.0;                     ///< φ: x(t) peaks at ωt = φ (mod 2π) [rad]
  double first_harmonic_amplitude = 0.0;  ///< √(a1² + b1²) of the exact x(t) [m]
  double dissipation_per_cycle = 0.0;     ///< 4 F_f X0 [J] (= π P b1, the work of the force)

  /// x(t) [m] and ẋ(t) [m/s] of the exact steady motion (0 unless non_stop).
  [[nodiscard]] double displacement(double time) const;
  [[nodiscard]] double velocity(double time) const;
  /// [x0, a1, b1, ..., aH, bH] of x(t) = x0 + Σ a_k cos kωt + b_k sin kωt (jointhb convention),
  /// integrated analytically over the exact piecewise motion (only odd k are non-zero).
  [[nodiscard]] Eigen::VectorXd coefficients(int harmonics) const;
};

/// Throws std::invalid_argument unless mass, stiffness, force_amplitude and omega are finite and
/// > 0 and friction_force is finite and ≥ 0.
DenHartogResult den_hartog(double mass, double stiffness, double friction_force,
                           double force_amplitude, double omega);

}  // namespace jointhb::timeint
