#pragma once
// C += A B for large dense blocks through the BLAS dgemm (the library CHOLMOD already uses:
// OpenBLAS serial after .ci/setup, docs/performance.md), 5–10× faster than Eigen's own kernel
// without -march=native. Single-threaded BLAS: the result does not depend on a thread count.

#include <Eigen/Core>
#include <stdexcept>

extern "C" void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
                       const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
                       const double* beta, double* c, const int* ldc);

namespace jointhb::support {

/// C += A B (column-major Eigen matrices; sizes checked).
inline void gemm_add(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, Eigen::MatrixXd& C) {
  if (A.cols() != B.rows() || C.rows() != A.rows() || C.cols() != B.cols())
    throw std::invalid_argument("gemm_add: sizes do not match");
  if (A.size() == 0 || B.size() == 0) return;
  const int m = static_cast<int>(A.rows()), n = static_cast<int>(B.cols()), k = static_cast<int>(A.cols());
  const double one = 1.0;
  const char no = 'N';
  dgemm_(&no, &no, &m, &n, &k, &one, A.data(), &m, B.data(), &k, &one, C.data(), &m);
}

}  // namespace jointhb::support
