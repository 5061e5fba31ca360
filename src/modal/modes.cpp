#include "jointhb/modal/modes.hpp"
#include "jointhb/fe/petsc_solvers.hpp"

#include <arpack/arpackdef.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <mutex>
#include <random>
#include <stdexcept>
#include <vector>

#include "../support/numeric_constants.hpp"
#include "../support/sparse_norm.hpp"
#include "../support/stopwatch.hpp"

// arpack-ng's ISO C binding (arpack/arpack.h declares these too, but also complex routines whose
// C99 `_Complex` types ISO C++ rejects).
extern "C" {
void dsaupd_c(a_int* ido, char const* bmat, a_int n, char const* which, a_int nev, double tol,
              double* resid, a_int ncv, double* v, a_int ldv, a_int* iparam, a_int* ipntr,
              double* workd, double* workl, a_int lworkl, a_int* info);
void dseupd_c(a_int rvec, char const* howmny, a_int const* select, double* d, double* z, a_int ldz,
              double sigma, char const* bmat, a_int n, char const* which, a_int nev, double tol,
              double* resid, a_int ncv, double* v, a_int ldv, a_int* iparam, a_int* ipntr,
              double* workd, double* workl, a_int lworkl, a_int* info);
}

namespace jointhb::modal {

namespace {

using support::kTwoPi;

std::string fmt_double(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

// The lock of every ARPACK call in the program (its state is process-global, see compute_modes).
std::mutex& arpack_mutex() {
  static std::mutex m;
  return m;
}

// dsaupd's info on return (ARPACK Users' Guide, dsaupd.f header).
std::string dsaupd_message(int info, int ncv) {
  switch (info) {
    case 1:
      return "maximum number of iterations reached (raise max_iterations or ncv)";
    case 3:
      return "no shifts could be applied during an implicit restart (raise ncv = " +
             std::to_string(ncv) + ")";
    case -1:
      return "n must be positive";
    case -2:
      return "count must be positive";
    case -3:
      return "ncv must satisfy count < ncv <= n";
    case -4:
      return "max_iterations must be positive";
    case -5:
      return "invalid 'which'";
    case -6:
      return "invalid 'bmat'";
    case -7:
      return "workl too short";
    case -8:
      return "LAPACK dsteqr failed on the tridiagonal matrix";
    case -9:
      return "starting vector is zero";
    case -10:
      return "invalid mode";
    case -11:
      return "mode and bmat incompatible";
    case -12:
      return "invalid iparam(1)";
    case -13:
      return "count and which = 'BE' incompatible";
    case -9999:
      return "could not build a Lanczos factorization (the operator may be rank "
             "deficient: is M singular?)";
    default:
      return "dsaupd info " + std::to_string(info);
  }
}

// dseupd's info on return (dseupd.f header).
std::string dseupd_message(int info) {
  switch (info) {
    case -8:
      return "LAPACK dsteqr failed computing the Ritz vectors";
    case -9:
      return "starting vector is zero";
    case -14:
      return "dsaupd found no eigenvalue to sufficient accuracy";
    case -17:
      return "dseupd found a different number of converged Ritz values than dsaupd";
    default:
      return "dseupd info " + std::to_string(info);
  }
}

void check_symmetric(const Eigen::SparseMatrix<double>& A, const char* name) {
  const double scale = A.coeffs().size() > 0 ? A.coeffs().cwiseAbs().maxCoeff() : 0.0;
  const Eigen::SparseMatrix<double> At = A.transpose();
  const Eigen::SparseMatrix<double> D = A - At;
  const double asym = D.coeffs().size() > 0 ? D.coeffs().cwiseAbs().maxCoeff() : 0.0;
  if (!(asym <= 1e-10 * scale))  // also catches NaN
    throw std::invalid_argument(std::string("compute_modes: ") + name +
                                " must be symmetric and stored in full (both triangles): "
                                "max |a_ij - a_ji| = " +
                                fmt_double(asym) + " vs max |a_ij| = " + fmt_double(scale));
}

}  // namespace

std::string ModalOptions::validate() const {
  if (count < 1) return "count: must be >= 1, got " + std::to_string(count);
  if (!std::isfinite(shift)) return "shift: must be finite, got " + fmt_double(shift);
  if (!(tolerance > 0.0 && tolerance <= 1e-3))
    return "tolerance: must be in (0, 1e-3], got " + fmt_double(tolerance);
  if (max_iterations < 1)
    return "max_iterations: must be >= 1, got " + std::to_string(max_iterations);
  if (ncv != 0 && ncv <= count)
    return "ncv: must be 0 (automatic) or > count = " + std::to_string(count) + ", got " +
           std::to_string(ncv);
  return {};
}

std::string ModalResult::brief() const {
  const auto m = eigenvalues.size();
  char line[320];
  std::snprintf(line, sizeof line,
                "%ld of %d modes, %.6g ... %.6g Hz, max residual %.2g, %d iterations, %d solves, "
                "%.3f s (factor %.3f s)",
                static_cast<long>(m), requested, m > 0 ? frequencies_hz(0) : 0.0,
                m > 0 ? frequencies_hz(m - 1) : 0.0, m > 0 ? residuals.maxCoeff() : 0.0, iterations,
                operator_applications, seconds, factor_seconds);
  return line;
}

Status ModalResult::status() const {
  if (!message.empty()) return {termination, message};
  return {termination, std::to_string(eigenvalues.size()) + " of " + std::to_string(requested) + " modes converged"};
}

namespace {

/// Fills result's modes from the solver's m eigenpairs (values[j], vectors.col(j)): ascending λ,
/// each φ mass-normalised with its largest |entry| positive (a fixed sign), with residuals and
/// backward errors.
void store_modes(const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& M,
                 const std::vector<double>& values, const Eigen::MatrixXd& vectors, int m,
                 const ModalOptions& options, ModalResult& result) {
  const Eigen::Index n = K.rows();
  std::vector<int> order(static_cast<std::size_t>(m));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return values[static_cast<std::size_t>(a)] < values[static_cast<std::size_t>(b)];
  });
  result.eigenvalues.resize(m);
  result.frequencies_hz.resize(m);
  result.shapes.resize(n, m);
  result.residuals.resize(m);
  result.backward_errors.resize(m);
  const double norm_k = support::norm1(K);
  const double norm_m = support::norm1(M);
  Eigen::VectorXd k_phi(n), m_phi(n);
  for (int j = 0; j < m; ++j) {
    const int source = order[static_cast<std::size_t>(j)];
    const double lambda = values[static_cast<std::size_t>(source)];
    Eigen::VectorXd phi = vectors.col(source);
    m_phi.noalias() = M * phi;
    const double modal_mass = phi.dot(m_phi);
    if (modal_mass > 0.0) {
      phi /= std::sqrt(modal_mass);
      m_phi /= std::sqrt(modal_mass);
    }
    Eigen::Index largest = 0;
    phi.cwiseAbs().maxCoeff(&largest);
    if (phi(largest) < 0.0) {
      phi = -phi;
      m_phi = -m_phi;
    }
    k_phi.noalias() = K * phi;
    const double r = (k_phi - lambda * m_phi).norm();
    result.eigenvalues(j) = lambda;
    result.frequencies_hz(j) = std::copysign(std::sqrt(std::abs(lambda)), lambda) / kTwoPi;
    result.residuals(j) =
        r /
        (std::max({std::abs(lambda), std::abs(options.shift), std::numeric_limits<double>::min()}) *
         m_phi.norm());
    result.backward_errors(j) = r / ((norm_k + std::abs(lambda) * norm_m) * phi.norm());
    result.shapes.col(j) = phi;
  }
}

/// The modes by SLEPc across the ranks (fe/petsc_solvers.hpp), stored as ARPACK's are.
ModalResult slepc_modes(const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& M,
                        const ModalOptions& options, ModalResult result,
                        support::Clock::time_point start) {
  fe::petsc::EigenpairOptions o;
  o.count = options.count;
  o.shift = options.shift;
  o.tolerance = options.tolerance;
  o.max_iterations = options.max_iterations;
  o.ncv = options.ncv;
  o.seed = options.seed;
  if (options.linear_solver == fe::LinearSolver::cg) o.iterative = options.iterative;
  const fe::petsc::EigenpairResult e = fe::petsc::distributed_eigenpairs(K, M, o);
  result.iterations = e.iterations;
  result.factor = fe::petsc::as_sparse_cholesky_statistics(e.factor);
  result.factor.factorizations = 1;
  result.factor.ordering = "SLEPc/" + result.factor.ordering;
  result.factor_seconds = e.factor_seconds;
  result.lanczos_seconds = e.solve_seconds;
  const int m = static_cast<int>(e.eigenvalues.size());
  if (m == 0) {
    result.termination = e.ok ? Termination::no_convergence : Termination::failed;
    result.message = e.message.empty() ? "SLEPc: no eigenpair converged" : e.message;
    result.seconds = support::seconds_since(start);
    return result;
  }
  const std::vector<double> values(e.eigenvalues.data(), e.eigenvalues.data() + m);
  store_modes(K, M, values, e.vectors, m, options, result);
  result.termination = m == options.count ? Termination::converged : Termination::no_convergence;
  result.message = result.termination == Termination::converged ? std::string() : e.message;
  result.seconds = support::seconds_since(start);
  return result;
}

}  // namespace

