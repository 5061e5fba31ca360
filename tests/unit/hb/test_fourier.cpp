// Fourier conventions (hb/fourier.hpp): round trip, Parseval, explicit sample values, batching.
#include "jointhb/hb/fourier.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

namespace jointhb::hb {
namespace {

Eigen::MatrixXd random_matrix(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd a(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) a(i, j) = u(gen);
  return a;
}

TEST(FourierBasis, OrderingAndSize) {
  const FourierBasis full(3, 16);
  EXPECT_EQ(full.size(), 7);
  EXPECT_EQ(full.cosine_index(1), 1);
  EXPECT_EQ(full.cosine_index(3), 5);
  EXPECT_EQ(full.cosine_index(4), -1);
  const FourierBasis odd(5, 16, true);
  EXPECT_EQ(odd.size(), 6);  // a1 b1 a3 b3 a5 b5
  EXPECT_EQ(odd.cosine_index(1), 0);
  EXPECT_EQ(odd.cosine_index(3), 2);
  EXPECT_EQ(odd.cosine_index(2), -1);
  EXPECT_EQ(odd.orders(), (std::vector<int>{1, 3, 5}));
}

TEST(FourierBasis, SampleValuesFollowTheConvention) {
  // x(t) = 0.5 + 2 cos Ωt − 3 sin 2Ωt at t_i = iT/N.
  const FourierBasis b(2, 8);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(b.size());
  c[0] = 0.5;
  c[b.cosine_index(1)] = 2.0;
  c[b.cosine_index(2) + 1] = -3.0;
  const Eigen::MatrixXd x = b.to_time(c);
  for (int i = 0; i < 8; ++i) {
    const double th = 2.0 * std::numbers::pi * i / 8.0;
    EXPECT_NEAR(x(i, 0), 0.5 + 2.0 * std::cos(th) - 3.0 * std::sin(2.0 * th), 1e-14) << i;
  }
}

TEST(FourierBasis, RoundTripIsIdentityForFullAndOddBases) {
  for (bool odd : {false, true}) {
    for (int h : {1, 4, 15}) {
      for (int n : {2 * h + 2, 4 * h + 1, 128}) {
        const FourierBasis b(h, n, odd);
        const Eigen::MatrixXd c = random_matrix(b.size(), 5, static_cast<unsigned>(h * n));
        const Eigen::MatrixXd back = b.to_frequency(b.to_time(c));
        EXPECT_LT((back - c).cwiseAbs().maxCoeff(), 1e-14) << "H " << h << " N " << n;
      }
    }
  }
}

TEST(FourierBasis, ForwardTransformLeavesItsInputUnchanged) {
  const FourierBasis b(5, 32);
  const Eigen::MatrixXd x = random_matrix(32, 4, 11);
  const Eigen::MatrixXd copy = x;
  (void)b.to_frequency(x);
  EXPECT_EQ(x, copy);
}

TEST(FourierBasis, ParsevalHolds) {
  const FourierBasis b(7, 64);
  const Eigen::MatrixXd c = random_matrix(b.size(), 3, 7);
  const Eigen::MatrixXd x = b.to_time(c);
  for (Eigen::Index j = 0; j < 3; ++j) {
    double spectral = c(0, j) * c(0, j);
    for (int k : b.orders()) {
      const int a = b.cosine_index(k);
      spectral += 0.5 * (c(a, j) * c(a, j) + c(a + 1, j) * c(a + 1, j));
    }
    EXPECT_NEAR(x.col(j).squaredNorm() / 64.0, spectral, 1e-14 * spectral);
  }
}

TEST(FourierBasis, MatricesMatchTheTransforms) {
  const FourierBasis b(5, 32);
  const Eigen::MatrixXd e = b.synthesis_matrix();
  const Eigen::MatrixXd a = b.analysis_matrix();
  const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(b.size(), b.size());
  EXPECT_LT((a * e - id).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((b.to_time(id) - e).cwiseAbs().maxCoeff(), 1e-14);
  const Eigen::MatrixXd x = random_matrix(32, 4, 3);
  EXPECT_LT((b.to_frequency(x) - a * x).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(FourierBasis, HigherHarmonicsAreDroppedNotAliased) {
  // A sample signal with harmonic H+1 projects to zero on the kept harmonics when N ≥ 2H+2... as
  // long as H+1 < N − H (no fold-back onto 1..H).
  const FourierBasis b(3, 16);
  Eigen::VectorXd x(16);
  for (int i = 0; i < 16; ++i) x[i] = std::cos(2.0 * std::numbers::pi * 4 * i / 16.0);
  EXPECT_LT(b.to_frequency(x).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(FourierBasis, PeakMagnitudeIsExactBetweenSamples) {
  // x = cos(θ − 0.1234) + 0.2 cos(3θ): max |x| found by dense sampling of the closed form.
  const FourierBasis b(3, 8);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(b.size());
  c[b.cosine_index(1)] = std::cos(0.1234);
  c[b.cosine_index(1) + 1] = std::sin(0.1234);
  c[b.cosine_index(3)] = 0.2;
  double ref = 0.0;
  for (int i = 0; i < 2000000; ++i) {
    const double th = 2.0 * std::numbers::pi * i / 2000000.0;
    ref = std::max(ref, std::abs(std::cos(th - 0.1234) + 0.2 * std::cos(3.0 * th)));
  }
  EXPECT_NEAR(b.peak_magnitude(c), ref, 1e-11);
  EXPECT_GE(b.peak_magnitude(c), ref - 1e-15);  // the refined maximum is not below any sample
}

TEST(FourierBasis, RejectsTooFewSamples) {
  EXPECT_THROW(FourierBasis(3, 7), std::invalid_argument);
  EXPECT_THROW(FourierBasis(0, 16), std::invalid_argument);
  EXPECT_NO_THROW(FourierBasis(3, 8));
}

TEST(FourierBasis, CopiesShareNothingObservable) {
  FourierBasis a(2, 8);
  const FourierBasis b = a;
  a = FourierBasis(4, 16);
  const Eigen::MatrixXd c = random_matrix(b.size(), 1, 1);
  EXPECT_LT((b.to_frequency(b.to_time(c)) - c).cwiseAbs().maxCoeff(), 1e-14);
}

}  // namespace
}  // namespace jointhb::hb
