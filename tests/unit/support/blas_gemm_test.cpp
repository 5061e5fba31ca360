// The row-split products of the residual flexibility and inertia (support/blas_gemm.hpp): equal
// to one BLAS call to round-off, bit-identical for 1 and 2 threads and from call to call.
#include <gtest/gtest.h>
#include <omp.h>

#include <random>

#include "../../../src/support/blas_gemm.hpp"

namespace jointhb::support {
namespace {

template <class Matrix>
Matrix random_matrix(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  Matrix a(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) a(i, j) = static_cast<typename Matrix::Scalar>(nd(rng));
  return a;
}

template <class Matrix>
void check_row_split(double tolerance) {
  const Eigen::Index n = 1203;  // above the split threshold, not a multiple of the row blocks
  const Matrix a0 = random_matrix<Matrix>(n, n, 1), a1 = random_matrix<Matrix>(n, n, 2);
  const Matrix b = random_matrix<Matrix>(n, 7, 3);
  const int saved = omp_get_max_threads();
  Matrix c0[2], c1[2];
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    c0[threads - 1] = Matrix::Zero(n, 7);
    c1[threads - 1] = Matrix::Zero(n, 7);
    gemm_add_by_rows(a0, b, c0[threads - 1], a1, c1[threads - 1]);
  }
  omp_set_num_threads(saved);
  EXPECT_EQ(c0[0], c0[1]);
  EXPECT_EQ(c1[0], c1[1]);
  Matrix r0 = Matrix::Zero(n, 7), r1 = Matrix::Zero(n, 7);
  gemm_add(a0, b, r0);
  gemm_add(a1, b, r1);
  const double scale = static_cast<double>((a0.cwiseAbs() * b.cwiseAbs()).maxCoeff());
  EXPECT_LT(static_cast<double>((c0[0] - r0).cwiseAbs().maxCoeff()), tolerance * scale);
  EXPECT_LT(static_cast<double>((c1[0] - r1).cwiseAbs().maxCoeff()), tolerance * scale);
}

TEST(BlasGemm, RowSplitProductsMatchOneCallAndTheThreadCount) {
  check_row_split<Eigen::MatrixXd>(1e-13);
  check_row_split<Eigen::MatrixXf>(1e-5);
}

// Repeated at 2 threads, as the residual and the GMRES products call it: bit-identical every time.
// The serial OpenBLAS is not reentrant, and the blocks once split over the threads came out wrong
// in about 1 call in 100 (at the size of case 09, 3P = 1080, m = 3) when both threads ran at once.
template <class Matrix>
void check_repeated_calls() {
  const Eigen::Index n = 1080, m = 3;
  const Matrix a0 = random_matrix<Matrix>(n, n, 4), a1 = random_matrix<Matrix>(n, n, 5);
  const Matrix b = random_matrix<Matrix>(n, m, 6);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(2);
  Matrix first0 = Matrix::Zero(n, m), first1 = Matrix::Zero(n, m);
  gemm_add_by_rows(a0, b, first0, a1, first1);
  int differing = 0;
  for (int call = 0; call < 200; ++call) {
    Matrix c0 = Matrix::Zero(n, m), c1 = Matrix::Zero(n, m);
    gemm_add_by_rows(a0, b, c0, a1, c1);
    if (c0 != first0 || c1 != first1) ++differing;
  }
  omp_set_num_threads(saved);
  EXPECT_EQ(differing, 0);
}

TEST(BlasGemm, RowSplitProductsAreTheSameFromCallToCall) {
  check_repeated_calls<Eigen::MatrixXd>();
  check_repeated_calls<Eigen::MatrixXf>();
}

}  // namespace
}  // namespace jointhb::support
