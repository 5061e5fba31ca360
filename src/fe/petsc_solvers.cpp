// The PETSc/SLEPc path of the FE stages (fe/petsc_solvers.hpp, docs/distributed.md).
#include "jointhb/fe/petsc_solvers.hpp"

#include <stdexcept>

#ifdef JOINTHB_WITH_PETSC
#include <fmt/format.h>
#include <mpi.h>
#include <petscksp.h>
#include <petscmat.h>
#include <slepceps.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <map>
#include <random>
#include <thread>
#include <vector>

#include "../support/stopwatch.hpp"
#endif

namespace jointhb::fe::petsc {

SparseCholeskyStatistics as_sparse_cholesky_statistics(const DistributedSolverStatistics& s) {
  SparseCholeskyStatistics to;
  to.iterations = s.iterations;
  to.solved_columns = s.solved_columns;
  to.rows = s.rows;
  to.matrix_nonzeros = s.matrix_nonzeros;
  to.factor_nonzeros = s.factor_entries;
  to.factor_entries = static_cast<long>(s.factor_entries);
  to.factor_flops = s.factor_flops;
  to.ordering = s.method + " on " + std::to_string(s.ranks) + (s.ranks == 1 ? " rank" : " ranks");
  to.analyze_seconds = s.analyze_seconds;
  to.factorize_seconds = s.factorize_seconds;
  return to;
}

#ifndef JOINTHB_WITH_PETSC

namespace {
[[noreturn]] void not_built() {
  throw std::runtime_error(
      "this jointhb was built without PETSc/SLEPc (configure with -DJOINTHB_WITH_PETSC=ON after "
      "installing libpetsc-real-dev and libslepc-real-dev: bash .ci/setup)");
}
}  // namespace

bool built() { return false; }
Session::Session(int*, char***) { not_built(); }
Session::~Session() = default;
int Session::rank() const { return 0; }
int Session::size() const { return 1; }
void Session::serve() {}
Session* Session::current() { return nullptr; }
DistributedSolver::DistributedSolver(bool, bool) { not_built(); }
DistributedSolver::DistributedSolver(const SparseCholeskyOptions::Iterative&, bool) { not_built(); }
DistributedSolver::~DistributedSolver() = default;
void DistributedSolver::analyze(const Eigen::SparseMatrix<double>&) { not_built(); }
void DistributedSolver::factorize(const Eigen::SparseMatrix<double>&) { not_built(); }
Eigen::MatrixXd DistributedSolver::solve(const Eigen::Ref<const Eigen::MatrixXd>&) { not_built(); }
long DistributedSolver::negative_pivots() const { return negative_; }
const DistributedSolverStatistics& DistributedSolver::statistics() const { return statistics_; }
EigenpairResult distributed_eigenpairs(const Eigen::SparseMatrix<double>&,
                                       const Eigen::SparseMatrix<double>&, const EigenpairOptions&) {
  not_built();
}

#else

namespace {

/// Throws the PETSc error `code` as one line naming the call.
void check(PetscErrorCode code, const char* call) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw std::runtime_error(fmt::format("PETSc {} failed: {}", call,
                                       text != nullptr ? text : fmt::format("error {}", code)));
}

// ---- the commands rank 0 sends -------------------------------------------------------------------
enum class Op : int { quit, analyze, factorize, solve, release, eigenpairs };

/// How a system is solved: MUMPS's factorisation, or CG with one of two multigrid preconditioners.
enum class Method : int { mumps, cg_gamg, cg_hypre };

struct Command {
  Op op = Op::quit;
  int handle = -1;
  Method method = Method::mumps;
  int positive_definite = 1;
  int null_vectors = 0;     // CG: columns of the near-null space sent with analyze / eigenpairs
  int deflation_vectors = 0;  // eigenpairs by CG: columns of K's null space the eigensolver skips
  int cg_max_iterations = 0;
  double cg_tolerance = 0.0;
  int count = 0;            // eigenpairs
  int max_iterations = 0;   // eigenpairs
  int ncv = 0;              // eigenpairs
  long long n = 0;          // rows
  long long columns = 0;    // right-hand sides (solve)
  double shift = 0.0;       // eigenpairs
  double tolerance = 0.0;   // eigenpairs
};

/// A symmetric matrix in compressed rows (global column indices): its upper triangle (upper_rows)
/// or all of it (full_rows).
struct SymmetricRows {
  std::vector<PetscInt> pointers;  // n + 1
  std::vector<PetscInt> columns;
  std::vector<double> values;
};

/// The upper triangle of A in compressed rows, read from A's lower (lower_triangle) or upper
/// triangle; columns ascending in every row.
SymmetricRows upper_rows(const Eigen::SparseMatrix<double>& A, bool lower_triangle) {
  const Eigen::Index n = A.cols();
  SymmetricRows u;
  u.pointers.assign(static_cast<std::size_t>(n) + 1, 0);
  const auto kept = [&](Eigen::Index i, Eigen::Index j) { return lower_triangle ? i >= j : i <= j; };
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      if (kept(it.row(), j)) ++u.pointers[static_cast<std::size_t>(std::min(it.row(), j)) + 1];
    }
  }
  for (std::size_t r = 0; r < static_cast<std::size_t>(n); ++r) u.pointers[r + 1] += u.pointers[r];
  u.columns.resize(static_cast<std::size_t>(u.pointers.back()));
  u.values.resize(u.columns.size());
  std::vector<PetscInt> next(u.pointers.begin(), u.pointers.end() - 1);
  // Column j in order: for the lower triangle row j of the upper one receives ascending i ≥ j; for
  // the upper triangle each row i ≤ j receives column j, and j ascends.
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      if (!kept(it.row(), j)) continue;
      const auto row = static_cast<std::size_t>(std::min(it.row(), j));
      const auto at = static_cast<std::size_t>(next[row]++);
      u.columns[at] = static_cast<PetscInt>(std::max(it.row(), j));
      u.values[at] = it.value();
    }
  }
  return u;
}

/// All of a symmetric matrix in compressed rows, from A's lower (lower_triangle) or upper triangle:
/// what PETSc's AIJ format and its multigrid preconditioners take. Column j of the symmetric
/// matrix is its row j, so Eigen's compressed columns are the rows.
SymmetricRows full_rows(const Eigen::SparseMatrix<double>& A, bool lower_triangle) {
  Eigen::SparseMatrix<double> full = lower_triangle ? Eigen::SparseMatrix<double>(A.selfadjointView<Eigen::Lower>())
                                                    : Eigen::SparseMatrix<double>(A.selfadjointView<Eigen::Upper>());
  full.makeCompressed();
  SymmetricRows u;
  u.pointers.assign(full.outerIndexPtr(), full.outerIndexPtr() + full.cols() + 1);
  u.columns.assign(full.innerIndexPtr(), full.innerIndexPtr() + full.nonZeros());
  u.values.assign(full.valuePtr(), full.valuePtr() + full.nonZeros());
  return u;
}

