#pragma once
// Sparse symmetric factorisation A = P L Lᵀ Pᵀ (or P L D Lᵀ Pᵀ) by CHOLMOD (SuiteSparse), for the
// three uses of the FE layers:
//   (a) preload Newton: the tangent keeps its pattern, so analyze() once (fill-reducing ordering
//       and symbolic factor), then factorize() with new values every iteration;
//   (b) shift-invert for modes: the caller forms K − σM (SPD for σ < 0 when K is positive
//       semi-definite and M positive definite, since xᵀ(K − σM)x = xᵀKx + |σ| xᵀMx > 0);
//   (c) constraint modes: solve() with a dense block of right-hand sides in one call.
//
// Only one triangle of A is read (Options::triangle); the other may be absent or hold anything,
// so a fully stored symmetric matrix can be passed as it is. CHOLMOD stays behind a pimpl.
//
// Determinism: the supernodal factor calls the BLAS (dsyrk/dgemm/dtrsm) and LAPACK (dpotrf); the
// ordering (AMD, or METIS for large 3D meshes) is deterministic. Results are independent of the
// thread count as long as the BLAS is: the environment (.ci/setup) uses Debian's single-threaded
// OpenBLAS (libopenblas0-serial, selected as libblas.so.3 by update-alternatives; the reference
// netlib BLAS works too, 8-10x slower at 100k-300k DOFs). Debian's CHOLMOD 5.12 links libgomp, but its OpenMP loops
// only copy and clear: validation/fe/modal_scaling and fe_scaling give bit-identical eigenvalues
// with OMP_NUM_THREADS=1 and 2 (checked), and two factorisations of one matrix agree bit for bit
// (tested). A multithreaded BLAS (libopenblas0-pthread, MKL) changes the last bits with the
// thread count: fe_scaling's frequencies moved by up to 1.4e-10 relative between 1 and 2
// OpenBLAS threads (docs/performance.md).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>

namespace jointhb::fe {

struct SparseCholeskyOptions {
  enum class Triangle {
    lower,  ///< the values are read from the lower triangle (incl. the diagonal)
    upper,  ///< the values are read from the upper triangle (incl. the diagonal)
  };
  enum class Method {
    /// Supernodal LLᵀ (dense BLAS-3 kernels; the fast choice for FE matrices). A must be
    /// positive definite; a failing pivot is reported.
    supernodal_llt,
    /// Simplicial LDLᵀ without pivoting: also factors symmetric indefinite matrices whose
    /// leading minors (in the fill-reducing order) are non-singular, e.g. K − σM with σ between
    /// eigenvalues; negative_pivots() then counts the eigenvalues of K below σ (Sylvester's law
    /// of inertia). No pivoting means no stability guarantee for indefinite A: check residuals.
    simplicial_ldlt,
  };
  /// Who factors: CHOLMOD in this process, or MUMPS across the ranks of the petsc::Session
  /// (fe/petsc_solvers.hpp; supernodal_llt → MUMPS's SPD mode, simplicial_ldlt → its symmetric
  /// indefinite mode with the inertia). Same contract, results equal to round-off.
  /// Or no factor at all: `cg`, PETSc's conjugate gradients preconditioned by algebraic multigrid
  /// across the same ranks (`iterative` below): factorize() builds the multigrid hierarchy, solve()
  /// iterates to a relative residual; results agree with the factorisations to that tolerance,
  /// memory grows as O(n) instead of the factor's O(n^{4/3}). supernodal_llt only (CG needs A
  /// positive definite; an indefinite A shows as a failed solve).
  enum class Backend { cholmod, mumps, cg };
  /// The cg backend's settings (docs/distributed.md §2).
  struct Iterative {
    enum class Preconditioner {
      gamg,   ///< PETSc's smoothed-aggregation multigrid with the near-null space below
      hypre,  ///< hypre's BoomerAMG (classical AMG; the near-null space is not used)
    };
    Preconditioner preconditioner = Preconditioner::gamg;
    /// ‖b − A x‖₂ ≤ relative_tolerance · ‖b‖₂ for every right-hand side (the true residual).
    double relative_tolerance = 1e-10;
    int max_iterations = 5000;  ///< per right-hand side; more is a failed solve
    /// The near-null space of A, n × k (for elasticity the six rigid-body modes restricted to A's
    /// DOFs: fe/rigid_body_modes.hpp): what smoothed aggregation must represent on its coarse
    /// grids. Empty: the constant vector only, which converges far more slowly on solids.
    Eigen::MatrixXd near_null_space;
  };
  Triangle triangle = Triangle::lower;     ///< which triangle of A holds the values
  Method method = Method::supernodal_llt;  ///< factorisation kind
  Backend backend = Backend::cholmod;
  Iterative iterative = {};                ///< Backend::cg only
};

/// The linear solver a stage factors with (its options' `linear_solver`).
using LinearSolver = SparseCholeskyOptions::Backend;
/// The settings of the iterative backend a stage may use (its options' `iterative`).
using IterativeSettings = SparseCholeskyOptions::Iterative;
/// "cholmod", "mumps", "cg".
[[nodiscard]] const char* to_string(LinearSolver backend);
/// "gamg", "hypre".
[[nodiscard]] const char* to_string(IterativeSettings::Preconditioner preconditioner);

/// What the factorisation cost, for performance logs.
struct SparseCholeskyStatistics {
  long rows = 0;                   ///< n
  long matrix_nonzeros = 0;        ///< entries of A read (the chosen triangle incl. diagonal)
  double factor_nonzeros = 0.0;    ///< nnz(L) of the symbolic analysis (CHOLMOD's lnz)
  long factor_entries = 0;         ///< entries stored for L (supernodal: incl. amalgamation zeros)
  double factor_flops = 0.0;       ///< flops of one numeric factorisation (CHOLMOD's fl)
  std::string ordering;            ///< fill-reducing ordering chosen: "AMD", "METIS", ...
  int factorizations = 0;          ///< numeric factorisations done on this analysis
  double analyze_seconds = 0.0;    ///< wall time of analyze()
  double factorize_seconds = 0.0;  ///< wall time of the last factorize()
  long iterations = 0;             ///< cg backend: Krylov iterations of all solves so far
  long solved_columns = 0;         ///< cg backend: right-hand sides solved so far

