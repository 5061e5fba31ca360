#pragma once
// The distributed linear-algebra path of the finite-element stages (docs/distributed.md): sparse
// symmetric factorisations by MUMPS (or, without a factor, conjugate gradients with algebraic
// multigrid: GAMG or hypre) and shift-invert eigenpairs by SLEPc's Krylov–Schur, on PETSc matrices
// whose rows are split across the MPI ranks.
//
// How the ranks cooperate. The pipeline (mesh, assembly, contact, harmonic balance) runs on rank 0
// alone, unchanged; the other ranks only ever take part in the linear algebra. A Session is made on
// every rank; ranks > 0 then call serve() and execute rank 0's commands until rank 0's Session ends.
// On rank 0, a DistributedSolver or distributed_eigenpairs() broadcasts a command, sends each rank
// its block of rows of the matrix (the upper triangle in compressed rows; PETSc's MPISBAIJ format),
// and all ranks enter PETSc's collective calls together. So the factor — the memory that grows
// fastest, O(n^{4/3}) entries for 3D meshes against O(n) for the matrix — is split across the ranks,
// while the assembled matrices stay on rank 0 (distributed assembly is the next step for 10⁷ DOFs,
// docs/distributed.md §5).
//
// Without a launcher (no mpirun), a Session is a world of one process: MUMPS and SLEPc run
// sequentially. In a build without PETSc (cmake -DJOINTHB_WITH_PETSC=OFF) built() is false, making a
// Session throws, and choosing the MUMPS or SLEPc backends is an input error.
//
// Results match the CHOLMOD/ARPACK path to round-off: different orderings and pivot sequences give
// different last bits, so the two paths agree to stated tolerances, not bitwise (tests/cli/petsc.sh).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "jointhb/fe/sparse_cholesky.hpp"

namespace jointhb::fe::petsc {

/// Whether this build has the PETSc/SLEPc path.
[[nodiscard]] bool built();

/// PETSc and SLEPc on every rank of this process's MPI world (collective: every rank makes one).
/// At most one per process; its lifetime brackets every use of the classes below.
class Session {
 public:
  /// Initialises SLEPc (and PETSc, and MPI unless already initialised). Throws std::runtime_error
  /// in a build without PETSc or when initialisation fails.
  Session(int* argc, char*** argv);
  /// Rank 0: tells the other ranks to leave serve(). All: finalises what this object initialised.
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  [[nodiscard]] int rank() const;
  [[nodiscard]] int size() const;
  /// Ranks > 0: executes rank 0's commands until its Session ends. Rank 0: returns at once.
  void serve();
  /// The session of this process, or nullptr.
  [[nodiscard]] static Session* current();
};

/// Statistics of a MUMPS factorisation (INFOG of MUMPS's user guide, §6) or of the iterative
/// solver's setup and solves.
struct DistributedSolverStatistics {
  long rows = 0;
  long matrix_nonzeros = 0;     ///< entries sent: the upper triangle (MUMPS) or all (CG)
  double factor_entries = 0.0;  ///< INFOG(29): entries of the factors, all ranks (0 for CG)
  double factor_flops = 0.0;    ///< RINFOG(3): flops of the elimination, all ranks (0 for CG)
  int ranks = 1;
  std::string method = "MUMPS"; ///< "MUMPS", "CG/GAMG", "CG/hypre"
  double analyze_seconds = 0.0;
  double factorize_seconds = 0.0;  ///< MUMPS: the numeric factorisation; CG: the multigrid setup
  long iterations = 0;             ///< CG: Krylov iterations of all solves
  long solved_columns = 0;         ///< CG: right-hand sides solved
};

/// The same in SparseCholesky's terms (ordering "MUMPS on R ranks"; factorizations 0: the caller's).
[[nodiscard]] SparseCholeskyStatistics as_sparse_cholesky_statistics(const DistributedSolverStatistics& s);

/// A x = b for a sparse symmetric A across the session's ranks, called on rank 0 only: A = LDLᵀ by
/// MUMPS, or conjugate gradients with algebraic multigrid (SparseCholeskyOptions::Iterative). The
/// contract of fe::SparseCholesky (fe/sparse_cholesky.hpp), whose mumps and cg backends it is:
/// analyze() the pattern once, factorize() new values, solve() many right-hand sides.
class DistributedSolver {
 public:
  /// MUMPS. positive_definite: its symmetric positive definite mode (SYM = 1, no pivoting; a matrix
  /// with negative pivots is refused, which MUMPS itself does not do), else the general symmetric
  /// mode (SYM = 2, LDLᵀ with 2×2 pivots) with the inertia available.
  /// lower_triangle: which triangle of A holds the values. Throws std::logic_error without a Session.
  DistributedSolver(bool positive_definite, bool lower_triangle);
  /// Conjugate gradients (A symmetric positive definite) with `settings`' preconditioner.
  DistributedSolver(const SparseCholeskyOptions::Iterative& settings, bool lower_triangle);
  ~DistributedSolver();
  DistributedSolver(const DistributedSolver&) = delete;
  DistributedSolver& operator=(const DistributedSolver&) = delete;

