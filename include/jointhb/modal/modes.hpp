#pragma once
// Normal modes of the undamped structure: the generalized symmetric eigenproblem
//   K φ = λ M φ,   λ = ω² [rad²/s²],   f = ω/(2π) [Hz],   φᵀ M φ = 1,
// for the `count` eigenvalues nearest the shift σ, by ARPACK's implicitly restarted Lanczos method
// in shift-invert mode (dsaupd/dseupd, mode 3, bmat = 'G', which = 'LM'; Lehoucq, Sorensen &
// Yang, ARPACK Users' Guide, SIAM 1998, §3.2.3 and §4.2): Lanczos on
//   OP = (K − σM)⁻¹ M  in the M inner product,   OP φ = θ φ  with  θ = 1/(λ − σ),
// so the λ nearest σ become the θ of largest magnitude. K − σM is factored once by CHOLMOD
// (fe/sparse_cholesky.hpp). With σ < 0, K − σM is positive definite whenever K is positive
// semi-definite and M positive definite, so a free-free structure (singular K) needs no special
// treatment: its rigid-body modes come out with λ ≈ 0 (to round-off, ~ε·‖K‖/‖M‖) and are
// reported like the others; the caller decides what to do with them. With σ < 0 every λ ≥ 0 lies
// above σ, so the λ nearest σ are the lowest ones.
//
// ARPACK's own random starting vector depends on a seed that its previous calls advanced; here
// the starting vector comes from a fixed seed (ModalOptions::seed), so the same input gives the
// same output in every run and every call. ARPACK keeps internal state between calls (Fortran
// SAVE variables): compute_modes must not run in two threads at once.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <string>

#include "jointhb/contact/termination.hpp"
#include "jointhb/fe/sparse_cholesky.hpp"

namespace jointhb::modal {

struct ModalOptions {
  int count = 20;  ///< modes wanted, 1 ≤ count < n
  /// σ [rad²/s²] (the units of λ = ω²). Negative values suit free-free structures (see above);
  /// the default −(2π · 1 Hz)² suits structures whose lowest elastic modes lie between about
  /// 1 Hz and 100 kHz. Any σ for which K − σM is positive definite is valid (σ < λ_min).
  double shift = -39.47841760435743;
  /// ARPACK's stopping tolerance (0, 1e-3]: Ritz values θ of OP accepted when the Lanczos residual
  /// bound is ≤ tolerance·|θ|.
  double tolerance = 1e-10;
  int max_iterations = 300;  ///< ≥ 1: implicit restarts of the Lanczos process (ARPACK's mxiter)
  /// Lanczos basis size: 0 = automatic, min(n, max(2·count + 1, count + 20)); otherwise
  /// count < ncv ≤ n. Larger ncv: fewer restarts, more memory (n·ncv doubles).
  int ncv = 0;
  std::uint64_t seed = 1;  ///< seed of the starting vector (std::mt19937_64)
  /// Who factors K − σM (and, in the condensation, the constraint and residual solves): CHOLMOD,
  /// or MUMPS across MPI ranks (fe/petsc_solvers.hpp).
  fe::LinearSolver linear_solver = fe::LinearSolver::cholmod;
  /// linear_solver = cg: preconditioner, tolerance and near-null space (fe/sparse_cholesky.hpp);
  /// with SLEPc the inner solves go two orders below `tolerance` (fe/petsc_solvers.hpp).
  fe::IterativeSettings iterative = {};
  /// Lanczos by ARPACK (in this process; with the linear_solver's factor), or SLEPc's
  /// Krylov–Schur across MPI ranks (its own MUMPS factor of K − σM; ncv and tolerance mean the
  /// same; `iterations` counts its restarts, operator/mass applications are not reported).
  enum class EigenSolver { arpack, slepc };
  EigenSolver eigen_solver = EigenSolver::arpack;

  /// Empty when valid, else "field: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

struct ModalResult {
  /// converged: all `count` modes converged; no_convergence: fewer did (ARPACK's restarts ran
  /// out, or no shifts applicable), the converged ones are returned, see `message`; failed: K − σM
  /// could not be factored or ARPACK stopped with an error, no modes.
  Termination termination = Termination::failed;
  std::string message;          ///< one line; empty when converged
  Eigen::VectorXd eigenvalues;  ///< λ_j = ω_j² [rad²/s²], ascending
  /// f_j = sign(λ_j)·√|λ_j| / (2π) [Hz]: a rigid-body mode whose λ came out slightly negative by
  /// round-off shows as a tiny negative frequency rather than hiding as 0.
  Eigen::VectorXd frequencies_hz;
  Eigen::MatrixXd shapes;  ///< n × m, column j = φ_j with φ_jᵀ M φ_j = 1, largest |entry| positive
  /// Relative residual ‖Kφ_j − λ_j Mφ_j‖₂ / (max(|λ_j|, |σ|) ‖Mφ_j‖₂): for an elastic mode
  /// (|λ| ≫ |σ|) the residual relative to λ‖Mφ‖ ≈ ‖Kφ‖. A rigid-body mode (λ ≈ 0) is measured
  /// against the shift instead, and there merely evaluating Kφ in floating point leaves a floor
  /// of about ε‖K‖/(‖M‖|σ|) (e.g. 3e-6 for a steel bar of 1 cm elements and σ = −(2π)²): judge
  /// rigid-body modes by `backward_errors`.
  Eigen::VectorXd residuals;
  /// Normwise backward error ‖Kφ_j − λ_j Mφ_j‖₂ / ((‖K‖₁ + |λ_j| ‖M‖₁) ‖φ_j‖₂) (Higham & Higham,
  /// 1998): the relative perturbation of K and M for which (λ_j, φ_j) is exact.
  Eigen::VectorXd backward_errors;
  double shift = 0.0;             ///< σ used [rad²/s²]
  int requested = 0;              ///< count asked for
  int iterations = 0;             ///< ARPACK restarts (its iparam(3) on exit)
  int operator_applications = 0;  ///< OP x = (K − σM)⁻¹ M x, i.e. factor solves (iparam(9))
  int mass_applications = 0;      ///< M x products requested by ARPACK (iparam(10))
  int ncv = 0;                    ///< Lanczos basis size used
  fe::SparseCholeskyStatistics factor;  ///< the factorisation of K − σM
  double factor_seconds = 0.0;          ///< forming and factoring K − σM
  double lanczos_seconds = 0.0;         ///< dsaupd + dseupd with the operator applications
  double seconds = 0.0;                 ///< total wall time

  /// One line: "20 modes, 0.0 … 1234.5 Hz, max residual …, … iterations, … s".
  [[nodiscard]] std::string brief() const;
  /// The status convention (contact/termination.hpp): `termination` with `message`, or with
  /// "m of count modes converged" when that is empty.
  [[nodiscard]] Status status() const;
};

/// The `options.count` modes of K φ = λ M φ nearest `options.shift`. K and M: square, same size,
/// symmetric and stored in full (both triangles, as assembled); only the lower triangle of
/// K − σM is factored. Throws std::invalid_argument on invalid options or matrices (naming the
/// field or the constraint); numerical failures (K − σM not positive definite, ARPACK errors,
/// non-convergence) are a status with a one-line message.
ModalResult compute_modes(const Eigen::SparseMatrix<double>& K,
                          const Eigen::SparseMatrix<double>& M, const ModalOptions& options = {});

}  // namespace jointhb::modal
