// LapackLu::determinant_sign (support/lapack_lu.hpp): the sign of det A from the LAPACK factors,
// against Eigen's own LU (an independent factorisation) on random matrices small enough for the
// determinant not to overflow, and against constructions whose sign is known: a permutation
// matrix times a positive diagonal (sign = the permutation's), a row swap (sign flips), a
// matrix of 400 unknowns whose determinant underflows a double, and an exactly singular one.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "../../../src/support/lapack_lu.hpp"

namespace jointhb::support {
namespace {

Eigen::MatrixXd random_matrix(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  Eigen::MatrixXd a(n, n);
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < n; ++i) a(i, j) = nd(rng);
  return a;
}

TEST(LapackLu, DeterminantSignAgreesWithEigen) {
  int negative = 0;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    const Eigen::MatrixXd a = random_matrix(1 + seed % 9, seed);
    const double det = a.partialPivLu().determinant();
    ASSERT_NE(det, 0.0);
    EXPECT_EQ(LapackLu(a).determinant_sign(), det > 0.0 ? 1 : -1) << "seed " << seed;
    negative += det < 0.0;
  }
  EXPECT_GT(negative, 5);  // both signs were exercised
  EXPECT_LT(negative, 35);
}

TEST(LapackLu, DeterminantSignOfKnownConstructions) {
  const Eigen::Index n = 400;
  // 0.01 I: det = 1e-800 underflows, sign +1; one diagonal entry negated: −1.
  Eigen::MatrixXd d = 0.01 * Eigen::MatrixXd::Identity(n, n);
  EXPECT_EQ(d.partialPivLu().determinant(), 0.0);  // what the product would say
  EXPECT_EQ(LapackLu(d).determinant_sign(), 1);
  d(7, 7) = -0.01;
  EXPECT_EQ(LapackLu(d).determinant_sign(), -1);
  // A cyclic shift of 400 rows (399 transpositions, odd) times 3 I: det = −3⁴⁰⁰.
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) p(i, (i + 1) % n) = 3.0;
  EXPECT_EQ(LapackLu(p).determinant_sign(), -1);
  // Swapping two rows of a random matrix flips the sign.
  Eigen::MatrixXd a = random_matrix(60, 99);
  const int s = LapackLu(a).determinant_sign();
  ASSERT_NE(s, 0);
  a.row(3).swap(a.row(41));
  EXPECT_EQ(LapackLu(a).determinant_sign(), -s);
  // Exactly singular: a zero column.
  a.col(5).setZero();
  EXPECT_EQ(LapackLu(a).determinant_sign(), 0);
}

}  // namespace
}  // namespace jointhb::support