  /// Distributes A (its pattern and values) and runs MUMPS's analysis (ordering, symbolic factor);
  /// for CG, the near-null space as well.
  void analyze(const Eigen::SparseMatrix<double>& A);
  /// Distributes A's values (the analysed pattern) and factors (CG: sets the multigrid up).
  /// std::runtime_error (one line) when MUMPS fails, e.g. a non-positive pivot in SPD mode.
  void factorize(const Eigen::SparseMatrix<double>& A);
  /// X = A⁻¹ B (B: n × k, k ≥ 1). CG: std::runtime_error (one line, PETSc's reason) when a column
  /// does not reach the tolerance (e.g. A indefinite, or max_iterations).
  [[nodiscard]] Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& B);
  /// Negative eigenvalues of A (inertia; MUMPS's general symmetric mode only, else −1).
  [[nodiscard]] long negative_pivots() const;
  [[nodiscard]] const DistributedSolverStatistics& statistics() const;

 private:
  // (unused in a build without PETSc, apart from negative_)
  [[maybe_unused]] int handle_ = -1;
  [[maybe_unused]] int method_ = 0;  // 0 MUMPS, 1 CG/GAMG, 2 CG/hypre
  [[maybe_unused]] bool positive_definite_ = true;
  [[maybe_unused]] bool lower_ = true;
  [[maybe_unused]] bool factorized_ = false;
  [[maybe_unused]] SparseCholeskyOptions::Iterative iterative_;
  long negative_ = -1;
  DistributedSolverStatistics statistics_;
};

struct EigenpairOptions {
  int count = 20;           ///< eigenpairs wanted, nearest the shift
  double shift = 0.0;       ///< σ; K − σM must be positive definite (σ below the spectrum)
  double tolerance = 1e-10; ///< SLEPc's relative residual tolerance
  int max_iterations = 300; ///< Krylov–Schur restarts
  int ncv = 0;              ///< basis size; 0: SLEPc's default
  std::uint64_t seed = 1;   ///< of the starting vector (as ARPACK's, modal/modes.hpp)
  /// Shift-and-invert by CG with algebraic multigrid instead of MUMPS's Cholesky: each solve with
  /// K − σM to min(relative_tolerance, tolerance / 100), so that the eigenpairs reach `tolerance`.
  std::optional<SparseCholeskyOptions::Iterative> iterative = {};
};

struct EigenpairResult {
  bool ok = false;
  std::string message;          ///< why not (or fewer converged), one line
  Eigen::VectorXd eigenvalues;  ///< λ, as SLEPc returns them (not sorted)
  Eigen::MatrixXd vectors;      ///< n × converged
  int iterations = 0;           ///< EPSGetIterationNumber
  int ranks = 1;
  DistributedSolverStatistics factor;  ///< of K − σM (CG: its setup and iterations)
  /// CG path: K's null space found among the near-null vectors (rigid-body motions of a free-free
  /// model), deflated from SLEPc's iteration and returned as its Rayleigh–Ritz pairs (first).
  int deflated = 0;
  /// The shift the solve ran at: options.shift, or lower on the CG path with a deflated null space
  /// (distributed_eigenpairs; the same `count` eigenpairs nearest, better conditioned inner solves).
  double shift_used = 0.0;
  double factor_seconds = 0.0;           ///< distributing K and M and factoring K − σM
  double solve_seconds = 0.0;            ///< EPSSolve after the factorisation, and the gather
};

/// K φ = λ M φ nearest the shift by SLEPc's Krylov–Schur with shift-and-invert (ST sinvert, MUMPS
/// Cholesky of K − σM), GHEP (M-orthogonal basis). K, M: symmetric, stored in full. Called on rank 0.
[[nodiscard]] EigenpairResult distributed_eigenpairs(const Eigen::SparseMatrix<double>& K,
                                                     const Eigen::SparseMatrix<double>& M,
                                                     const EigenpairOptions& options);

}  // namespace jointhb::fe::petsc
