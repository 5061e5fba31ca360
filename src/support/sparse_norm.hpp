#pragma once
// ‖A‖₁ = max_j Σ_i |a_ij| of a sparse matrix (modal backward errors, the Craig–Bampton rigid-mode
// test).

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

namespace jointhb::support {

inline double norm1(const Eigen::SparseMatrix<double>& A) {
  double best = 0.0;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    double sum = 0.0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) sum += std::abs(it.value());
    best = std::max(best, sum);
  }
  return best;
}

}  // namespace jointhb::support
