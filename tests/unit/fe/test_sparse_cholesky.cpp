// SparseCholesky (CHOLMOD) against Eigen's SimplicialLDLT and dense eigenvalues.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "jointhb/fe/sparse_cholesky.hpp"

namespace {

using jointhb::fe::SparseCholesky;
using SpMat = Eigen::SparseMatrix<double>;
using Method = jointhb::fe::SparseCholeskyOptions::Method;
using Triangle = jointhb::fe::SparseCholeskyOptions::Triangle;

// 7-point Laplacian of an nx × ny × nz grid (Dirichlet outside) plus `diagonal_shift`·I, with
// the off-diagonal couplings perturbed randomly (symmetrically) by up to ±20 % so the test does not
// rest on a structured matrix. Stored in full.
SpMat laplacian_3d(int nx, int ny, int nz, double diagonal_shift = 0.0, unsigned seed = 7) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> factor(0.8, 1.2);
  const int n = nx * ny * nz;
  auto index = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd diagonal = Eigen::VectorXd::Constant(n, diagonal_shift);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int a = index(i, j, k);
        diagonal(a) += 6.0;
        const int neighbours[3][3] = {{i + 1, j, k}, {i, j + 1, k}, {i, j, k + 1}};
        for (const auto& nb : neighbours) {
          if (nb[0] >= nx || nb[1] >= ny || nb[2] >= nz) continue;
          const int b = index(nb[0], nb[1], nb[2]);
          const double w = -factor(random);
          entries.emplace_back(a, b, w);
          entries.emplace_back(b, a, w);
        }
      }
  for (int a = 0; a < n; ++a) entries.emplace_back(a, a, diagonal(a));
  SpMat A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

Eigen::MatrixXd random_block(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd B(rows, cols);
  for (Eigen::Index k = 0; k < B.size(); ++k) B.data()[k] = value(random);
  return B;
}

TEST(SparseCholesky, SolvesLikeEigenSimplicialLdltOnA3dLaplacian) {
  const SpMat A = laplacian_3d(12, 10, 9);  // n = 1080
  const Eigen::MatrixXd B = random_block(A.rows(), 6, 3);
  Eigen::SimplicialLDLT<SpMat> reference(A);
  ASSERT_EQ(reference.info(), Eigen::Success);
  const Eigen::MatrixXd expected = reference.solve(B);

  SparseCholesky cholesky;
  cholesky.compute(SpMat(A.triangularView<Eigen::Lower>()));
  const Eigen::MatrixXd X = cholesky.solve(B);
  EXPECT_LT((X - expected).norm() / expected.norm(), 1e-13);
  EXPECT_LT((A * X - B).norm() / B.norm(), 1e-13);
  const Eigen::VectorXd x0 = cholesky.solve(Eigen::VectorXd(B.col(0)));
  EXPECT_LT((x0 - expected.col(0)).norm() / expected.col(0).norm(), 1e-13);

  const auto& s = cholesky.statistics();
  EXPECT_EQ(s.rows, A.rows());
  EXPECT_EQ(s.matrix_nonzeros, (A.nonZeros() + A.rows()) / 2);
  EXPECT_GE(s.factor_nonzeros, static_cast<double>(s.matrix_nonzeros));
  EXPECT_GE(static_cast<double>(s.factor_entries), s.factor_nonzeros);
  EXPECT_GT(s.factor_flops, 0.0);
  EXPECT_FALSE(s.ordering.empty());
  EXPECT_EQ(s.factorizations, 1);
  std::printf("  %s\n", s.brief().c_str());
}

TEST(SparseCholesky, ReadsOnlyTheChosenTriangle) {
  const SpMat A = laplacian_3d(6, 5, 4);
  const Eigen::VectorXd b = random_block(A.rows(), 1, 5).col(0);
  const Eigen::VectorXd expected = Eigen::SimplicialLDLT<SpMat>(A).solve(b);

  // Garbage in the ignored triangle must not matter.
  SpMat lower_plus_garbage = A;
  for (int j = 0; j < A.outerSize(); ++j)
    for (SpMat::InnerIterator it(lower_plus_garbage, j); it; ++it)
      if (it.row() < it.col()) it.valueRef() = 1e6;
  SparseCholesky lower;
  lower.compute(lower_plus_garbage);
  EXPECT_LT((lower.solve(b) - expected).norm() / expected.norm(), 1e-13);

  SparseCholesky upper({Triangle::upper, Method::supernodal_llt});
  upper.compute(SpMat(A.triangularView<Eigen::Upper>()));
  EXPECT_LT((upper.solve(b) - expected).norm() / expected.norm(), 1e-13);
}