/// The rows a method distributes: the upper triangle for MUMPS (MPISBAIJ), all for CG (MPIAIJ).
SymmetricRows method_rows(const Eigen::SparseMatrix<double>& A, bool lower_triangle, Method method) {
  return method == Method::mumps ? upper_rows(A, lower_triangle) : full_rows(A, lower_triangle);
}

/// Rows [first[r], first[r + 1]) belong to rank r: n / size each, the first n % size one more.
std::vector<PetscInt> row_ranges(long long n, int size) {
  std::vector<PetscInt> first(static_cast<std::size_t>(size) + 1, 0);
  for (int r = 0; r < size; ++r) {
    first[static_cast<std::size_t>(r) + 1] =
        first[static_cast<std::size_t>(r)] + static_cast<PetscInt>(n / size + (r < n % size ? 1 : 0));
  }
  return first;
}

/// Rank q's share of an n-vector for MPI_Scatterv/Gatherv: counts[q] entries from offsets[q].
struct RowBlocks {
  std::vector<int> counts, offsets;
};
RowBlocks row_blocks(long long n, int size) {
  const auto first = row_ranges(n, size);
  RowBlocks b;
  for (std::size_t q = 0; q + 1 < first.size(); ++q) {
    b.offsets.push_back(first[q]);
    b.counts.push_back(first[q + 1] - first[q]);
  }
  return b;
}

/// A distributed symmetric matrix: this rank's rows (of the upper triangle, or whole: SymmetricRows).
struct LocalRows {
  std::vector<PetscInt> pointers;  // local, from 0
  std::vector<PetscInt> columns;   // global
  std::vector<double> values;
};

struct Factor {
  Method method = Method::mumps;
  Mat matrix = nullptr;   // MPISBAIJ (MUMPS) or MPIAIJ (CG)
  Mat factor = nullptr;   // MUMPS
  KSP ksp = nullptr;      // CG
  LocalRows rows;
  PetscInt first_row = 0;
};

struct World {
  MPI_Comm comm = MPI_COMM_NULL;
  int rank = 0;
  int size = 1;
  bool initialised_mpi = false;
  std::map<int, Factor> factors;
  int next_handle = 0;
};

World* world = nullptr;       // the Session's state
Session* session = nullptr;   // the Session of this process

/// What rank 0 passes to and receives from a command (null on the other ranks).
struct Rank0Data {
  const SymmetricRows* a = nullptr;        // analyze, factorize, eigenpairs (K)
  const SymmetricRows* b = nullptr;        // eigenpairs (M)
  const SymmetricRows* p = nullptr;        // eigenpairs by CG: K − σM, the preconditioner's matrix
  const double* right_hand_sides = nullptr;  // solve: n × columns, column-major
  const double* start_vector = nullptr;      // eigenpairs: n
  Eigen::MatrixXd* solution = nullptr;       // solve
  EigenpairResult* eigen = nullptr;          // eigenpairs
  const double* near_null_space = nullptr;   // analyze (CG), eigenpairs (CG): n × null_vectors
  const double* deflation = nullptr;         // eigenpairs (CG): n × deflation_vectors
  DistributedSolverStatistics* statistics = nullptr;  // analyze, factorize, solve (CG)
  std::string* failure = nullptr;      // factorize, solve: the numerical failure, else empty
  long* negative = nullptr;            // factorize: inertia
};

/// Rank 0 (u given): rank q's entries of `u` (its rows' columns and values) for MPI_Scatterv.
RowBlocks entry_blocks(const SymmetricRows* u, const std::vector<PetscInt>& first) {
  RowBlocks b;
  if (u == nullptr) return b;
  for (std::size_t q = 0; q + 1 < first.size(); ++q) {
    b.offsets.push_back(u->pointers[static_cast<std::size_t>(first[q])]);
    b.counts.push_back(u->pointers[static_cast<std::size_t>(first[q + 1])] - b.offsets.back());
  }
  return b;
}

/// Rank 0's rows of `u` for each rank: scattered so that every rank holds its block (collective).
LocalRows scatter_rows(const World& w, const SymmetricRows* u, long long n) {
  const auto first = row_ranges(n, w.size);
  const auto r = static_cast<std::size_t>(w.rank);
  const PetscInt local = first[r + 1] - first[r];
  const RowBlocks entry = entry_blocks(w.rank == 0 ? u : nullptr, first);
  // The row ends of rank q's rows (global pointers, from pointers[first[q] + 1]), shifted to start
  // from 0 below.
  RowBlocks row_ends = row_blocks(n, w.size);
  for (int& offset : row_ends.offsets) ++offset;
  LocalRows rows;
  std::vector<PetscInt> ends(static_cast<std::size_t>(local));
  MPI_Scatterv(w.rank == 0 ? u->pointers.data() : nullptr, row_ends.counts.data(), row_ends.offsets.data(),
               MPIU_INT, ends.data(), local, MPIU_INT, 0, w.comm);
  int entries = 0;
  MPI_Scatter(entry.counts.data(), 1, MPI_INT, &entries, 1, MPI_INT, 0, w.comm);
  int begin = 0;
  MPI_Scatter(entry.offsets.data(), 1, MPI_INT, &begin, 1, MPI_INT, 0, w.comm);
  rows.pointers.resize(static_cast<std::size_t>(local) + 1);
  rows.pointers[0] = 0;
  for (std::size_t i = 0; i < ends.size(); ++i) rows.pointers[i + 1] = ends[i] - begin;
  rows.columns.resize(static_cast<std::size_t>(entries));
  rows.values.resize(static_cast<std::size_t>(entries));
  MPI_Scatterv(w.rank == 0 ? u->columns.data() : nullptr, entry.counts.data(), entry.offsets.data(),
               MPIU_INT, rows.columns.data(), entries, MPIU_INT, 0, w.comm);
  MPI_Scatterv(w.rank == 0 ? u->values.data() : nullptr, entry.counts.data(), entry.offsets.data(),
               MPI_DOUBLE, rows.values.data(), entries, MPI_DOUBLE, 0, w.comm);
  return rows;
}

/// The values only, into `rows` (its pattern from an earlier scatter_rows).
void scatter_values(const World& w, const SymmetricRows* u, long long n, LocalRows& rows) {
  const RowBlocks entry = entry_blocks(w.rank == 0 ? u : nullptr, row_ranges(n, w.size));
  MPI_Scatterv(w.rank == 0 ? u->values.data() : nullptr, entry.counts.data(), entry.offsets.data(), MPI_DOUBLE,
               rows.values.data(), static_cast<int>(rows.values.size()), MPI_DOUBLE, 0, w.comm);
}

