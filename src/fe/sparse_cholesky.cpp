#include "jointhb/fe/sparse_cholesky.hpp"

#include <cholmod.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "../support/stopwatch.hpp"
#include "jointhb/fe/petsc_solvers.hpp"

namespace jointhb::fe {

namespace {

const char* ordering_name(int ordering) {
  switch (ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_GIVEN:
      return "given";
    case CHOLMOD_AMD:
      return "AMD";
    case CHOLMOD_METIS:
      return "METIS";
    case CHOLMOD_NESDIS:
      return "NESDIS";
    case CHOLMOD_COLAMD:
      return "COLAMD";
    case CHOLMOD_POSTORDERED:
      return "postordered";
    default:
      return "?";
  }
}

std::string status_text(int status) {
  switch (status) {
    case CHOLMOD_OK:
      return "CHOLMOD_OK";
    case CHOLMOD_NOT_INSTALLED:
      return "CHOLMOD_NOT_INSTALLED";
    case CHOLMOD_OUT_OF_MEMORY:
      return "CHOLMOD_OUT_OF_MEMORY";
    case CHOLMOD_TOO_LARGE:
      return "CHOLMOD_TOO_LARGE";
    case CHOLMOD_INVALID:
      return "CHOLMOD_INVALID";
    case CHOLMOD_GPU_PROBLEM:
      return "CHOLMOD_GPU_PROBLEM";
    case CHOLMOD_NOT_POSDEF:
      return "CHOLMOD_NOT_POSDEF";
    case CHOLMOD_DSMALL:
      return "CHOLMOD_DSMALL";
    default:
      return "status " + std::to_string(status);
  }
}

}  // namespace

const char* to_string(LinearSolver backend) {
  switch (backend) {
    case LinearSolver::mumps:
      return "mumps";
    case LinearSolver::cg:
      return "cg";
    case LinearSolver::cholmod:
      break;
  }
  return "cholmod";
}

const char* to_string(IterativeSettings::Preconditioner preconditioner) {
  return preconditioner == IterativeSettings::Preconditioner::hypre ? "hypre" : "gamg";
}

std::string SparseCholeskyStatistics::brief() const {
  if (factor_entries == 0 && (iterations > 0 || solved_columns > 0 || ordering.rfind("CG", 0) == 0)) {
    // The cg backend: no factor; its setup and Krylov iterations instead.
    // (SLEPc's inner solves count their iterations but are no right-hand sides of ours.)
    const std::string over = solved_columns > 0 ? fmt::format(" for {} right-hand sides", solved_columns)
                                                : std::string(" (eigensolver inner solves)");
    return fmt::format("n={}, nnz(A)={}, {}, setup {:.3f} s, {} iterations{}", rows, matrix_nonzeros,
                       ordering, factorize_seconds, iterations, over);
  }
  const double fill =
      matrix_nonzeros > 0 ? factor_nonzeros / static_cast<double>(matrix_nonzeros) : 0.0;
  char line[256];
  std::snprintf(line, sizeof line,
                "n=%ld, nnz(A)=%ld, nnz(L)=%.0f (fill x%.1f, %ld stored), %.3g Gflop, ordering %s, "
                "analyze %.3f s, factorize %.3f s",
                rows, matrix_nonzeros, factor_nonzeros, fill, factor_entries, factor_flops * 1e-9,
                ordering.c_str(), analyze_seconds, factorize_seconds);
  return line;
}

struct SparseCholesky::Impl {
  Options options;
  // The mumps backend (fe/petsc_solvers.hpp); null for CHOLMOD.
  std::unique_ptr<petsc::DistributedSolver> distributed;
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  bool valid = false;  // a numeric factor of the analysed pattern exists
  // The analysed pattern, in CHOLMOD's long indices (Eigen's are int).
  std::vector<SuiteSparse_long> outer, inner;
  SparseCholeskyStatistics statistics;
  // Reused by cholmod_l_solve2 across calls (allocated on first use, resized when k changes).
  cholmod_dense* solution = nullptr;
  cholmod_dense* work_y = nullptr;
  cholmod_dense* work_e = nullptr;

