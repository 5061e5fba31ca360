// The designs of a parameter study (study/sampling.hpp): their order, their strata, and the Sobol
// points against the sequence's defining properties.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "jointhb/study/sampling.hpp"

namespace jointhb::study {
namespace {

StudyParameter values_of(std::string name, std::vector<double> values) {
  StudyParameter p;
  p.name = std::move(name);
  p.values = std::move(values);
  return p;
}

StudyParameter range_of(std::string name, double lower, double upper, bool log_scale = false) {
  StudyParameter p;
  p.name = std::move(name);
  p.lower = lower;
  p.upper = upper;
  p.log_scale = log_scale;
  return p;
}

TEST(StudySampling, ListTakesTheIthValueOfEveryParameter) {
  Sampling s;
  s.kind = SamplingKind::list;
  s.parameters = {values_of("a", {1, 2, 3}), values_of("b", {10, 20, 30})};
  const auto points = sample_points(s);
  ASSERT_EQ(points.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(points[i][0], static_cast<double>(i + 1));
    EXPECT_EQ(points[i][1], 10.0 * static_cast<double>(i + 1));
  }
  s.parameters[1].values.pop_back();
  EXPECT_NE(s.validate().find("as many values"), std::string::npos) << s.validate();
  EXPECT_THROW((void)sample_points(s), std::invalid_argument);
}

TEST(StudySampling, GridIsTheTensorProductWithTheFirstParameterSlowest) {
  Sampling s;
  s.kind = SamplingKind::grid;
  s.parameters = {values_of("a", {1, 2}), values_of("b", {10, 20, 30}), values_of("c", {-1, 1})};
  const auto points = sample_points(s);
  ASSERT_EQ(points.size(), 12u);
  EXPECT_EQ(s.count(), 12u);
  std::set<std::vector<double>> seen(points.begin(), points.end());
  EXPECT_EQ(seen.size(), 12u);  // every combination once
  std::size_t i = 0;
  for (double a : {1.0, 2.0}) {
    for (double b : {10.0, 20.0, 30.0}) {
      for (double c : {-1.0, 1.0}) {
        EXPECT_EQ(points[i], (std::vector<double>{a, b, c})) << "sample " << i;
        ++i;
      }
    }
  }
}

TEST(StudySampling, LatinHypercubeHasOnePointPerStratumInEveryCoordinate) {
  Sampling s;
  s.kind = SamplingKind::latin_hypercube;
  s.samples = 40;
  s.seed = 7;
  s.parameters = {range_of("lin", 2.0, 6.0), range_of("log", 1e-3, 1e3, true)};
  const auto points = sample_points(s);
  ASSERT_EQ(points.size(), 40u);
  for (int d = 0; d < 2; ++d) {
    std::vector<int> strata;
    for (const auto& p : points) {
      const double u = d == 0 ? (p[0] - 2.0) / 4.0 : (std::log10(p[1]) + 3.0) / 6.0;
      ASSERT_GE(u, 0.0);
      ASSERT_LE(u, 1.0);
      strata.push_back(std::min(39, static_cast<int>(std::floor(u * 40.0))));
    }
    std::sort(strata.begin(), strata.end());
    for (int k = 0; k < 40; ++k) EXPECT_EQ(strata[static_cast<std::size_t>(k)], k) << "coordinate " << d;
  }
  EXPECT_EQ(sample_points(s), points);  // deterministic for a seed
  s.seed = 8;
  EXPECT_NE(sample_points(s), points);
}

// Sobol's sequence: its first coordinate is van der Corput's base-2 sequence in Gray-code order
// (1/2, 3/4, 1/4, 3/8, 7/8, 5/8, 1/8, ...), and every 2^m consecutive points from the start form
// a (0, m, 1)-net in each coordinate: exactly one point in each interval [k 2^-m, (k+1) 2^-m).
TEST(StudySampling, SobolPointsAreStratifiedInEveryCoordinate) {
  const auto points = sobol_points(1023, 5);
  const double expected[] = {0.5, 0.75, 0.25, 0.375, 0.875, 0.625, 0.125};
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(points[i][0], expected[i]) << i;
  // With the zero point the sequence leaves out, the first 2^m − 1 points fill 2^m − 1 of the 2^m
  // intervals of width 2^-m, all but the first.
  for (int m = 1; m <= 10; ++m) {
    const std::size_t n = (std::size_t{1} << m) - 1;
    for (std::size_t d = 0; d < 5; ++d) {
      std::set<long> cells;
      for (std::size_t i = 0; i < n; ++i) cells.insert(static_cast<long>(std::floor(points[i][d] * static_cast<double>(n + 1))));
      EXPECT_EQ(cells.size(), n) << "m " << m << " coordinate " << d;
      EXPECT_EQ(cells.count(0), 0u) << "m " << m << " coordinate " << d;
    }
  }
  // Quasi-Monte Carlo: the mean of u1 u2 u3 over 1023 points is within 1e-3 of 1/8 (plain Monte
  // Carlo's standard error at this n is 3e-3).
  double sum = 0.0;
  for (const auto& p : points) sum += p[0] * p[1] * p[2];
  EXPECT_NEAR(sum / 1023.0, 0.125, 1e-3);
}

TEST(StudySampling, SobolDesignMapsTheUnitBoxToTheRanges) {
  Sampling s;
  s.kind = SamplingKind::sobol;
  s.samples = 3;
  s.parameters = {range_of("lin", 2.0, 6.0), range_of("log", 1e-2, 1e2, true)};
  const auto points = sample_points(s);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_DOUBLE_EQ(points[0][0], 4.0);  // u = 1/2
  EXPECT_NEAR(points[0][1], 1.0, 1e-14);
  EXPECT_DOUBLE_EQ(points[1][0], 5.0);  // u = 3/4
  EXPECT_NEAR(points[1][1], 0.1, 1e-14);  // u = 1/4 in the second coordinate
}

TEST(StudySampling, ValidationNamesTheField) {
  Sampling s;
  s.kind = SamplingKind::latin_hypercube;
  s.parameters = {range_of("a", 1.0, 2.0)};
  EXPECT_NE(s.validate().find("samples: must be >= 1"), std::string::npos) << s.validate();
  s.samples = 4;
  s.parameters.push_back(range_of("a", 1.0, 2.0));
  EXPECT_NE(s.validate().find("listed twice"), std::string::npos) << s.validate();
  s.parameters.pop_back();
  s.parameters[0].log_scale = true;
  s.parameters[0].lower = 0.0;
  EXPECT_FALSE(s.validate().empty());
  EXPECT_FALSE(sampling_kind("monte_carlo").has_value());
  EXPECT_EQ(sampling_kind("sobol"), SamplingKind::sobol);
}

}  // namespace
}  // namespace jointhb::study