ModalResult compute_modes(const Eigen::SparseMatrix<double>& K,
                          const Eigen::SparseMatrix<double>& M, const ModalOptions& options) {
  const auto start = support::Clock::now();
  if (const auto problem = options.validate(); !problem.empty())
    throw std::invalid_argument("compute_modes: " + problem);
  const Eigen::Index n = K.rows();
  if (K.cols() != n || M.rows() != n || M.cols() != n)
    throw std::invalid_argument("compute_modes: K (" + std::to_string(K.rows()) + " x " +
                                std::to_string(K.cols()) + ") and M (" + std::to_string(M.rows()) +
                                " x " + std::to_string(M.cols()) +
                                ") must be square and of the same size");
  if (options.count >= n)
    throw std::invalid_argument("compute_modes: count: must be < n = " + std::to_string(n) +
                                ", got " + std::to_string(options.count));
  if (options.ncv > n)
    throw std::invalid_argument("compute_modes: ncv: must be <= n = " + std::to_string(n) +
                                ", got " + std::to_string(options.ncv));
  check_symmetric(K, "K");
  check_symmetric(M, "M");

  ModalResult result;
  result.shift = options.shift;
  result.requested = options.count;
  if (options.eigen_solver == ModalOptions::EigenSolver::slepc)
    return slepc_modes(K, M, options, std::move(result), start);
  const int nev = options.count;
  const int size = static_cast<int>(n);
  const int ncv = options.ncv > 0 ? options.ncv : std::min(size, std::max(2 * nev + 1, nev + 20));
  result.ncv = ncv;

  // Factor K − σM (lower triangle).
  fe::SparseCholesky factor(fe::SparseCholesky::Options{.backend = options.linear_solver,
                                                        .iterative = options.iterative});
  try {
    const Eigen::SparseMatrix<double> shifted =
        Eigen::SparseMatrix<double>(K - options.shift * M).triangularView<Eigen::Lower>();
    factor.compute(shifted);
  } catch (const std::runtime_error& error) {
    result.termination = Termination::failed;
    result.message = "K - sigma*M (sigma = " + fmt_double(options.shift) +
                     ") is not positive definite: sigma must lie below the lowest eigenvalue and "
                     "K be positive semi-definite, M positive definite (" +
                     error.what() + ")";
    result.factor = factor.statistics();
    result.seconds = support::seconds_since(start);
    return result;
  }
  result.factor = factor.statistics();
  result.factor_seconds = support::seconds_since(start);

  // Deterministic starting vector: uniform in [-1, 1) from mt19937_64, whose output sequence the
  // C++ standard fixes (std::uniform_real_distribution's is implementation-defined).
  std::vector<double> resid(static_cast<std::size_t>(n));
  std::mt19937_64 random(options.seed);
  for (double& r : resid) r = static_cast<double>(random() >> 11) * 0x1.0p-52 - 1.0;

  const auto lanczos_start = support::Clock::now();
  const auto un = static_cast<std::size_t>(n);
  std::vector<double> v(un * static_cast<std::size_t>(ncv));
  std::vector<double> workd(3 * un);
  const int lworkl = ncv * (ncv + 8);
  std::vector<double> workl(static_cast<std::size_t>(lworkl));
  a_int iparam[11] = {};
  a_int ipntr[11] = {};
  iparam[0] = 1;  // exact shifts
  iparam[2] = options.max_iterations;
  iparam[3] = 1;  // block size
  iparam[6] = 3;  // mode 3: shift-invert, OP = (K − σM)⁻¹M, B = M
  a_int ido = 0;
  a_int info = 1;  // resid holds the starting vector
  // ARPACK keeps its reverse-communication state in Fortran SAVE variables (dsaupd, dsaup2,
  // dsaitr): two threads iterating at once would corrupt each other. A study runs samples on
  // several threads (study/study.hpp), so the Lanczos iteration and dseupd hold one lock.
  const std::lock_guard arpack_lock(arpack_mutex());
  Eigen::VectorXd mass_x(n);
  auto at = [&](a_int pointer) { return workd.data() + (pointer - 1); };  // ipntr is 1-based
  while (true) {
    dsaupd_c(&ido, "G", size, "LM", nev, options.tolerance, resid.data(), ncv, v.data(), size,
             iparam, ipntr, workd.data(), workl.data(), lworkl, &info);
    if (ido == -1) {  // y = (K − σM)⁻¹ M x  (initialisation: M x is not yet available)
      Eigen::Map<const Eigen::VectorXd> x(at(ipntr[0]), n);
      Eigen::Map<Eigen::VectorXd> y(at(ipntr[1]), n);
      mass_x.noalias() = M * x;
      factor.solve_into(mass_x, y);
    } else if (ido == 1) {  // y = (K − σM)⁻¹ (M x), with M x given at ipntr(3)
      Eigen::Map<const Eigen::VectorXd> mx(at(ipntr[2]), n);
      Eigen::Map<Eigen::VectorXd> y(at(ipntr[1]), n);
      factor.solve_into(mx, y);
    } else if (ido == 2) {  // y = M x
      Eigen::Map<const Eigen::VectorXd> x(at(ipntr[0]), n);
      Eigen::Map<Eigen::VectorXd> y(at(ipntr[1]), n);
      y.noalias() = M * x;
    } else {
      break;
    }
  }
  result.iterations = iparam[2];
  result.operator_applications = iparam[8];
  result.mass_applications = iparam[9];

  std::string message;
  if (info < 0) {
    result.termination = Termination::failed;
    result.message = "ARPACK dsaupd: " + dsaupd_message(info, ncv);
    result.lanczos_seconds = support::seconds_since(lanczos_start);
    result.seconds = support::seconds_since(start);
    return result;
  }
  const int converged = iparam[4];
  if (info == 1 || info == 3 || converged < nev)
    message = "ARPACK: " + std::to_string(converged) + " of " + std::to_string(nev) +
              " modes converged: " +
              (info == 0 ? std::string("fewer than requested") : dsaupd_message(info, ncv));
  if (converged == 0) {
    result.termination = Termination::no_convergence;
    result.message = message;
    result.lanczos_seconds = support::seconds_since(lanczos_start);
    result.seconds = support::seconds_since(start);
    return result;
  }

  std::vector<a_int> select(static_cast<std::size_t>(ncv));
  std::vector<double> values(static_cast<std::size_t>(nev));
  Eigen::MatrixXd vectors(n, nev);
  a_int eupd_info = 0;
  dseupd_c(1, "A", select.data(), values.data(), vectors.data(), size, options.shift, "G", size,
           "LM", nev, options.tolerance, resid.data(), ncv, v.data(), size, iparam, ipntr,
           workd.data(), workl.data(), lworkl, &eupd_info);
  result.lanczos_seconds = support::seconds_since(lanczos_start);
  if (eupd_info != 0) {
    result.termination = Termination::failed;
    result.message = "ARPACK dseupd: " + dseupd_message(eupd_info);
    result.seconds = support::seconds_since(start);
    return result;
  }
  const int m = std::min(converged, nev);

  store_modes(K, M, values, vectors, m, options, result);
  result.termination = (m == nev) ? Termination::converged : Termination::no_convergence;
  result.message = result.termination == Termination::converged ? std::string() : message;
  result.seconds = support::seconds_since(start);
  return result;
}

}  // namespace jointhb::modal