/// The matrix of this rank's rows (collective): MPISBAIJ (block size 1) of the upper triangle for
/// MUMPS, MPIAIJ of whole rows for CG.
Mat create_matrix(const World& w, const LocalRows& rows, long long n, Method method = Method::mumps) {
  const auto local = static_cast<PetscInt>(rows.pointers.size()) - 1;
  const auto global = static_cast<PetscInt>(n);
  Mat m = nullptr;
  if (method == Method::mumps) {
    check(MatCreateMPISBAIJWithArrays(w.comm, 1, local, local, global, global, rows.pointers.data(),
                                      rows.columns.data(), rows.values.data(), &m),
          "MatCreateMPISBAIJWithArrays");
  } else {
    check(MatCreateMPIAIJWithArrays(w.comm, local, local, global, global, rows.pointers.data(),
                                    rows.columns.data(), rows.values.data(), &m),
          "MatCreateMPIAIJWithArrays");
  }
  return m;
}

/// Rank q's share of an n × k block, its rows of every column: counts[q] entries from offsets[q].
RowBlocks column_blocks(const std::vector<PetscInt>& first, long long k) {
  RowBlocks b;
  int at = 0;
  for (std::size_t q = 0; q + 1 < first.size(); ++q) {
    b.offsets.push_back(at);
    at += static_cast<int>(first[q + 1] - first[q]) * static_cast<int>(k);
    b.counts.push_back(at - b.offsets.back());
  }
  return b;
}

/// Rank 0's n × k column-major block, each rank receiving its rows of every column (column after
/// column; collective). Returns this rank's local × k block, column-major.
std::vector<double> scatter_block(const World& w, const double* block, long long n, long long k) {
  const auto first = row_ranges(n, w.size);
  const auto r = static_cast<std::size_t>(w.rank);
  const auto local = static_cast<std::size_t>(first[r + 1] - first[r]);
  std::vector<double> send;
  const RowBlocks b = column_blocks(first, k);
  const std::vector<int>&counts = b.counts, &offsets = b.offsets;
  if (w.rank == 0) {
    send.resize(static_cast<std::size_t>(offsets.back() + counts.back()));
    std::size_t i_send = 0;
    for (std::size_t q = 0; q < counts.size(); ++q)
      for (long long j = 0; j < k; ++j)
        for (PetscInt i = first[q]; i < first[q + 1]; ++i)
          send[i_send++] = block[static_cast<std::size_t>(j) * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)];
  }
  std::vector<double> mine(local * static_cast<std::size_t>(k));
  MPI_Scatterv(send.data(), counts.data(), offsets.data(), MPI_DOUBLE, mine.data(),
               static_cast<int>(mine.size()), MPI_DOUBLE, 0, w.comm);
  return mine;
}

/// The inverse of scatter_block: every rank's local × k block gathered into `out` (n × k) on rank 0.
void gather_block(const World& w, const std::vector<double>& mine, long long n, long long k,
                  Eigen::MatrixXd* out) {
  const auto first = row_ranges(n, w.size);
  const RowBlocks b = column_blocks(first, k);
  const std::vector<int>&counts = b.counts, &offsets = b.offsets;
  std::vector<double> all(w.rank == 0 ? static_cast<std::size_t>(offsets.back() + counts.back()) : 0);
  MPI_Gatherv(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(), counts.data(),
              offsets.data(), MPI_DOUBLE, 0, w.comm);
  if (w.rank != 0) return;
  out->resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(k));
  std::size_t i_all = 0;
  for (std::size_t q = 0; q < counts.size(); ++q)
    for (long long j = 0; j < k; ++j)
      for (PetscInt i = first[q]; i < first[q + 1]; ++i) (*out)(i, static_cast<Eigen::Index>(j)) = all[i_all++];
}

/// Rank 0's n × k block as k distributed vectors, each rank its rows (collective; the caller
/// destroys them).
std::vector<Vec> scatter_vectors(const World& w, const double* block, long long n, int k) {
  const std::vector<double> mine = scatter_block(w, block, n, k);
  const auto local = static_cast<PetscInt>(mine.size() / static_cast<std::size_t>(k));
  std::vector<Vec> v(static_cast<std::size_t>(k), nullptr);
  for (std::size_t j = 0; j < v.size(); ++j) {
    check(VecCreateMPI(w.comm, local, static_cast<PetscInt>(n), &v[j]), "VecCreateMPI");
    double* a = nullptr;
    check(VecGetArray(v[j], &a), "VecGetArray");
    std::copy_n(mine.data() + j * static_cast<std::size_t>(local), local, a);
    check(VecRestoreArray(v[j], &a), "VecRestoreArray");
  }
  return v;
}

/// The near-null space rank 0 sends (n × k, orthonormal columns) attached to `matrix` for GAMG's
/// aggregation (MatSetNearNullSpace; PETSc manual, PCGAMG). Collective; nothing when k = 0.
void attach_near_null_space(const World& w, Mat matrix, const double* vectors, long long n, int k) {
  if (k <= 0) return;
  std::vector<Vec> v = scatter_vectors(w, vectors, n, k);
  MatNullSpace space = nullptr;
  const PetscErrorCode code = MatNullSpaceCreate(w.comm, PETSC_FALSE, k, v.data(), &space);
  for (Vec& x : v) VecDestroy(&x);
  check(code, "MatNullSpaceCreate");
  const PetscErrorCode set = MatSetNearNullSpace(matrix, space);
  MatNullSpaceDestroy(&space);
  check(set, "MatSetNearNullSpace");
}

/// CG (true residual norm, so that `tolerance` bounds ‖b − Ax‖/‖b‖) with the method's
/// preconditioner on `ksp` (collective). PETSC_OPTIONS (e.g. -pc_gamg_threshold 0.02) apply last.
void configure_cg(KSP ksp, Method method, double tolerance, int max_iterations) {
  check(KSPSetType(ksp, KSPCG), "KSPSetType");
  check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
  check(KSPSetTolerances(ksp, tolerance, 0.0, PETSC_DEFAULT, max_iterations), "KSPSetTolerances");
  PC pc = nullptr;
  check(KSPGetPC(ksp, &pc), "KSPGetPC");
  if (method == Method::cg_gamg) {
    check(PCSetType(pc, PCGAMG), "PCSetType");
  } else {
    check(PCSetType(pc, PCHYPRE), "PCSetType");
    check(PCHYPRESetType(pc, "boomeramg"), "PCHYPRESetType");
  }
  check(KSPSetFromOptions(ksp), "KSPSetFromOptions");
}

const char* method_name(Method method) {
  return method == Method::mumps ? "MUMPS" : method == Method::cg_gamg ? "CG/GAMG" : "CG/hypre";
}

/// A vector's entries gathered on rank 0 into `out` (n entries; untouched on other ranks).
void gather_vector(const World& w, Vec v, long long n, double* out) {
  const RowBlocks b = row_blocks(n, w.size);
  const double* local = nullptr;
  check(VecGetArrayRead(v, &local), "VecGetArrayRead");
  MPI_Gatherv(local, b.counts[static_cast<std::size_t>(w.rank)], MPI_DOUBLE, out, b.counts.data(),
              b.offsets.data(), MPI_DOUBLE, 0, w.comm);
  check(VecRestoreArrayRead(v, &local), "VecRestoreArrayRead");
}

