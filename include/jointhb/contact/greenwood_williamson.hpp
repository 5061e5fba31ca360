#pragma once
// Greenwood–Williamson contact of a rough elastic surface on a rigid plane with an exponential
// distribution of asperity heights, φ(z) = σ⁻¹ exp(-z/σ) (Gaul & Mayer eq. 3). Each asperity is a
// Hertzian sphere (eq. 1, 2). Closed forms of eq. (4) and (5):
//   A_R(g_N) = π r N ∫_{g_N}^∞ (z - g_N) φ(z) dz           = π r N σ exp(-g_N/σ)          (4)
//   F_N(g_N) = 4/3 N E* r^{1/2} ∫_{g_N}^∞ (z-g_N)^{3/2} φ dz = √π N E* r^{1/2} σ^{3/2} exp(-g_N/σ)
//   (5)
// so that F_N ∝ A_R (eq. 7) and F_N/A_0 is the exponential law of eq. (6) with λ = 1/σ.

#include <string>

#include "jointhb/contact/normal_law.hpp"

namespace jointhb::contact {

struct GreenwoodWilliamson {
  double asperity_count = 1.0e6;    ///< N [-], > 0: number of asperities (peaks) in the area A_0
  double asperity_radius = 1.0e-4;  ///< r [m], > 0: radius of curvature of an asperity summit
  double contact_modulus = 3.8e10;  ///< E* [Pa], > 0: Hertzian contact modulus
  double roughness = 1.0e-6;        ///< σ [m], > 0: standard deviation of the height profile
  double apparent_area = 1.0e-4;    ///< A_0 [m²], > 0: apparent (nominal) contact area

  [[nodiscard]] std::string validate() const;

  /// A_R(g_N), eq. (4), closed form [m²].
  [[nodiscard]] double real_area(double gap) const;
  /// F_N(g_N), eq. (5), closed form [N].
  [[nodiscard]] double normal_force(double gap) const;
  /// The integrands of eq. (4) and (5) at height z (for checks by quadrature).
  [[nodiscard]] double real_area_integrand(double z, double gap) const;
  [[nodiscard]] double normal_force_integrand(double z, double gap) const;
  /// The equivalent exponential pressure law of eq. (6): p_N = F_N/A_0, with g_N0 = 0.
  [[nodiscard]] NormalLaw pressure_law() const;
};

}  // namespace jointhb::contact
