#include "jointhb/fit/parameters.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace jointhb::fit {
namespace {

TEST(FitParameters, UnitBoxRoundTripLinearAndLog) {
  const FitParameter linear{"a", -2.0, 3.0, 0.5, false};
  const FitParameter log{"b", 1e2, 1e6, 1e4, true};
  for (double u : {0.0, 1e-9, 0.25, 0.5, 0.731, 1.0}) {
    EXPECT_NEAR(linear.to_unit(linear.from_unit(u)), u, 1e-15);
    EXPECT_NEAR(log.to_unit(log.from_unit(u)), u, 1e-14);
  }
  EXPECT_DOUBLE_EQ(log.from_unit(0.5), 1e4);  // the geometric middle
  EXPECT_EQ(log.from_unit(0.0), 1e2);         // bounds exactly
  EXPECT_EQ(log.from_unit(1.0), 1e6);
  EXPECT_DOUBLE_EQ(linear.from_unit(0.5), 0.5);
  for (double v : {-2.0, -1.0, 0.0, 2.9})
    EXPECT_NEAR(linear.from_unit(linear.to_unit(v)), v, 1e-14);
  // dθ/du by central differences.
  for (const auto& p : {linear, log}) {
    const double u = 0.3, h = 1e-6;
    EXPECT_NEAR(p.derivative(u), (p.from_unit(u + h) - p.from_unit(u - h)) / (2 * h),
                1e-6 * std::abs(p.derivative(u)));
  }
}

TEST(FitParameters, ValidateNamesFieldAndValue) {
  EXPECT_EQ(FitParameter({"a", 0.0, 1.0, 0.5, false}).validate(), "");
  EXPECT_EQ(FitParameter({"a", 1.0, 1.0, 1.0, false}).validate(),
            "a.upper: must be > lower = 1, got 1");
  EXPECT_EQ(FitParameter({"a", 0.0, 1.0, 0.5, true}).validate(),
            "a.lower: must be > 0 with log_scale, got 0");
  EXPECT_EQ(FitParameter({"a", 0.0, 1.0, 2.0, false}).validate(),
            "a.start: must be in [lower, upper] = [0, 1], got 2");
  EXPECT_EQ(validate({{"a", 0.0, 1.0, 0.5, false}, {"a", 0.0, 1.0, 0.5, false}}),
            "a: is listed twice");
}

}  // namespace
}  // namespace jointhb::fit
