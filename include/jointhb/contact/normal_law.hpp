#pragma once
// Normal contact of rough surfaces: the exponential pressure-gap law of Gaul & Mayer, eq. (6),
//   p_N(g_N) = p_N0 exp(-λ (g_N - g_N0)),  λ = 1/σ,
// whose normal stiffness per area is k_N = -dp_N/dg_N = λ p_N (the paper's k_N = -λ p_N is the
// slope dp_N/dg_N). The law never reaches p_N = 0: "gapping" means p_N has fallen below a floor.
//
// Sign convention used throughout jointhb: g_N is the normal gap (opening positive), and the normal
// traction conjugate to g_N in the virtual work (eq. 22) is t_N = -p_N (the paper's p_N = -t_N).

#include <string>

namespace jointhb::contact {

struct ExponentialNormalLaw {
  double reference_pressure =
      1.0e6;                   ///< p_N0 [Pa] (or [N] in force mode), > 0: value at g_N = g_N0
  double decay = 1.0e5;        ///< λ = 1/σ [1/m], > 0: inverse standard deviation of roughness
  double reference_gap = 0.0;  ///< g_N0 [m]: gap at which p_N = p_N0

  /// Empty when valid, otherwise a message naming the field and the violated constraint.
  [[nodiscard]] std::string validate() const;

  /// p_N(g_N), eq. (6). The exponent is capped so that the result stays finite for any closure.
  [[nodiscard]] double pressure(double gap) const;
  /// k_N = λ p_N(g_N) = -dp_N/dg_N (normal stiffness per area, eq. 6).
  [[nodiscard]] double stiffness(double gap) const;
  /// Gap at which the pressure equals p (inverse of eq. 6), p > 0.
  [[nodiscard]] double gap_at_pressure(double p) const;
};

}  // namespace jointhb::contact