  /// One line: "n=…, nnz(A)=…, nnz(L)=… (fill ×…), … Gflop, ordering …".
  [[nodiscard]] std::string brief() const;
};

class SparseCholesky {
 public:
  using Options = SparseCholeskyOptions;

  explicit SparseCholesky(Options options = {});
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  /// Ordering and symbolic factorisation of A's pattern (the chosen triangle). A square;
  /// explicit zeros count as entries. Throws std::invalid_argument (not square) or
  /// std::runtime_error (CHOLMOD failure, e.g. out of memory).
  void analyze(const Eigen::SparseMatrix<double>& A);

  /// Numeric factorisation with A's values. A must have exactly the pattern given to analyze()
  /// (std::invalid_argument otherwise); analyze() is run first if it has not been. Throws
  /// std::runtime_error with one line when A is not positive definite (LLᵀ) or has a zero pivot
  /// (LDLᵀ), naming the column and CHOLMOD's status; the factor is then unusable until the next
  /// successful factorize().
  void factorize(const Eigen::SparseMatrix<double>& A);

  /// analyze(A) then factorize(A).
  void compute(const Eigen::SparseMatrix<double>& A);

  /// X = A⁻¹ B for one or many right-hand sides in one call (B: n × k, any k ≥ 0; a vector gives
  /// an n × 1 result, assignable to a VectorXd). Throws std::logic_error without a valid factor
  /// and std::invalid_argument on a size mismatch. Reuses internal workspace: one SparseCholesky
  /// must not be used by two threads at once.
  [[nodiscard]] Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& B) const;
  /// x = A⁻¹ b into `x` (size n), without allocating once the workspace exists.
  void solve_into(const Eigen::Ref<const Eigen::VectorXd>& b, Eigen::Ref<Eigen::VectorXd> x) const;

  [[nodiscard]] bool analyzed() const;
  [[nodiscard]] bool factorized() const;
  [[nodiscard]] long rows() const;
  /// Simplicial LDLᵀ only: the number of negative entries of D (= eigenvalues of A below 0);
  /// -1 for LLᵀ or without a factor.
  [[nodiscard]] long negative_pivots() const;
  [[nodiscard]] const SparseCholeskyStatistics& statistics() const;
  [[nodiscard]] const Options& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace jointhb::fe