TEST(SparseCholesky, AnalyzeOnceFactorizeManyLikeANewtonLoop) {
  const SpMat A = laplacian_3d(8, 8, 8);
  SparseCholesky cholesky;
  cholesky.analyze(A);
  const Eigen::VectorXd b = random_block(A.rows(), 1, 9).col(0);
  for (int iteration = 0; iteration < 3; ++iteration) {
    SpMat Ai = A;
    Ai.coeffs() *= 1.0 + 0.5 * iteration;  // new values, same pattern
    Ai.diagonal().array() += iteration;
    cholesky.factorize(Ai);
    const Eigen::VectorXd x = cholesky.solve(b);
    EXPECT_LT((Ai * x - b).norm() / b.norm(), 1e-13) << "iteration " << iteration;
  }
  EXPECT_EQ(cholesky.statistics().factorizations, 3);

  SpMat other = laplacian_3d(8, 8, 8);
  other.coeffRef(0, 100) = 0.1;  // an entry outside the analysed pattern
  EXPECT_THROW(cholesky.factorize(other), std::invalid_argument);
}

TEST(SparseCholesky, ReportsTheColumnWhereTheMatrixIsNotPositiveDefinite) {
  // A positive diagonal except for column 17: whatever the elimination order, the failing pivot
  // is column 17's, and the message must name it in A's own numbering (not the permuted one).
  const int n = 40;
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) entries.emplace_back(i, i, i == 17 ? -100.0 : 4.0);
  SpMat A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  SparseCholesky cholesky;
  try {
    cholesky.compute(A);
    FAIL() << "no exception for an indefinite matrix";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("not positive definite"), std::string::npos) << message;
    EXPECT_NE(message.find("at column 17 "), std::string::npos) << message;
    EXPECT_NE(message.find("CHOLMOD_NOT_POSDEF"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_FALSE(cholesky.factorized());
  EXPECT_THROW((void)cholesky.solve(Eigen::VectorXd::Ones(n)), std::logic_error);

  // A shifted Laplacian with a negative shift beyond its smallest eigenvalue: also detected.
  const SpMat B = laplacian_3d(6, 6, 6, -4.0);
  SparseCholesky second;
  EXPECT_THROW(second.compute(B), std::runtime_error);
}

TEST(SparseCholesky, RepeatedFactorizationsAgreeBitForBit) {
  const SpMat A = laplacian_3d(10, 9, 8);
  const Eigen::MatrixXd B = random_block(A.rows(), 3, 11);
  SparseCholesky first, second;
  first.compute(A);
  second.compute(A);
  const Eigen::MatrixXd x1 = first.solve(B);
  const Eigen::MatrixXd x2 = second.solve(B);
  EXPECT_EQ((x1 - x2).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SparseCholesky, LdltFactorsAnIndefiniteShiftAndCountsTheEigenvaluesBelowIt) {
  // A − σI with σ between eigenvalues: LDLᵀ solves it and its inertia counts the eigenvalues of
  // A below σ (Sylvester), the Sturm check for shift-invert.
  const SpMat A = laplacian_3d(5, 4, 3);  // n = 60
  const Eigen::VectorXd eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(A)).eigenvalues();
  const double sigma = 0.5 * (eigenvalues(9) + eigenvalues(10));  // 10 eigenvalues below σ
  SpMat shifted = A;
  shifted.diagonal().array() -= sigma;
  SparseCholesky ldlt({Triangle::lower, Method::simplicial_ldlt});
  ldlt.compute(shifted);
  EXPECT_EQ(ldlt.negative_pivots(), 10);
  const Eigen::VectorXd b = random_block(A.rows(), 1, 13).col(0);
  const Eigen::VectorXd expected = Eigen::MatrixXd(shifted).lu().solve(b);
  EXPECT_LT((ldlt.solve(b) - expected).norm() / expected.norm(), 1e-10);

  SparseCholesky llt;
  EXPECT_EQ(llt.negative_pivots(), -1);
  EXPECT_THROW(llt.compute(shifted), std::runtime_error);
}

TEST(SparseCholesky, RejectsBadSizes) {
  SparseCholesky cholesky;
  EXPECT_THROW(cholesky.analyze(SpMat(3, 4)), std::invalid_argument);
  const SpMat A = laplacian_3d(3, 3, 3);
  cholesky.compute(A);
  EXPECT_THROW((void)cholesky.solve(Eigen::VectorXd::Ones(5)), std::invalid_argument);
  EXPECT_EQ(cholesky.solve(Eigen::MatrixXd(27, 0)).cols(), 0);
}

}  // namespace
