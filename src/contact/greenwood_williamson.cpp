// Greenwood–Williamson contact with an exponential height distribution (Gaul & Mayer eq. 3–7):
//   φ(z) = σ⁻¹ exp(-z/σ)                                                         (3)
//   A_R(g_N) = π r N ∫_{g_N}^∞ (z - g_N) φ(z) dz        = π r N σ exp(-g_N/σ)              (4)
//   F_N(g_N) = 4/3 N E* r^{1/2} ∫_{g_N}^∞ (z - g_N)^{3/2} φ(z) dz
//            = 4/3 N E* r^{1/2} Γ(5/2) σ^{3/2} exp(-g_N/σ) = √π N E* r^{1/2} σ^{3/2} exp(-g_N/σ)
//            (5)
// (substitute u = z - g_N: ∫_0^∞ u^k σ⁻¹ e^{-u/σ} du = Γ(k+1) σ^k, Γ(5/2) = 3√π/4).
// Both are proportional to exp(-g_N/σ), hence A_R ∝ F_N (eq. 7) and p_N = F_N/A_0 is eq. (6) with
// λ = 1/σ, g_N0 = 0, p_N0 = F_N(0)/A_0.
//
// The closed forms here are literal (they overflow to +inf for closures of some 700 σ); the law
// used in computations is pressure_law(), whose evaluation is capped (normal_law.cpp).

#include "jointhb/contact/greenwood_williamson.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

namespace jointhb::contact {

namespace {

std::string positive_finite(const char* field, double value, const char* meaning) {
  if (std::isfinite(value) && value > 0.0) {
    return {};
  }
  return fmt::format("{} = {} is invalid: must be finite and > 0 ({})", field, value, meaning);
}

}  // namespace

std::string GreenwoodWilliamson::validate() const {
  for (const auto& message :
       {positive_finite("asperity_count", asperity_count, "number of asperities N"),
        positive_finite("asperity_radius", asperity_radius, "summit radius r [m]"),
        positive_finite("contact_modulus", contact_modulus, "Hertzian modulus E* [Pa]"),
        positive_finite("roughness", roughness, "height standard deviation σ [m]"),
        positive_finite("apparent_area", apparent_area, "apparent area A_0 [m²]")}) {
    if (!message.empty()) {
      return message;
    }
  }
  return {};
}

double GreenwoodWilliamson::real_area(double gap) const {
  // eq. (4)
  return std::numbers::pi * asperity_radius * asperity_count * roughness *
         std::exp(-gap / roughness);
}

double GreenwoodWilliamson::normal_force(double gap) const {
  // eq. (5)
  return std::sqrt(std::numbers::pi) * asperity_count * contact_modulus *
         std::sqrt(asperity_radius) * roughness * std::sqrt(roughness) * std::exp(-gap / roughness);
}

double GreenwoodWilliamson::real_area_integrand(double z, double gap) const {
  // π r N (z - g_N) φ(z) on z > g_N: asperities taller than the gap touch the plane.
  if (!(z > gap)) {
    return 0.0;
  }
  const double phi = std::exp(-z / roughness) / roughness;
  return std::numbers::pi * asperity_radius * asperity_count * (z - gap) * phi;
}

double GreenwoodWilliamson::normal_force_integrand(double z, double gap) const {
  // 4/3 N E* r^{1/2} (z - g_N)^{3/2} φ(z) on z > g_N: the Hertz force of eq. (2) inverted,
  // F = 4/3 E* r^{1/2} α^{3/2}, with the approach α = z - g_N.
  if (!(z > gap)) {
    return 0.0;
  }
  const double approach = z - gap;
  const double phi = std::exp(-z / roughness) / roughness;
  return 4.0 / 3.0 * asperity_count * contact_modulus * std::sqrt(asperity_radius) * approach *
         std::sqrt(approach) * phi;
}

NormalLaw GreenwoodWilliamson::pressure_law() const {
  // eq. (6) with λ = 1/σ and g_N0 = 0.
  NormalLaw law;
  law.reference_pressure = normal_force(0.0) / apparent_area;
  law.decay = 1.0 / roughness;
  law.reference_gap = 0.0;
  return law;
}

}  // namespace jointhb::contact