double infog_real(Mat factor, PetscInt index) {
  PetscReal value = 0.0;
  if (MatMumpsGetRinfog(factor, index, &value) != 0) return 0.0;
  return static_cast<double>(value);
}

/// Entries of the factors (INFOG(29); MUMPS gives −value·10⁶ when it exceeds an int).
double factor_entries(Mat factor) {
  PetscInt value = 0;
  if (MatMumpsGetInfog(factor, 29, &value) != 0) return 0.0;
  return value < 0 ? -1e6 * static_cast<double>(value) : static_cast<double>(value);
}

/// MUMPS's numerical failure of `factor` as one line, or empty.
std::string factor_failure(Mat factor) {
  MatFactorError error = MAT_FACTOR_NOERROR;
  check(MatFactorGetError(factor, &error), "MatFactorGetError");
  if (error == MAT_FACTOR_NOERROR) return {};
  PetscInt info = 0;
  MatMumpsGetInfog(factor, 1, &info);
  PetscInt info2 = 0;
  MatMumpsGetInfog(factor, 2, &info2);
  const char* kind = error == MAT_FACTOR_NUMERIC_ZEROPIVOT ? "zero or negative pivot"
                     : error == MAT_FACTOR_OUTMEMORY       ? "out of memory"
                                                           : "factorisation failed";
  return fmt::format("MUMPS: {} (INFOG(1) = {}, INFOG(2) = {})", kind, info, info2);
}

// ---- the commands, executed by every rank -------------------------------------------------------

void run_analyze(World& w, const Command& c, Rank0Data* io) {
  const auto start = support::Clock::now();
  Factor f;
  f.method = c.method;
  f.rows = scatter_rows(w, io != nullptr ? io->a : nullptr, c.n);
  f.first_row = row_ranges(c.n, w.size)[static_cast<std::size_t>(w.rank)];
  f.matrix = create_matrix(w, f.rows, c.n, c.method);
  if (c.positive_definite != 0) check(MatSetOption(f.matrix, MAT_SPD, PETSC_TRUE), "MatSetOption");
  if (c.method != Method::mumps) {
    attach_near_null_space(w, f.matrix, io != nullptr ? io->near_null_space : nullptr, c.n, c.null_vectors);
    check(KSPCreate(w.comm, &f.ksp), "KSPCreate");
    configure_cg(f.ksp, c.method, c.cg_tolerance, c.cg_max_iterations);
  } else {
    check(MatGetFactor(f.matrix, MATSOLVERMUMPS, MAT_FACTOR_CHOLESKY, &f.factor), "MatGetFactor");
    // The count of negative pivots (INFOG(12)) must cover every front, the root one too, so no
    // ScaLAPACK on the root node (ICNTL(13) = 1; MUMPS 5.5 user guide §6.1): in SPD mode it is how
    // an indefinite matrix is detected at all (MUMPS's SYM = 1 factors one without complaint: found
    // by validation/petsc/solvers.cpp), in the general mode it is the inertia.
    check(MatMumpsSetIcntl(f.factor, 13, 1), "MatMumpsSetIcntl");
    MatFactorInfo info;
    check(MatFactorInfoInitialize(&info), "MatFactorInfoInitialize");
    check(MatCholeskyFactorSymbolic(f.factor, f.matrix, nullptr, &info), "MatCholeskyFactorSymbolic");
  }
  w.factors[c.handle] = std::move(f);
  if (io != nullptr) {
    io->statistics->rows = c.n;
    io->statistics->matrix_nonzeros = static_cast<long>(io->a->columns.size());
    io->statistics->ranks = w.size;
    io->statistics->method = method_name(c.method);
    io->statistics->analyze_seconds = support::seconds_since(start);
  }
}

