#include "jointhb/io/value_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace jointhb::io {
namespace {

TEST(io_ValueChecks, ParsesNumbersAndTheYamlSpecialValues) {
  EXPECT_EQ(parse_number("0.3"), 0.3);
  EXPECT_EQ(parse_number("-1e-6"), -1e-6);
  EXPECT_TRUE(std::isnan(*parse_number("nan")));
  EXPECT_TRUE(std::isnan(*parse_number(".nan")));
  EXPECT_EQ(parse_number(".inf"), std::numeric_limits<double>::infinity());
  EXPECT_EQ(parse_number("-.inf"), -std::numeric_limits<double>::infinity());
  EXPECT_FALSE(parse_number(""));
  EXPECT_FALSE(parse_number("0.3x"));
  EXPECT_FALSE(parse_number(" 0.3"));
  EXPECT_FALSE(parse_number("abc"));
}

TEST(io_ValueChecks, ParsesOnlyWholeIntegers) {
  EXPECT_EQ(parse_integer("41"), 41);
  EXPECT_EQ(parse_integer("-3"), -3);
  EXPECT_FALSE(parse_integer("41.0"));
  EXPECT_FALSE(parse_integer("4e1"));
  EXPECT_FALSE(parse_integer("99999999999999999999999"));
}

TEST(io_ValueChecks, ConstraintsNameTheValue) {
  EXPECT_EQ(check_positive(-1.0), "must be > 0, got -1");
  EXPECT_EQ(check_positive(0.0), "must be > 0, got 0");
  EXPECT_EQ(check_positive(std::nan("")), "must be finite, got not-a-number");
  EXPECT_EQ(check_non_negative(-0.5), "must be >= 0, got -0.5");
  EXPECT_EQ(check_open_unit(1.5), "must be in (0, 1), got 1.5");
  EXPECT_EQ(check_open_unit(1.0), "must be in (0, 1), got 1");
  EXPECT_EQ(check_in_range(2, 4, 10), "must be in [4, 10], got 2");
  EXPECT_EQ(check_one_of("foo", {"gaul-mayer", "jenkins"}),
            "must be one of gaul-mayer, jenkins, got 'foo'");
  EXPECT_TRUE(check_positive(1e-300).empty());
  EXPECT_TRUE(check_open_unit(1.0 / 3.0).empty());
  EXPECT_TRUE(check_one_of("jenkins", {"gaul-mayer", "jenkins"}).empty());
}

TEST(io_ValueChecks, FormatNumberRoundTrips) {
  for (double v : {0.1, 1.0 / 3.0, 1e-300, -2.5e17, 4.9e-324}) {
    EXPECT_EQ(*parse_number(format_number(v)), v);
  }
}

}  // namespace
}  // namespace jointhb::io
