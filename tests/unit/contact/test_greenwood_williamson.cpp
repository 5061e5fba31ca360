// Greenwood–Williamson closed forms, eq. (4) and (5), against an independent numerical quadrature
// of the integrals, and the exponential pressure law they imply (eq. 6, 7).

#include "jointhb/contact/greenwood_williamson.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>

namespace jointhb::contact {
namespace {

struct Quadrature {
  double value = 0.0;
  double last_change = 0.0;  ///< |I_h - I_{2h}| of the final halving
  int levels = 0;
};

// exp-sinh quadrature of ∫_0^∞ f(u) du: u = s exp(π/2 sinh t), trapezoidal rule in t. The
// double-exponential decay of the transformed integrand at both ends makes the rule converge
// geometrically in 1/h even with the u^{3/2} branch point at u = 0 (eq. 5). The step is halved
// until two successive estimates agree to `tolerance` (relative).
Quadrature exp_sinh(const std::function<double(double)>& f, double scale, double tolerance) {
  constexpr double kHalfPi = std::numbers::pi / 2.0;
  constexpr double kRange = 4.5;  // t ∈ [-4.5, 4.5]: u from s e^{-70} to s e^{+71}
  auto term = [&](double t) {
    const double u = scale * std::exp(kHalfPi * std::sinh(t));
    const double w = u * kHalfPi * std::cosh(t);
    const double value = f(u) * w;
    return std::isfinite(value) ? value : 0.0;  // far tail: 0·inf from e^{-u/σ} underflow
  };
  double h = 0.5;
  double sum = term(0.0);
  for (double t = h; t <= kRange; t += h) {
    sum += term(t) + term(-t);
  }
  Quadrature q;
  q.value = h * sum;
  for (int level = 1; level <= 12; ++level) {
    // Halving adds the midpoints of the previous grid.
    double mid = 0.0;
    for (double t = h / 2.0; t <= kRange; t += h) {
      mid += term(t) + term(-t);
    }
    sum += mid;
    h /= 2.0;
    const double next = h * sum;
    q.last_change = std::abs(next - q.value);
    q.value = next;
    q.levels = level;
    if (q.last_change <= tolerance * std::abs(next)) {
      break;
    }
  }
  return q;
}

GreenwoodWilliamson sample_surface() {
  GreenwoodWilliamson gw;
  gw.asperity_count = 2.5e5;
  gw.asperity_radius = 5.0e-5;
  gw.contact_modulus = 1.15e11;
  gw.roughness = 0.8e-6;
  gw.apparent_area = 4.0e-4;
  return gw;
}

// Gaps in units of σ, from deep closure (negative gap: the plane sits below the mean plane) to
// nearly open.
const double kGapsOverSigma[] = {-6.0, -2.5, -1.0, -0.1, 0.0, 0.3, 1.0, 4.0, 12.0};

TEST(GreenwoodWilliamson, RealAreaMatchesQuadratureOfEq4) {
  const GreenwoodWilliamson gw = sample_surface();
  for (const double s : kGapsOverSigma) {
    const double gap = s * gw.roughness;
    const Quadrature q = exp_sinh([&](double u) { return gw.real_area_integrand(gap + u, gap); },
                                  gw.roughness, 1e-15);
    const double closed = gw.real_area(gap);
    EXPECT_NEAR(q.value / closed, 1.0, 2e-14)
        << "gap = " << s << " σ: quadrature " << q.value << " (levels " << q.levels
        << ", last change " << q.last_change << ") vs closed form " << closed;
  }
}

TEST(GreenwoodWilliamson, NormalForceMatchesQuadratureOfEq5) {
  const GreenwoodWilliamson gw = sample_surface();
  for (const double s : kGapsOverSigma) {
    const double gap = s * gw.roughness;
    const Quadrature q = exp_sinh([&](double u) { return gw.normal_force_integrand(gap + u, gap); },
                                  gw.roughness, 1e-15);
    const double closed = gw.normal_force(gap);
    EXPECT_NEAR(q.value / closed, 1.0, 2e-14)
        << "gap = " << s << " σ: quadrature " << q.value << " (levels " << q.levels
        << ", last change " << q.last_change << ") vs closed form " << closed;
  }
}

TEST(GreenwoodWilliamson, QuadratureIsNotTrivialAndConverges) {
  // Guards the check itself: the rule must need several halvings and must detect a wrong
  // constant (the Γ(5/2) factor) by many orders of magnitude more than its tolerance.
  const GreenwoodWilliamson gw = sample_surface();
  const Quadrature q =
      exp_sinh([&](double u) { return gw.normal_force_integrand(u, 0.0); }, gw.roughness, 1e-15);
  EXPECT_GE(q.levels, 3);
  EXPECT_LT(q.last_change, 1e-14 * q.value);
  const double without_gamma = 4.0 / 3.0 * gw.asperity_count * gw.contact_modulus *
                               std::sqrt(gw.asperity_radius) * std::pow(gw.roughness, 1.5);
  EXPECT_GT(std::abs(q.value / without_gamma - 1.0), 0.1);
}

TEST(GreenwoodWilliamson, IntegrandsVanishBelowTheGap) {
  const GreenwoodWilliamson gw = sample_surface();
  const double gap = 0.5 * gw.roughness;
  EXPECT_EQ(gw.real_area_integrand(gap - 1e-9, gap), 0.0);
  EXPECT_EQ(gw.normal_force_integrand(gap - 1e-9, gap), 0.0);
  EXPECT_EQ(gw.real_area_integrand(gap, gap), 0.0);
  EXPECT_GT(gw.real_area_integrand(gap + gw.roughness, gap), 0.0);
  EXPECT_GT(gw.normal_force_integrand(gap + gw.roughness, gap), 0.0);
}

TEST(GreenwoodWilliamson, RealAreaProportionalToPressureEq7) {
  // eq. (7): A_R/A_0 ∝ p_N, and A_R(g)/A_R(0) = exp(-g/σ) = p_N(g)/p_N(0).
  const GreenwoodWilliamson gw = sample_surface();
  const NormalLaw law = gw.pressure_law();
  const double ratio0 = gw.real_area(0.0) / law.pressure(0.0);
  for (const double s : kGapsOverSigma) {
    const double gap = s * gw.roughness;
    EXPECT_NEAR(gw.real_area(gap) / law.pressure(gap) / ratio0, 1.0, 1e-13) << "gap " << s << " σ";
    EXPECT_NEAR(gw.real_area(gap) / gw.real_area(0.0) / std::exp(-s), 1.0, 1e-13)
        << "gap " << s << " σ";
  }
}

TEST(GreenwoodWilliamson, PressureLawIsForceOverApparentArea) {
  // eq. (6): p_N = F_N/A_0 with λ = 1/σ, g_N0 = 0.
  const GreenwoodWilliamson gw = sample_surface();
  const NormalLaw law = gw.pressure_law();
  EXPECT_EQ(law.validate(), "");
  EXPECT_DOUBLE_EQ(law.decay, 1.0 / gw.roughness);
  EXPECT_EQ(law.reference_gap, 0.0);
  EXPECT_DOUBLE_EQ(law.reference_pressure, gw.normal_force(0.0) / gw.apparent_area);
  for (const double s : kGapsOverSigma) {
    const double gap = s * gw.roughness;
    EXPECT_NEAR(law.pressure(gap) / (gw.normal_force(gap) / gw.apparent_area), 1.0, 1e-13)
        << "gap " << s << " σ";
  }
}

TEST(GreenwoodWilliamson, ClosedFormOfEq5ByHand) {
  // √π N E* r^{1/2} σ^{3/2} at g_N = 0, evaluated independently for round numbers.
  GreenwoodWilliamson gw;
  gw.asperity_count = 1.0;
  gw.asperity_radius = 4.0;
  gw.contact_modulus = 1.0;
  gw.roughness = 1.0;
  gw.apparent_area = 1.0;
  EXPECT_NEAR(gw.normal_force(0.0), 2.0 * std::sqrt(std::numbers::pi), 1e-15);
  EXPECT_NEAR(gw.real_area(0.0), 4.0 * std::numbers::pi, 1e-14);
  EXPECT_NEAR(gw.normal_force(1.0), 2.0 * std::sqrt(std::numbers::pi) / std::numbers::e, 1e-15);
}

TEST(GreenwoodWilliamson, ValidateNamesTheField) {
  EXPECT_EQ(sample_surface().validate(), "");
  const double bad_values[] = {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                               std::numeric_limits<double>::infinity()};
  struct Field {
    const char* name;
    double GreenwoodWilliamson::*member;
  };
  const Field fields[] = {{"asperity_count", &GreenwoodWilliamson::asperity_count},
                          {"asperity_radius", &GreenwoodWilliamson::asperity_radius},
                          {"contact_modulus", &GreenwoodWilliamson::contact_modulus},
                          {"roughness", &GreenwoodWilliamson::roughness},
                          {"apparent_area", &GreenwoodWilliamson::apparent_area}};
  for (const Field& field : fields) {
    for (const double bad : bad_values) {
      GreenwoodWilliamson gw = sample_surface();
      gw.*field.member = bad;
      const std::string message = gw.validate();
      EXPECT_NE(message.find(field.name), std::string::npos)
          << field.name << " = " << bad << " gave \"" << message << "\"";
      EXPECT_NE(message.find("> 0"), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace jointhb::contact