void run_factorize(World& w, const Command& c, Rank0Data* io) {
  const auto start = support::Clock::now();
  Factor& f = w.factors.at(c.handle);
  scatter_values(w, io != nullptr ? io->a : nullptr, c.n, f.rows);
  const auto local = static_cast<PetscInt>(f.rows.pointers.size()) - 1;
  for (PetscInt i = 0; i < local; ++i) {
    const PetscInt row = f.first_row + i;
    const PetscInt begin = f.rows.pointers[static_cast<std::size_t>(i)];
    const PetscInt count = f.rows.pointers[static_cast<std::size_t>(i) + 1] - begin;
    check(MatSetValues(f.matrix, 1, &row, count, f.rows.columns.data() + begin,
                       f.rows.values.data() + begin, INSERT_VALUES),
          "MatSetValues");
  }
  check(MatAssemblyBegin(f.matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  check(MatAssemblyEnd(f.matrix, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  if (f.method != Method::mumps) {
    // The multigrid hierarchy for the new values. Its failures are collective (every rank gets
    // the same code), so every rank records them instead of aborting its serve() loop.
    std::string failure;
    try {
      check(KSPSetOperators(f.ksp, f.matrix, f.matrix), "KSPSetOperators");
      check(KSPSetUp(f.ksp), "KSPSetUp");
    } catch (const std::exception& e) {
      failure = e.what();
    }
    if (io != nullptr) {
      *io->failure = failure;
      *io->negative = -1;
      io->statistics->factorize_seconds = support::seconds_since(start);
    }
    return;
  }
  MatFactorInfo info;
  check(MatFactorInfoInitialize(&info), "MatFactorInfoInitialize");
  check(MatCholeskyFactorNumeric(f.factor, f.matrix, &info), "MatCholeskyFactorNumeric");
  std::string failure = factor_failure(f.factor);
  PetscInt negative = -1;
  if (failure.empty()) {
    // Only the negative count: zero and positive counts need MUMPS's null-pivot detection
    // (ICNTL(24) = 1), which PETSc otherwise refuses to report.
    check(MatGetInertia(f.factor, &negative, nullptr, nullptr), "MatGetInertia");
    if (c.positive_definite != 0 && negative > 0)
      failure = fmt::format("matrix not positive definite ({} negative pivots in MUMPS's LDL^T)", negative);
  }
  if (io != nullptr) {
    *io->failure = failure;
    *io->negative = static_cast<long>(negative);
    io->statistics->factor_entries = factor_entries(f.factor);
    io->statistics->factor_flops = infog_real(f.factor, 3);
    io->statistics->factorize_seconds = support::seconds_since(start);
  }
}

/// Rank 0's right-hand sides solved with the factor or by CG, one column at a time (collective).
/// CG failures (PETSc's KSPConvergedReason, the same on every rank) end the loop and are reported.
void run_solve(World& w, const Command& c, Rank0Data* io) {
  Factor& f = w.factors.at(c.handle);
  const auto first = row_ranges(c.n, w.size);
  const auto r = static_cast<std::size_t>(w.rank);
  const PetscInt local = first[r + 1] - first[r];
  const auto k = static_cast<PetscInt>(c.columns);
  const std::vector<double> b = scatter_block(w, io != nullptr ? io->right_hand_sides : nullptr, c.n, k);
  std::vector<double> x(b.size(), 0.0);
  std::string failure;
  long iterations = 0;
  if (f.method == Method::mumps) {
    Mat bm = nullptr, xm = nullptr;
    check(MatCreateDense(w.comm, local, PETSC_DECIDE, static_cast<PetscInt>(c.n), k,
                         const_cast<double*>(b.data()), &bm),
          "MatCreateDense");
    check(MatCreateDense(w.comm, local, PETSC_DECIDE, static_cast<PetscInt>(c.n), k, x.data(), &xm),
          "MatCreateDense");
    const PetscErrorCode code = MatMatSolve(f.factor, bm, xm);
    MatDestroy(&bm);
    MatDestroy(&xm);
    check(code, "MatMatSolve");
  } else {
    for (PetscInt j = 0; j < k && failure.empty(); ++j) {
      Vec bv = nullptr, xv = nullptr;
      const std::size_t offset = static_cast<std::size_t>(j) * static_cast<std::size_t>(local);
      check(VecCreateMPIWithArray(w.comm, 1, local, static_cast<PetscInt>(c.n), b.data() + offset, &bv),
            "VecCreateMPIWithArray");
      check(VecCreateMPIWithArray(w.comm, 1, local, static_cast<PetscInt>(c.n), x.data() + offset, &xv),
            "VecCreateMPIWithArray");
      const PetscErrorCode code = KSPSolve(f.ksp, bv, xv);
      KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
      PetscInt its = 0;
      KSPGetConvergedReason(f.ksp, &reason);
      KSPGetIterationNumber(f.ksp, &its);
      VecDestroy(&bv);
      VecDestroy(&xv);
      iterations += its;
      if (code != 0) {
        failure = fmt::format("PETSc KSPSolve failed (error {}) at right-hand side {} of {}", code, j + 1, k);
      } else if (reason < 0) {
        failure = fmt::format("{}: no convergence at right-hand side {} of {}: {} after {} iterations "
                              "(relative residual tolerance {:.1e}){}",
                              method_name(f.method), j + 1, k, KSPConvergedReasons[reason], its,
                              c.cg_tolerance,
                              reason == KSP_DIVERGED_INDEFINITE_MAT || reason == KSP_DIVERGED_INDEFINITE_PC
                                  ? " - the matrix is not positive definite"
                                  : "");
      }
    }
  }
  gather_block(w, x, c.n, k, io != nullptr ? io->solution : nullptr);
  if (io != nullptr) {
    if (io->failure != nullptr) *io->failure = failure;
    if (io->statistics != nullptr) {
      io->statistics->iterations += iterations;
      io->statistics->solved_columns += k;
    }
  }
}

void release(World& w, int handle) {
  auto it = w.factors.find(handle);
  if (it == w.factors.end()) return;
  KSPDestroy(&it->second.ksp);
  MatDestroy(&it->second.factor);
  MatDestroy(&it->second.matrix);
  w.factors.erase(it);
}

void run_eigenpairs(World& w, const Command& c, Rank0Data* io) {
  const auto start = support::Clock::now();
  const bool iterative = c.method != Method::mumps;
  LocalRows k_rows = scatter_rows(w, io != nullptr ? io->a : nullptr, c.n);
  LocalRows m_rows = scatter_rows(w, io != nullptr ? io->b : nullptr, c.n);
  LocalRows p_rows;
  if (iterative) p_rows = scatter_rows(w, io != nullptr ? io->p : nullptr, c.n);
  Mat K = create_matrix(w, k_rows, c.n, c.method);
  Mat M = create_matrix(w, m_rows, c.n, c.method);
  Mat P = iterative ? create_matrix(w, p_rows, c.n, c.method) : nullptr;
  EPS eps = nullptr;
  Vec start_vector = nullptr, x = nullptr;
  const auto cleanup = [&] {
    EPSDestroy(&eps);
    VecDestroy(&start_vector);
    VecDestroy(&x);
    MatDestroy(&K);
    MatDestroy(&M);
    MatDestroy(&P);
  };
  try {
    check(EPSCreate(w.comm, &eps), "EPSCreate");
    check(EPSSetOperators(eps, K, M), "EPSSetOperators");
    check(EPSSetProblemType(eps, EPS_GHEP), "EPSSetProblemType");
    check(EPSSetType(eps, EPSKRYLOVSCHUR), "EPSSetType");
    check(EPSSetDimensions(eps, c.count, c.ncv > 0 ? c.ncv : PETSC_DEFAULT, PETSC_DEFAULT),
          "EPSSetDimensions");
    check(EPSSetTolerances(eps, c.tolerance, c.max_iterations), "EPSSetTolerances");
    check(EPSSetTarget(eps, c.shift), "EPSSetTarget");
    check(EPSSetWhichEigenpairs(eps, EPS_TARGET_MAGNITUDE), "EPSSetWhichEigenpairs");
    ST st = nullptr;
    check(EPSGetST(eps, &st), "EPSGetST");
    check(STSetType(st, STSINVERT), "STSetType");
    // K and M are given on the union of their patterns (distributed_eigenpairs), so K − σM keeps it.
    check(STSetMatStructure(st, SAME_NONZERO_PATTERN), "STSetMatStructure");
    KSP ksp = nullptr;
    check(STGetKSP(st, &ksp), "STGetKSP");
    PC pc = nullptr;
    check(KSPGetPC(ksp, &pc), "KSPGetPC");
    if (iterative) {
      // (K − σM)⁻¹ by CG, preconditioned by multigrid built on our own copy of K − σM, which
      // carries the near-null space (the copy SLEPc forms would not).
      check(MatSetOption(P, MAT_SPD, PETSC_TRUE), "MatSetOption");
      attach_near_null_space(w, P, io != nullptr ? io->near_null_space : nullptr, c.n, c.null_vectors);
      check(STSetPreconditionerMat(st, P), "STSetPreconditionerMat");
      configure_cg(ksp, c.method, c.cg_tolerance, c.cg_max_iterations);
    } else {
      check(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
      check(PCSetType(pc, PCCHOLESKY), "PCSetType");
      check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    }
    // The starting vector ARPACK's path uses (modal/modes.cpp), sent from rank 0.
    check(MatCreateVecs(K, &start_vector, &x), "MatCreateVecs");
    {
      const RowBlocks b = row_blocks(c.n, w.size);
      double* local = nullptr;
      check(VecGetArray(start_vector, &local), "VecGetArray");
      MPI_Scatterv(io != nullptr ? io->start_vector : nullptr, b.counts.data(), b.offsets.data(),
                   MPI_DOUBLE, local, b.counts[static_cast<std::size_t>(w.rank)], MPI_DOUBLE, 0,
                   w.comm);
      check(VecRestoreArray(start_vector, &local), "VecRestoreArray");
    }
    check(EPSSetInitialSpace(eps, 1, &start_vector), "EPSSetInitialSpace");
    if (c.deflation_vectors > 0) {
      // K's null space (the rigid-body motions of a free-free model, distributed_eigenpairs):
      // the Krylov basis is kept M-orthogonal to it (EPSSetDeflationSpace).
      std::vector<Vec> v = scatter_vectors(w, io != nullptr ? io->deflation : nullptr, c.n, c.deflation_vectors);
      const PetscErrorCode code = EPSSetDeflationSpace(eps, c.deflation_vectors, v.data());
      for (Vec& vec : v) VecDestroy(&vec);
      check(code, "EPSSetDeflationSpace");
    }
    // The user's PETSc options last (PETSC_OPTIONS="-eps_ncv 60 -mat_mumps_icntl_14 50 ..."):
    // docs/distributed.md §5.
    check(EPSSetFromOptions(eps), "EPSSetFromOptions");
    check(EPSSetUp(eps), "EPSSetUp");
    Mat factor = nullptr;
    if (!iterative) check(PCFactorGetMatrix(pc, &factor), "PCFactorGetMatrix");
    const double factored = support::seconds_since(start);
    const auto solve_start = support::Clock::now();
    check(EPSSolve(eps), "EPSSolve");
    PetscInt converged = 0, iterations = 0;
    check(EPSGetConverged(eps, &converged), "EPSGetConverged");
    check(EPSGetIterationNumber(eps, &iterations), "EPSGetIterationNumber");
    const PetscInt kept = std::min<PetscInt>(converged, c.count);
    EigenpairResult* r = io != nullptr ? io->eigen : nullptr;
    if (r != nullptr) {
      r->eigenvalues.resize(kept);
      r->vectors.resize(static_cast<Eigen::Index>(c.n), kept);
    }
    for (PetscInt j = 0; j < kept; ++j) {
      PetscScalar lambda = 0.0;
      check(EPSGetEigenpair(eps, j, &lambda, nullptr, x, nullptr), "EPSGetEigenpair");
      gather_vector(w, x, c.n, r != nullptr ? r->vectors.col(j).data() : nullptr);
      if (r != nullptr) r->eigenvalues(j) = static_cast<double>(lambda);
    }
    if (r != nullptr) {
      r->ok = kept > 0;
      r->iterations = static_cast<int>(iterations);
      r->ranks = w.size;
      r->factor.rows = c.n;
      r->factor.matrix_nonzeros = static_cast<long>(io->a->columns.size());
      r->factor.ranks = w.size;
      r->factor.method = method_name(c.method);
      if (iterative) {
        PetscInt total = 0;
        KSPGetTotalIterations(ksp, &total);
        r->factor.iterations = static_cast<long>(total);
      } else {
        r->factor.factor_entries = factor_entries(factor);
        r->factor.factor_flops = infog_real(factor, 3);
      }
      r->factor_seconds = factored;
      r->solve_seconds = support::seconds_since(solve_start);
      if (kept < c.count) {
        r->message = fmt::format("SLEPc Krylov-Schur: {} of {} eigenpairs converged in {} restarts",
                                 kept, c.count, iterations);
      }
    }
  } catch (const std::exception& e) {
    // PETSc's and SLEPc's failures here are collective (every rank sees the same code): rank 0
    // reports it, the others carry on serving.
    cleanup();
    if (io != nullptr) {
      io->eigen->ok = false;
      io->eigen->message = e.what();
    }
    return;
  }
  cleanup();
}

void execute(World& w, const Command& c, Rank0Data* io) {
  switch (c.op) {
    case Op::analyze:
      run_analyze(w, c, io);
      return;
    case Op::factorize:
      run_factorize(w, c, io);
      return;
    case Op::solve:
      run_solve(w, c, io);
      return;
    case Op::release:
      release(w, c.handle);
      return;
    case Op::eigenpairs:
      run_eigenpairs(w, c, io);
      return;
    case Op::quit:
      return;
  }
}

/// The command from rank 0 (every rank calls it; rank 0 with its command in `c`). The other ranks
/// wait without spinning: between commands rank 0 computes for seconds to hours (contact laws,
/// harmonic balance on its OpenMP threads), and a blocking broadcast would keep a core of every
/// waiting rank busy-polling meanwhile. So a non-blocking broadcast, tested with sleeps growing from
/// 50 µs to 5 ms: at most ~5 ms of latency per command, against factorisations of seconds.
void broadcast(const World& w, Command& c) {
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Ibcast(&c, sizeof c, MPI_BYTE, 0, w.comm, &request);
  if (w.rank == 0) {
    MPI_Wait(&request, MPI_STATUS_IGNORE);
    return;
  }
  auto pause = std::chrono::microseconds(50);
  for (int done = 0;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done != 0) return;
    std::this_thread::sleep_for(pause);
    pause = std::min(2 * pause, std::chrono::microseconds(5000));
  }
}

/// Rank 0: broadcasts `c`, then executes it with the other ranks.
void command(const Command& c, Rank0Data* io) {
  if (world == nullptr)
    throw std::logic_error("the PETSc solvers need a petsc::Session (fe/petsc_solvers.hpp)");
  Command copy = c;
  broadcast(*world, copy);
  execute(*world, copy, io);
}

}  // namespace

bool built() { return true; }

Session::Session([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
  if (session != nullptr) throw std::logic_error("petsc::Session: one per process");
  auto w = std::make_unique<World>();
  int mpi_ready = 0;
  MPI_Initialized(&mpi_ready);
  w->initialised_mpi = mpi_ready == 0;
  // PETSc's own signal handlers would replace the program's (SIGINT stops a run cleanly); errors
  // come back as codes and become exceptions (check()).
  PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
  check(SlepcInitializeNoArguments(), "SlepcInitialize");
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  // GAMG's Chebyshev smoothers bound the spectrum of each level by a few CG steps times a safety
  // factor (1.1 by default): on the 93 930-DOF lap on two ranks that bound fell short, the smoother
  // amplified the top of the spectrum and CG stopped with DIVERGED_INDEFINITE_PC in the first
  // preload solve (also with 50 estimation steps); with 1.5 it converged (docs/distributed.md §2a).
  // A default only: PETSC_OPTIONS may set its own. "-st_": the modes' inner solver.
  for (const char* name : {"-mg_levels_ksp_chebyshev_esteig", "-st_mg_levels_ksp_chebyshev_esteig"}) {
    PetscBool given = PETSC_FALSE;
    PetscOptionsHasName(nullptr, nullptr, name, &given);
    if (given == PETSC_FALSE) PetscOptionsSetValue(nullptr, name, "0,0.05,0,1.5");
  }
  MPI_Comm_dup(PETSC_COMM_WORLD, &w->comm);
  MPI_Comm_rank(w->comm, &w->rank);
  MPI_Comm_size(w->comm, &w->size);
  world = w.release();
  session = this;
}

Session::~Session() {
  if (world == nullptr) return;
  if (world->rank == 0) {
    Command quit;
    quit.op = Op::quit;
    broadcast(*world, quit);
  }
  for (auto& [handle, f] : world->factors) {
    KSPDestroy(&f.ksp);
    MatDestroy(&f.factor);
    MatDestroy(&f.matrix);
  }
  MPI_Comm_free(&world->comm);
  delete world;
  world = nullptr;
  session = nullptr;
  SlepcFinalize();  // finalises MPI too when PETSc initialised it
}

int Session::rank() const { return world->rank; }
int Session::size() const { return world->size; }
Session* Session::current() { return session; }

void Session::serve() {
  if (world->rank == 0) return;
  // mpirun forwards a Ctrl-C (SIGINT) and SIGTERM to every rank: rank 0 stops the run the way a
  // serial run stops (summary "interrupted", exit 130/143) and ends the session, which releases the
  // ranks serving it. Dying here instead would abort rank 0 in its next collective call. If rank 0
  // dies, mpirun ends this rank with SIGKILL.
  std::signal(SIGINT, SIG_IGN);
  std::signal(SIGTERM, SIG_IGN);
  while (true) {
    Command c;
    broadcast(*world, c);
    if (c.op == Op::quit) return;
    try {
      execute(*world, c, nullptr);
    } catch (const std::exception& e) {
      // A failure on this rank alone would leave rank 0 waiting in a collective call.
      std::fprintf(stderr, "jointhb: rank %d: %s\n", world->rank, e.what());
      MPI_Abort(world->comm, 1);
    }
  }
}

namespace {

/// An orthonormal basis of span(V) (MatNullSpaceCreate wants orthonormal vectors): the first
/// rank(V) columns of Q of V's column-pivoted QR.
Eigen::MatrixXd orthonormal_basis(const Eigen::MatrixXd& V) {
  if (V.cols() == 0) return V;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(V);
  const Eigen::Index rank = qr.rank();
  Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(V.rows(), rank);
  return Q;
}

/// The near-null space to send with a command: orthonormal columns of `settings`', or none when it
/// does not match n rows (then GAMG falls back to the constant vector).
Eigen::MatrixXd near_null_space_for(const SparseCholeskyOptions::Iterative& settings, Eigen::Index n) {
  if (settings.near_null_space.rows() != n) return {};
  return orthonormal_basis(settings.near_null_space);
}

/// K's null space within the span of the near-null vectors (the rigid-body motions a free-free
/// model keeps), with its eigenpairs by Rayleigh–Ritz: what the iterative eigen path deflates.
struct RigidSubspace {
  Eigen::MatrixXd basis;       // n × d, M-orthonormal
  Eigen::VectorXd eigenvalues;  // d Rayleigh quotients (round-off level)
};

/// Why: shift-and-invert by CG is accurate only relative to the largest eigenvalue of (K − σM)⁻¹M,
/// 1/(λ − σ). With rigid-body modes at λ = 0 and σ a little below, that is 1/|σ|, and the elastic
/// modes (1/(λ − σ) some 10⁵ times smaller) came out with relative eigenvalue errors of 1e-5 on the
/// lap (case 08) at inner tolerances of 1e-12 and 1e-14 alike, while a clamped model (case 07)
/// agreed with ARPACK to 2e-12. Deflating the exact null space removes that scale.
/// d = the eigenvalues of QᵀKQ (Q an orthonormal basis of the near-null vectors) at or below
/// 1e-12·max|K_ii|: for symmetric positive semi-definite K, zᵀQᵀKQz = ‖K^{1/2}Qz‖², so those
/// directions are null directions of K to round-off. A constrained model gives d = 0 (no change).
RigidSubspace rigid_subspace(const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& M,
                             const Eigen::MatrixXd& near_null) {
  RigidSubspace r;
  if (near_null.rows() != K.rows() || near_null.cols() == 0) return r;
  const Eigen::MatrixXd Q = orthonormal_basis(near_null);
  const Eigen::MatrixXd KQ = K * Q;
  Eigen::MatrixXd QKQ = Q.transpose() * KQ;
  QKQ = 0.5 * (QKQ + QKQ.transpose()).eval();
  const double scale = K.diagonal().cwiseAbs().maxCoeff();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> small(QKQ);
  Eigen::Index d = 0;
  while (d < QKQ.rows() && small.eigenvalues()(d) <= 1e-12 * scale) ++d;
  if (d == 0) return r;
  const Eigen::MatrixXd R = Q * small.eigenvectors().leftCols(d);
  // Rayleigh–Ritz on span(R): (RᵀKR) w = λ (RᵀMR) w, w M-normalised.
  Eigen::MatrixXd RKR = R.transpose() * (K * R), RMR = R.transpose() * (M * R);
  RKR = 0.5 * (RKR + RKR.transpose()).eval();
  RMR = 0.5 * (RMR + RMR.transpose()).eval();
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(RKR, RMR);
  r.basis = R * ritz.eigenvectors();
  r.eigenvalues = ritz.eigenvalues();
  return r;
}

/// The rigid pairs first, then SLEPc's (the caller sorts by eigenvalue).
void prepend_rigid_pairs(const RigidSubspace& rigid, EigenpairResult& result) {
  const Eigen::Index d = rigid.basis.cols(), m = result.eigenvalues.size();
  Eigen::VectorXd values(d + m);
  values << rigid.eigenvalues, result.eigenvalues;
  Eigen::MatrixXd vectors(rigid.basis.rows(), d + m);
  vectors.leftCols(d) = rigid.basis;
  if (m > 0) vectors.rightCols(m) = result.vectors;
  result.eigenvalues = std::move(values);
  result.vectors = std::move(vectors);
  result.deflated = static_cast<int>(d);
  result.ok = result.ok || d > 0;
}

Method method_of(const SparseCholeskyOptions::Iterative& settings) {
  return settings.preconditioner == SparseCholeskyOptions::Iterative::Preconditioner::gamg ? Method::cg_gamg
                                                                                            : Method::cg_hypre;
}

}  // namespace

DistributedSolver::DistributedSolver(bool positive_definite, bool lower_triangle)
    : positive_definite_(positive_definite), lower_(lower_triangle) {
  if (world == nullptr)
    throw std::logic_error(
        "the mumps linear solver needs a petsc::Session (jointhb run --linear-algebra petsc)");
  handle_ = world->next_handle++;
}

DistributedSolver::DistributedSolver(const SparseCholeskyOptions::Iterative& settings, bool lower_triangle)
    : method_(static_cast<int>(method_of(settings))), lower_(lower_triangle), iterative_(settings) {
  if (world == nullptr)
    throw std::logic_error(
        "the cg linear solver needs a petsc::Session (jointhb run --linear-algebra petsc-gamg)");
  if (!(settings.relative_tolerance > 0.0 && settings.relative_tolerance < 1.0))
    throw std::invalid_argument("cg: relative_tolerance must lie in (0, 1)");
  if (settings.max_iterations < 1) throw std::invalid_argument("cg: max_iterations must be >= 1");
  handle_ = world->next_handle++;
}

DistributedSolver::~DistributedSolver() {
  if (world == nullptr || handle_ < 0 || world->factors.count(handle_) == 0) return;
  Command c;
  c.op = Op::release;
  c.handle = handle_;
  try {
    command(c, nullptr);
  } catch (...) {  // a destructor must not throw; the factor is freed at the session's end
  }
}

void DistributedSolver::analyze(const Eigen::SparseMatrix<double>& A) {
  if (world->factors.count(handle_) != 0) {
    Command r;
    r.op = Op::release;
    r.handle = handle_;
    command(r, nullptr);
  }
  factorized_ = false;
  const auto method = static_cast<Method>(method_);
  const SymmetricRows u = method_rows(A, lower_, method);
  Command c;
  c.op = Op::analyze;
  c.handle = handle_;
  c.method = method;
  c.positive_definite = positive_definite_ ? 1 : 0;
  c.n = A.rows();
  Rank0Data io;
  io.a = &u;
  Eigen::MatrixXd null_space;
  if (method != Method::mumps) {
    null_space = near_null_space_for(iterative_, A.rows());
    c.null_vectors = static_cast<int>(null_space.cols());
    c.cg_tolerance = iterative_.relative_tolerance;
    c.cg_max_iterations = iterative_.max_iterations;
    io.near_null_space = null_space.data();
  }
  statistics_ = {};
  io.statistics = &statistics_;
  command(c, &io);
}

void DistributedSolver::factorize(const Eigen::SparseMatrix<double>& A) {
  if (world->factors.count(handle_) == 0) analyze(A);
  factorized_ = false;
  const auto method = static_cast<Method>(method_);
  const SymmetricRows u = method_rows(A, lower_, method);
  if (static_cast<long>(u.columns.size()) != statistics_.matrix_nonzeros ||
      A.rows() != statistics_.rows)
    throw std::invalid_argument(
        "DistributedSolver::factorize: A's pattern differs from the analysed one");
  Command c;
  c.op = Op::factorize;
  c.handle = handle_;
  c.method = method;
  c.positive_definite = positive_definite_ ? 1 : 0;
  c.n = A.rows();
  std::string failure;
  Rank0Data io;
  io.a = &u;
  io.statistics = &statistics_;
  io.failure = &failure;
  io.negative = &negative_;
  command(c, &io);
  if (!failure.empty()) throw std::runtime_error(failure);
  factorized_ = true;
}

Eigen::MatrixXd DistributedSolver::solve(const Eigen::Ref<const Eigen::MatrixXd>& B) {
  if (!factorized_) throw std::logic_error("DistributedSolver::solve: no valid factor");
  const Eigen::MatrixXd packed = B;  // contiguous columns
  Command c;
  c.op = Op::solve;
  c.handle = handle_;
  c.method = static_cast<Method>(method_);
  c.cg_tolerance = iterative_.relative_tolerance;
  c.n = B.rows();
  c.columns = B.cols();
  Eigen::MatrixXd x;
  std::string failure;
  Rank0Data io;
  io.right_hand_sides = packed.data();
  io.solution = &x;
  io.failure = &failure;
  io.statistics = &statistics_;
  command(c, &io);
  if (!failure.empty()) throw std::runtime_error(failure);
  return x;
}

long DistributedSolver::negative_pivots() const {
  return factorized_ && !positive_definite_ && method_ == 0 ? negative_ : -1;
}

const DistributedSolverStatistics& DistributedSolver::statistics() const { return statistics_; }

EigenpairResult distributed_eigenpairs(const Eigen::SparseMatrix<double>& K,
                                       const Eigen::SparseMatrix<double>& M,
                                       const EigenpairOptions& options) {
  const Method method = options.iterative ? method_of(*options.iterative) : Method::mumps;
  // The same pattern for both (the union, explicit zeros kept), so that SLEPc forms K − σM in place.
  const Eigen::SparseMatrix<double> k_union = K + 0.0 * M;
  const Eigen::SparseMatrix<double> m_union = M + 0.0 * K;
  const SymmetricRows ku = method_rows(k_union, true, method);
  const SymmetricRows mu = method_rows(m_union, true, method);
  SymmetricRows pu;
  Eigen::MatrixXd null_space;
  // ARPACK's starting vector (modal/modes.cpp): uniform in [−1, 1) from mt19937_64(seed).
  std::vector<double> start(static_cast<std::size_t>(K.rows()));
  std::mt19937_64 random(options.seed);
  for (double& r : start) r = static_cast<double>(random() >> 11) * 0x1.0p-52 - 1.0;
  Command c;
  c.op = Op::eigenpairs;
  c.method = method;
  c.n = K.rows();
  c.count = options.count;
  c.shift = options.shift;
  c.tolerance = options.tolerance;
  c.max_iterations = options.max_iterations;
  c.ncv = options.ncv;
  EigenpairResult result;
  result.shift_used = options.shift;
  Rank0Data io;
  io.a = &ku;
  io.b = &mu;
  RigidSubspace rigid;
  if (options.iterative) {
    rigid = rigid_subspace(K, M, options.iterative->near_null_space);
    c.deflation_vectors = static_cast<int>(rigid.basis.cols());
    c.count = options.count - c.deflation_vectors;
    io.deflation = rigid.basis.data();
    pu = full_rows(Eigen::SparseMatrix<double>(k_union - options.shift * m_union), true);
    null_space = near_null_space_for(*options.iterative, K.rows());
    c.null_vectors = static_cast<int>(null_space.cols());
    // Inexact inner solves limit the eigenpairs' accuracy (SLEPc users' manual, §3.4.1): two
    // orders below the eigensolver's tolerance.
    c.cg_tolerance = std::min(options.iterative->relative_tolerance, 0.01 * options.tolerance);
    c.cg_max_iterations = options.iterative->max_iterations;
    io.p = &pu;
    io.near_null_space = null_space.data();
  }
  io.start_vector = start.data();
  io.eigen = &result;
  if (c.count > 0 && c.deflation_vectors > 0) {
    // With K's null space deflated, a shift just below 0 still leaves K − σM nearly singular on it,
    // and the inexact inner solves then cost the elastic eigenpairs accuracy: 2e-6 relative on a
    // free-free brick at σ = −1 against 6e-14 at σ = −1e8 (validation/petsc/solvers.cpp, §7). Every
    // eigenvalue lies above σ (K − σM is positive definite), so any σ' ≤ σ has the same `count`
    // nearest ones: a first, loose pass finds the lowest elastic eigenvalue λ₁, and the solve runs
    // at σ' = min(σ, −λ₁/2), where (K − σ'M) is as well conditioned as a shift below λ₁ allows.
    Command first = c;
    first.count = 1;
    first.tolerance = 1e-6;
    first.cg_tolerance = 1e-8;
    EigenpairResult estimate;
    Rank0Data first_io = io;
    first_io.eigen = &estimate;
    command(first, &first_io);
    if (estimate.eigenvalues.size() > 0 && estimate.eigenvalues(0) > 0.0)
      c.shift = std::min(c.shift, -0.5 * estimate.eigenvalues(0));
    result.shift_used = c.shift;
  }
  if (c.count > 0) command(c, &io);
  else result.ok = true;
  if (rigid.basis.cols() > 0) prepend_rigid_pairs(rigid, result);
  return result;
}

#endif

}  // namespace jointhb::fe::petsc
