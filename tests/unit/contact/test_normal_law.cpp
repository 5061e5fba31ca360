// The exponential normal law, eq. (6): values, stiffness k_N = λ p_N = -dp_N/dg_N, inverse,
// overflow guard and option validation.

#include "jointhb/contact/normal_law.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace jointhb::contact {
namespace {

NormalLaw sample_law() {
  NormalLaw law;
  law.reference_pressure = 3.0e6;
  law.decay = 2.0e5;
  law.reference_gap = 1.5e-6;
  return law;
}

TEST(NormalLaw, PressureFollowsEq6) {
  const NormalLaw law = sample_law();
  EXPECT_EQ(law.validate(), "");
  EXPECT_DOUBLE_EQ(law.pressure(law.reference_gap), law.reference_pressure);
  // One σ = 1/λ of opening divides the pressure by e, one σ of closure multiplies it by e.
  const double sigma = 1.0 / law.decay;
  EXPECT_NEAR(law.pressure(law.reference_gap + sigma) * std::exp(1.0) / law.reference_pressure, 1.0,
              1e-14);
  EXPECT_NEAR(
      law.pressure(law.reference_gap - 3.0 * sigma) / std::exp(3.0) / law.reference_pressure, 1.0,
      1e-14);
  for (double gap = -2e-5; gap <= 4e-5; gap += 1.7e-6) {
    const double expected =
        law.reference_pressure * std::exp(-law.decay * (gap - law.reference_gap));
    EXPECT_NEAR(law.pressure(gap) / expected, 1.0, 1e-14) << "gap " << gap;
  }
}

TEST(NormalLaw, StiffnessIsMinusSlopeByCentralDifferences) {
  // k_N = -dp_N/dg_N. Central differences with h = 1e-3/λ: truncation (λh)²/6 ≈ 2e-7, round-off
  // ≈ ε/(λh) ≈ 1e-13, so 1e-6 separates a correct slope from any wrong factor or sign.
  const NormalLaw law = sample_law();
  const double h = 1e-3 / law.decay;
  for (double gap = -2e-5; gap <= 4e-5; gap += 3.1e-6) {
    const double slope = (law.pressure(gap + h) - law.pressure(gap - h)) / (2.0 * h);
    EXPECT_GT(law.stiffness(gap), 0.0);
    EXPECT_NEAR(law.stiffness(gap) / -slope, 1.0, 1e-6) << "gap " << gap;
    EXPECT_NEAR(law.stiffness(gap) / (law.decay * law.pressure(gap)), 1.0, 1e-15);
  }
}

TEST(NormalLaw, GapAtPressureInvertsTheLaw) {
  const NormalLaw law = sample_law();
  for (double gap = -3e-5; gap <= 6e-5; gap += 2.3e-6) {
    EXPECT_NEAR(law.gap_at_pressure(law.pressure(gap)), gap, 1e-15 * (1.0 + 1e6 * std::abs(gap)))
        << "gap " << gap;
  }
  EXPECT_DOUBLE_EQ(law.gap_at_pressure(law.reference_pressure), law.reference_gap);
  // Pressures far below p_N0 (p_N0/p overflows) still invert.
  const double tiny = 1e-300;
  EXPECT_NEAR(law.gap_at_pressure(tiny),
              law.reference_gap + (std::log(law.reference_pressure) - std::log(tiny)) / law.decay,
              1e-15);
  EXPECT_THROW((void)law.gap_at_pressure(0.0), std::invalid_argument);
  EXPECT_THROW((void)law.gap_at_pressure(-1.0), std::invalid_argument);
  EXPECT_THROW((void)law.gap_at_pressure(std::numeric_limits<double>::quiet_NaN()),
               std::invalid_argument);
}

TEST(NormalLaw, DeepClosureStaysFinite) {
  // g = -1 m is 2e5 σ of closure: exp(2e5) overflows unless the exponent is capped.
  const NormalLaw law = sample_law();
  for (const double gap : {-1.0, -1e-2, -1e3, -std::numeric_limits<double>::max()}) {
    EXPECT_TRUE(std::isfinite(law.pressure(gap))) << "gap " << gap;
    EXPECT_TRUE(std::isfinite(law.stiffness(gap))) << "gap " << gap;
    EXPECT_GT(law.pressure(gap), 1e100) << "gap " << gap;
  }
  // The cap keeps the law monotone (non-increasing in the gap).
  EXPECT_GE(law.pressure(-1.0), law.pressure(-1e-3));
  EXPECT_GE(law.pressure(-1e-3), law.pressure(0.0));
  // A huge reference pressure with a large decay: p_N0 exp(700) and λ p_N would both overflow.
  NormalLaw stiff = law;
  stiff.reference_pressure = 1e20;
  stiff.decay = 1e9;
  EXPECT_TRUE(std::isfinite(stiff.pressure(-1.0)));
  EXPECT_TRUE(std::isfinite(stiff.stiffness(-1.0)));
  // Far open: the pressure underflows gracefully to (nearly) zero, never negative.
  EXPECT_GE(law.pressure(1.0), 0.0);
  EXPECT_LT(law.pressure(1.0), 1e-300);
}

TEST(NormalLaw, ValidateNamesTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double bad : {0.0, -1.0, nan, inf}) {
    NormalLaw law = sample_law();
    law.reference_pressure = bad;
    EXPECT_NE(law.validate().find("reference_pressure"), std::string::npos) << law.validate();
    law = sample_law();
    law.decay = bad;
    EXPECT_NE(law.validate().find("decay"), std::string::npos) << law.validate();
  }
  for (const double bad : {nan, inf, -inf}) {
    NormalLaw law = sample_law();
    law.reference_gap = bad;
    EXPECT_NE(law.validate().find("reference_gap"), std::string::npos) << law.validate();
  }
  NormalLaw law = sample_law();
  law.reference_gap = -2e-6;  // any finite reference gap is valid
  EXPECT_EQ(law.validate(), "");
  law.decay = -1.0;
  const std::string message = law.validate();
  EXPECT_NE(message.find("> 0"), std::string::npos) << message;
  EXPECT_NE(message.find("-1"), std::string::npos) << message;
}

}  // namespace
}  // namespace jointhb::contact
