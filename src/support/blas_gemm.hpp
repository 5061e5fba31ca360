#pragma once
// C += A B for large dense blocks through the BLAS dgemm (the library CHOLMOD already uses:
// OpenBLAS serial after .ci/setup, docs/performance.md), 5–10× faster than Eigen's own kernel
// without -march=native. Single-threaded BLAS: the result does not depend on a thread count. Never
// call it from two threads at once: the serial OpenBLAS is not reentrant (gemm_add_by_rows).

#include <Eigen/Core>
#include <stdexcept>

extern "C" void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
                       const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
                       const double* beta, double* c, const int* ldc);

extern "C" void sgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
                       const float* alpha, const float* a, const int* lda, const float* b, const int* ldb,
                       const float* beta, float* c, const int* ldc);

namespace jointhb::support {

// C(m × n, ldc) += A(m × k, lda) B(k × n, ldb) on raw column-major storage.
inline void gemm_raw(int m, int n, int k, const double* a, int lda, const double* b, int ldb, double* c, int ldc) {
  const double one = 1.0;
  const char no = 'N';
  dgemm_(&no, &no, &m, &n, &k, &one, a, &lda, b, &ldb, &one, c, &ldc);
}
inline void gemm_raw(int m, int n, int k, const float* a, int lda, const float* b, int ldb, float* c, int ldc) {
  const float one = 1.0f;
  const char no = 'N';
  sgemm_(&no, &no, &m, &n, &k, &one, a, &lda, b, &ldb, &one, c, &ldc);
}

/// C += A B (column-major Eigen matrices of double, or of float through sgemm: half the memory
/// traffic of a large A by a few columns; sizes checked).
template <class Matrix>
void gemm_add(const Matrix& A, const Matrix& B, Matrix& C) {
  if (A.cols() != B.rows() || C.rows() != A.rows() || C.cols() != B.cols())
    throw std::invalid_argument("gemm_add: sizes do not match");
  if (A.size() == 0 || B.size() == 0) return;
  const int m = static_cast<int>(A.rows()), n = static_cast<int>(B.cols()), k = static_cast<int>(A.cols());
  gemm_raw(m, n, k, A.data(), m, B.data(), k, C.data(), m);
}

/// C0 += A0 B and C1 += A1 B for two large square A (the residual flexibility and inertia) and a
/// few columns B. The rows are always cut into the same kRowBlocks blocks, one BLAS call each, so
/// the result is the one the earlier split over the threads gave with one thread.
template <class Matrix>
void gemm_add_by_rows(const Matrix& A0, const Matrix& B, Matrix& C0, const Matrix& A1, Matrix& C1) {
  constexpr int kRowBlocks = 8;
  const Eigen::Index n = A0.rows();
  if (A0.cols() != B.rows() || A1.rows() != n || A1.cols() != B.rows() || C0.rows() != n || C1.rows() != n ||
      C0.cols() != B.cols() || C1.cols() != B.cols())
    throw std::invalid_argument("gemm_add_by_rows: sizes do not match");
  if (n == 0 || B.cols() == 0 || B.rows() == 0) return;
  if (n < 1024) {  // small: one call each (a fork would cost more than it saves)
    gemm_add(A0, B, C0);
    gemm_add(A1, B, C1);
    return;
  }
  const int k = static_cast<int>(B.rows()), cols = static_cast<int>(B.cols()), ld = static_cast<int>(n);
  // One thread: the serial OpenBLAS (libopenblas0-serial 0.3.21) takes its packing buffer in
  // blas_memory_alloc without a lock, so two threads calling dgemm/sgemm at once can pack into the
  // same buffer; with the blocks split over two threads about 1 product in 100 came out wrong by
  // O(1) (case 09: residuals and Jacobian products that differed from run to run, Newton
  // failures).
  for (int task = 0; task < 2 * kRowBlocks; ++task) {
    const int block = task % kRowBlocks;
    const Eigen::Index first = n * block / kRowBlocks, rows = n * (block + 1) / kRowBlocks - first;
    const Matrix& A = task < kRowBlocks ? A0 : A1;
    Matrix& C = task < kRowBlocks ? C0 : C1;
    gemm_raw(static_cast<int>(rows), cols, k, A.data() + first, ld, B.data(), k, C.data() + first, ld);
  }
}

}  // namespace jointhb::support