  explicit Impl(Options o) : options(o) {
    if (options.backend == Options::Backend::mumps) {
      distributed = std::make_unique<petsc::DistributedSolver>(
          options.method == Options::Method::supernodal_llt,
          options.triangle == Options::Triangle::lower);
    } else if (options.backend == Options::Backend::cg) {
      if (options.method != Options::Method::supernodal_llt)
        throw std::invalid_argument(
            "SparseCholesky: the cg backend solves positive definite systems only (no inertia): "
            "use supernodal_llt, or the mumps backend for LDL^T");
      distributed = std::make_unique<petsc::DistributedSolver>(
          options.iterative, options.triangle == Options::Triangle::lower);
    }
    cholmod_l_start(&common);
    common.print = 0;  // the library prints nothing; failures are reported by exceptions
    common.supernodal =
        options.method == Options::Method::supernodal_llt ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    common.final_ll = options.method == Options::Method::supernodal_llt;
  }
  // A⁻¹ B on the PETSc path, with its running Krylov counts copied into the statistics.
  Eigen::MatrixXd distributed_solve(const Eigen::Ref<const Eigen::MatrixXd>& B) {
    Eigen::MatrixXd x = distributed->solve(B);
    statistics.iterations = distributed->statistics().iterations;
    statistics.solved_columns = distributed->statistics().solved_columns;
    return x;
  }
  // solution = A⁻¹ B for the column-major block B (rows × cols, leading dimension ld), through
  // the workspace reused across calls (cholmod_l_solve2).
  void solve(const double* data, Eigen::Index rows, Eigen::Index cols, Eigen::Index ld) {
    cholmod_dense rhs{};
    rhs.nrow = static_cast<size_t>(rows);
    rhs.ncol = static_cast<size_t>(cols);
    rhs.d = static_cast<size_t>(ld);
    rhs.nzmax = rhs.d * rhs.ncol;
    rhs.x = const_cast<double*>(data);  // CHOLMOD reads B only
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_l_solve2(CHOLMOD_A, factor, &rhs, nullptr, &solution, nullptr, &work_y, &work_e,
                          &common))
      throw std::runtime_error("SparseCholesky::solve: CHOLMOD failed (" +
                               status_text(common.status) + ")");
  }
  ~Impl() {
    free_factor();
    cholmod_l_free_dense(&solution, &common);
    cholmod_l_free_dense(&work_y, &common);
    cholmod_l_free_dense(&work_e, &common);
    cholmod_l_finish(&common);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  void free_factor() {
    if (factor != nullptr) cholmod_l_free_factor(&factor, &common);
    valid = false;
  }

  // A view of A (compressed) for CHOLMOD, with the stored long pattern and A's values.
  cholmod_sparse view(const Eigen::SparseMatrix<double>& A) {
    cholmod_sparse s{};
    s.nrow = static_cast<size_t>(A.rows());
    s.ncol = static_cast<size_t>(A.cols());
    s.nzmax = inner.size();
    s.p = outer.data();
    s.i = inner.data();
    s.nz = nullptr;
    s.x = const_cast<double*>(A.valuePtr());  // CHOLMOD reads A only
    s.z = nullptr;
    s.stype = options.triangle == Options::Triangle::lower ? -1 : 1;
    s.itype = CHOLMOD_LONG;
    s.xtype = CHOLMOD_REAL;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
  }

  bool same_pattern(const Eigen::SparseMatrix<double>& A) const {
    if (static_cast<std::size_t>(A.cols()) + 1 != outer.size()) return false;
    if (static_cast<std::size_t>(A.nonZeros()) != inner.size()) return false;
    const int* p = A.outerIndexPtr();
    const int* i = A.innerIndexPtr();
    for (std::size_t k = 0; k < outer.size(); ++k)
      if (outer[k] != p[k]) return false;
    for (std::size_t k = 0; k < inner.size(); ++k)
      if (inner[k] != i[k]) return false;
    return true;
  }
};

namespace {
// Eigen's compressed storage of A, copying only when A is in uncompressed (insert) mode.
const Eigen::SparseMatrix<double>& compressed(const Eigen::SparseMatrix<double>& A,
                                              std::optional<Eigen::SparseMatrix<double>>& copy) {
  if (A.isCompressed()) return A;
  copy.emplace(A);
  copy->makeCompressed();
  return *copy;
}
}  // namespace

SparseCholesky::SparseCholesky(Options options) : impl_(std::make_unique<Impl>(options)) {}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

void SparseCholesky::analyze(const Eigen::SparseMatrix<double>& A_in) {
  if (A_in.rows() != A_in.cols())
    throw std::invalid_argument("SparseCholesky::analyze: A must be square, got " +
                                std::to_string(A_in.rows()) + " x " + std::to_string(A_in.cols()));
  const auto start = support::Clock::now();
  std::optional<Eigen::SparseMatrix<double>> copy;
  const auto& A = compressed(A_in, copy);
  Impl& d = *impl_;
  if (d.distributed) {
    d.distributed->analyze(A);
    d.statistics = petsc::as_sparse_cholesky_statistics(d.distributed->statistics());
    d.valid = false;
    return;
  }
  d.free_factor();

  const long n = A.cols();
  d.outer.assign(A.outerIndexPtr(), A.outerIndexPtr() + n + 1);
  d.inner.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  long used = 0;  // entries in the triangle CHOLMOD reads
  const bool lower = d.options.triangle == Options::Triangle::lower;
  for (long j = 0; j < n; ++j) {
    for (auto k = d.outer[static_cast<std::size_t>(j)];
         k < d.outer[static_cast<std::size_t>(j + 1)]; ++k) {
      const auto i = d.inner[static_cast<std::size_t>(k)];
      if (lower ? i >= j : i <= j) ++used;
      if (k > d.outer[static_cast<std::size_t>(j)] && d.inner[static_cast<std::size_t>(k - 1)] >= i)
        throw std::invalid_argument("SparseCholesky::analyze: row indices of column " +
                                    std::to_string(j) + " not strictly increasing");
    }
  }

  cholmod_sparse view = d.view(A);
  d.factor = cholmod_l_analyze(&view, &d.common);
  if (d.factor == nullptr || d.common.status < CHOLMOD_OK)
    throw std::runtime_error("SparseCholesky::analyze: CHOLMOD failed (" +
                             status_text(d.common.status) + ") for n = " + std::to_string(n));

  SparseCholeskyStatistics& s = d.statistics;
  s = {};
  s.rows = n;
  s.matrix_nonzeros = used;
  s.factor_nonzeros = d.common.lnz;
  s.factor_flops = d.common.fl;
  s.ordering = ordering_name(d.common.method[d.common.selected].ordering);
  s.factor_entries =
      d.factor->is_super ? static_cast<long>(d.factor->xsize) : static_cast<long>(d.common.lnz);
  s.analyze_seconds = support::seconds_since(start);
}

void SparseCholesky::factorize(const Eigen::SparseMatrix<double>& A_in) {
  Impl& d = *impl_;
  if (d.distributed) {
    d.valid = false;
    std::optional<Eigen::SparseMatrix<double>> copy;
    try {
      d.distributed->factorize(compressed(A_in, copy));
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(std::string("SparseCholesky::factorize: ") + e.what());
    }
    const int factorizations = d.statistics.factorizations + 1;
    d.statistics = petsc::as_sparse_cholesky_statistics(d.distributed->statistics());
    d.statistics.factorizations = factorizations;
    d.valid = true;
    return;
  }
  if (d.factor == nullptr) analyze(A_in);
  const auto start = support::Clock::now();
  std::optional<Eigen::SparseMatrix<double>> copy;
  const auto& A = compressed(A_in, copy);
  if (!d.same_pattern(A))
    throw std::invalid_argument(
        "SparseCholesky::factorize: A's pattern differs from the analysed one (call analyze())");
  d.valid = false;
  cholmod_sparse view = d.view(A);
  cholmod_l_factorize(&view, d.factor, &d.common);
  const int status = d.common.status;
  if (status < CHOLMOD_OK)
    throw std::runtime_error("SparseCholesky::factorize: CHOLMOD failed (" + status_text(status) +
                             ")");
  const auto n = static_cast<std::size_t>(d.statistics.rows);
  if (status == CHOLMOD_NOT_POSDEF || d.factor->minor < n) {
    // L->minor is the failing column of the permuted matrix PAPᵀ; Perm maps it back to A.
    const std::size_t k = d.factor->minor;
    const auto* perm = static_cast<const SuiteSparse_long*>(d.factor->Perm);
    const long column =
        (perm != nullptr && k < n) ? static_cast<long>(perm[k]) : static_cast<long>(k);
    const bool llt = d.options.method == Options::Method::supernodal_llt;
    throw std::runtime_error(std::string("SparseCholesky::factorize: ") +
                             (llt ? "matrix not positive definite" : "zero pivot in LDL^T") +
                             " at column " + std::to_string(column) + " (0-based; pivot " +
                             std::to_string(k) + " of " + std::to_string(n) +
                             " in the fill-reducing order; " + status_text(status) + ")");
  }
  d.valid = true;
  ++d.statistics.factorizations;
  if (d.factor->is_super)
    d.statistics.factor_entries = static_cast<long>(d.factor->xsize);
  else
    d.statistics.factor_entries = static_cast<long>(d.factor->nzmax);
  d.statistics.factorize_seconds = support::seconds_since(start);
}

void SparseCholesky::compute(const Eigen::SparseMatrix<double>& A) {
  analyze(A);
  factorize(A);
}

void SparseCholesky::solve_into(const Eigen::Ref<const Eigen::VectorXd>& b,
                                Eigen::Ref<Eigen::VectorXd> x) const {
  Impl& d = *impl_;
  if (!d.valid) throw std::logic_error("SparseCholesky::solve: no valid factor (call factorize())");
  if (b.size() != d.statistics.rows || x.size() != d.statistics.rows)
    throw std::invalid_argument("SparseCholesky::solve: right-hand side has " +
                                std::to_string(b.size()) + " rows, solution " +
                                std::to_string(x.size()) + ", matrix " +
                                std::to_string(d.statistics.rows));
  if (d.distributed) {
    x = d.distributed_solve(b);
    return;
  }
  d.solve(b.data(), b.size(), 1, b.size());
  x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(d.solution->x), b.size());
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::Ref<const Eigen::MatrixXd>& B) const {
  Impl& d = *impl_;
  if (!d.valid) throw std::logic_error("SparseCholesky::solve: no valid factor (call factorize())");
  if (B.rows() != d.statistics.rows)
    throw std::invalid_argument("SparseCholesky::solve: right-hand side has " +
                                std::to_string(B.rows()) + " rows, matrix " +
                                std::to_string(d.statistics.rows));
  if (B.cols() == 0) return Eigen::MatrixXd(B.rows(), 0);
  if (d.distributed) return d.distributed_solve(B);
  d.solve(B.data(), B.rows(), B.cols(), B.outerStride());
  const auto ld = static_cast<Eigen::Index>(d.solution->d);
  return Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>(
      static_cast<const double*>(d.solution->x), B.rows(), B.cols(), Eigen::OuterStride<>(ld));
}

bool SparseCholesky::analyzed() const {
  return impl_->factor != nullptr || (impl_->distributed && impl_->statistics.rows > 0);
}
bool SparseCholesky::factorized() const { return impl_->valid; }
long SparseCholesky::rows() const { return impl_->statistics.rows; }

long SparseCholesky::negative_pivots() const {
  const Impl& d = *impl_;
  if (d.distributed) return d.valid ? d.distributed->negative_pivots() : -1;
  if (!d.valid || d.factor->is_super || d.factor->is_ll) return -1;
  // Simplicial LDLᵀ: column j of L starts with its diagonal entry, which holds D(j).
  const auto* p = static_cast<const SuiteSparse_long*>(d.factor->p);
  const auto* x = static_cast<const double*>(d.factor->x);
  long negative = 0;
  for (std::size_t j = 0; j < d.factor->n; ++j)
    if (x[p[j]] < 0.0) ++negative;
  return negative;
}

const SparseCholeskyStatistics& SparseCholesky::statistics() const { return impl_->statistics; }
const SparseCholesky::Options& SparseCholesky::options() const { return impl_->options; }

}  // namespace jointhb::fe
