// Description: wall time and accuracy of compute_modes (ARPACK mode 3 + CHOLMOD supernodal LLᵀ)
// on a free-free 3D pencil of about 100 000 DOFs: K the 7-point graph Laplacian of an
// nx × ny × nz grid (Neumann: singular, one rigid mode, the constant), M = I/2 + A/16 with A the
// grid's adjacency (SPD by Gershgorin). Prints the factor statistics, the modal summary, the
// lowest eigenvalues, residuals and backward errors, and a checksum of the eigenvalues (run it
// with different OMP_NUM_THREADS: the checksum must not change). ctest runs it with --ci on a
// 12³ grid (a smoke run); the full size takes tens of seconds on one core.
//
// Sample run:  modal_scaling [nx ny nz] [count]   (default 47 46 46 → 99 452 DOFs, 20 modes)
//   Measured (one core of the shared build machine, reference BLAS, OMP_NUM_THREADS=1):
//   METIS ordering, nnz(L) = 25.7 M (fill ×66 over tril(K − σM)), 37.5 Gflop, analyze 0.8 s,
//   factorize 8.3 s; ncv 41, 5 restarts, 86 solves, Lanczos 6.8 s; total 16.0 s, 431 MB peak;
//   rigid mode λ = 2.4e-16, elastic residuals ≤ 5e-12, backward errors ≤ 2.2e-15.

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <Eigen/SparseCore>

#include "jointhb/modal/modes.hpp"

// The study is one function of the multi-call program jointhb_validate_fe (CMakeLists.txt).
namespace jointhb_study_fe_modal_scaling {

int run(int argc, char** argv) {
  int nx = 47, ny = 46, nz = 46, count = 20;
  if (argc >= 2 && std::strcmp(argv[1], "--ci") == 0) {
    nx = ny = nz = 12;  // ctest's smoke run (validation/fe/CMakeLists.txt): 1728 DOFs
  } else if (argc >= 4) {
    nx = std::atoi(argv[1]);
    ny = std::atoi(argv[2]);
    nz = std::atoi(argv[3]);
  }
  if (argc >= 5) count = std::atoi(argv[4]);
  const int n = nx * ny * nz;
  auto index = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  std::vector<Eigen::Triplet<double>> k_entries, m_entries;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int a = index(i, j, k);
        m_entries.emplace_back(a, a, 0.5);
        const int neighbours[3][3] = {{i + 1, j, k}, {i, j + 1, k}, {i, j, k + 1}};
        for (const auto& nb : neighbours) {
          if (nb[0] >= nx || nb[1] >= ny || nb[2] >= nz) continue;
          const int b = index(nb[0], nb[1], nb[2]);
          // K: graph Laplacian (each edge adds [1 −1; −1 1]); M: adjacency / 16.
          k_entries.emplace_back(a, a, 1.0);
          k_entries.emplace_back(b, b, 1.0);
          k_entries.emplace_back(a, b, -1.0);
          k_entries.emplace_back(b, a, -1.0);
          m_entries.emplace_back(a, b, 1.0 / 16);
          m_entries.emplace_back(b, a, 1.0 / 16);
        }
      }
  Eigen::SparseMatrix<double> K(n, n), M(n, n);
  K.setFromTriplets(k_entries.begin(), k_entries.end());
  M.setFromTriplets(m_entries.begin(), m_entries.end());

  jointhb::modal::ModalOptions options;
  options.count = count;
  options.shift = -1e-4;  // below the lowest elastic λ (5.2e-3 for the default grid)
  const auto result = jointhb::modal::compute_modes(K, M, options);
  std::printf("grid %d x %d x %d: n = %d, nnz(K) = %ld, nnz(M) = %ld\n", nx, ny, nz, n,
              static_cast<long>(K.nonZeros()), static_cast<long>(M.nonZeros()));
  std::printf("factor: %s\n", result.factor.brief().c_str());
  std::printf("modes:  %s\n", result.brief().c_str());
  if (!result.message.empty()) std::printf("message: %s\n", result.message.c_str());
  double checksum = 0.0, worst_elastic = 0.0;
  for (Eigen::Index j = 0; j < result.eigenvalues.size(); ++j) {
    std::printf("  %2ld  lambda = %.15e  residual %.2e  backward error %.2e\n",
                static_cast<long>(j + 1), result.eigenvalues(j), result.residuals(j),
                result.backward_errors(j));
    checksum += result.eigenvalues(j) * static_cast<double>(j + 1);
    if (j > 0 && result.residuals(j) > worst_elastic) worst_elastic = result.residuals(j);
  }
  std::printf(
      "checksum %.17g; factor %.2f s, Lanczos %.2f s, total %.2f s; ncv %d, %d iterations,"
      " %d solves\n",
      checksum, result.factor_seconds, result.lanczos_seconds, result.seconds, result.ncv,
      result.iterations, result.operator_applications);
  const bool ok = result.termination == jointhb::Termination::converged && worst_elastic < 1e-8;
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}

}  // namespace jointhb_study_fe_modal_scaling
