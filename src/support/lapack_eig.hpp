#pragma once
// Eigenvalues and right eigenvectors of a real nonsymmetric matrix through LAPACK dgeev
// (Hessenberg QR; liblapack.so.3, the same serial OpenBLAS as support/lapack_lu.hpp, so the result
// does not depend on a thread count). Several times faster than Eigen::EigenSolver on the
// 2N × 2N companion matrices of Hill's method (hb/hill_stability.hpp). dgeev first balances the
// matrix (dgebal: a diagonal similarity by powers of 2 that equalises row and column norms,
// Parlett & Reinsch 1969), which Eigen::EigenSolver does not: a monodromy whose state mixes units
// (modal coordinates, velocities, tractions in Pa) spans 27 orders of magnitude, and unbalanced QR
// then returns |ρ| ≈ 1e4 for multipliers at 1 (docs/stability.md §7).

#include <Eigen/Core>
#include <complex>
#include <vector>

extern "C" {
void dgeev_(const char* jobvl, const char* jobvr, const int* n, double* a, const int* lda,
            double* wr, double* wi, double* vl, const int* ldvl, double* vr, const int* ldvr,
            double* work, const int* lwork, int* info);
}

namespace jointhb::support {

struct EigenDecomposition {
  Eigen::VectorXcd values;   ///< λ_j
  Eigen::MatrixXcd vectors;  ///< column j: right eigenvector of λ_j (unit 2-norm)
  bool ok = false;           ///< false when the QR iteration did not converge
};

/// A v = λ v for a square real matrix (copied); without `vectors`, the eigenvalues only (`vectors`
/// of the result empty).
inline EigenDecomposition eigen_decomposition(const Eigen::MatrixXd& a, bool vectors = true) {
  EigenDecomposition out;
  const int n = static_cast<int>(a.rows());
  if (n == 0 || a.rows() != a.cols() || !a.allFinite()) return out;
  Eigen::MatrixXd work_matrix = a;
  std::vector<double> wr(static_cast<std::size_t>(n)), wi(static_cast<std::size_t>(n));
  Eigen::MatrixXd vr(vectors ? n : 1, vectors ? n : 1);
  const char no = 'N', yes = vectors ? 'V' : 'N';
  const int ldvr = static_cast<int>(vr.rows());
  const int one = 1;
  int info = 0;
  int lwork = -1;
  double query = 0.0;
  dgeev_(&no, &yes, &n, work_matrix.data(), &n, wr.data(), wi.data(), nullptr, &one, vr.data(),
         &ldvr, &query, &lwork, &info);
  lwork = static_cast<int>(query);
  std::vector<double> work(static_cast<std::size_t>(std::max(lwork, 4 * n)));
  lwork = static_cast<int>(work.size());
  dgeev_(&no, &yes, &n, work_matrix.data(), &n, wr.data(), wi.data(), nullptr, &one, vr.data(),
         &ldvr, work.data(), &lwork, &info);
  if (info != 0) return out;
  out.values.resize(n);
  for (int j = 0; j < n; ++j) out.values[j] = {wr[static_cast<std::size_t>(j)], wi[static_cast<std::size_t>(j)]};
  out.ok = true;
  if (!vectors) return out;
  out.vectors.resize(n, n);
  // dgeev stores a complex pair λ, λ̄ (wi_j > 0) as columns j (real part) and j+1 (imaginary part).
  for (int j = 0; j < n; ++j) {
    if (wi[static_cast<std::size_t>(j)] == 0.0) {
      out.vectors.col(j) = vr.col(j).cast<std::complex<double>>();
    } else if (wi[static_cast<std::size_t>(j)] > 0.0 && j + 1 < n) {
      const std::complex<double> i(0.0, 1.0);
      out.vectors.col(j) = vr.col(j).cast<std::complex<double>>() + i * vr.col(j + 1);
      out.vectors.col(j + 1) = out.vectors.col(j).conjugate();
      ++j;
    }
  }
  return out;
}

}  // namespace jointhb::support
