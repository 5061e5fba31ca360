#pragma once
// Weighted nonlinear least squares by NLopt, model-agnostic: minimise
//   S(θ) = Σ_i r_i(θ)²
// over the box of the parameters (fit/parameters.hpp: NLopt works in the unit box u), with the
// residuals r_i from the model (for the case models, fit/targets.hpp). At the optimum, the
// Jacobian J = ∂r/∂u by central differences gives the Gauss–Newton (asymptotic) covariance
//   Cov(θ̂) = s² D (JᵀJ)⁻¹ D,   s² = S(θ̂) / (m − p),   D = diag(dθ/du)
// (G. A. F. Seber, C. J. Wild, "Nonlinear Regression", Wiley 1989, §2.1 eq. 2.21; D. M. Bates,
// D. G. Watts, "Nonlinear Regression Analysis and Its Applications", Wiley 1988, §2.3), the
// standard errors, the correlation matrix, and from the singular values σ_k of J (right singular
// vectors v_k) the directions the data cannot resolve: σ_k < 1e-3 σ_max (numerically
// rank-deficient), or s/σ_k > 1 (the standard error along v_k exceeds the whole search range).
// docs/identification.md.
//
// Failed evaluations (the model throws or reports !ok, e.g. a continuation that stopped) are not
// fatal: their objective is the penalty (FitOptions::penalty, default 10 max(m, largest
// successful objective of the same start so far), 1e12 before that start's first success), and
// they are counted. Everything is deterministic: the starts come from a seeded Latin hypercube, and
// each start's search sees only its own evaluations (its own cache, penalty and replayed rows), so
// the starts can run in any order, in parallel on worker processes and MPI ranks
// (ParallelOptions), and give the same result bit for bit. The global searches direct and mlsl
// evaluate their candidates in batches (src/fit/global_search.hpp) on the same workers, every rank
// following the search: the same result bit for bit too.
//
// Resume: every evaluation is a HistoryRow (fit/history.hpp writes and reads them as CSV). Given
// the rows of an interrupted run, fit() answers evaluations of a start at parameters found in that
// start's rows (exact match) from the rows instead of the model; the deterministic search then retraces its path at
// no cost and continues where the run stopped.

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "jointhb/fit/parameters.hpp"
#include "jointhb/contact/termination.hpp"

namespace jointhb::study {
class Communicator;
}

namespace jointhb::fit {

/// What the model returns for one parameter vector (physical values, in parameter order).
struct Evaluation {
  bool ok = true;
  std::string message;            ///< why not, when !ok
  std::vector<double> residuals;  ///< r_i (same length at every successful evaluation)
};
using Model = std::function<Evaluation(const std::vector<double>& values)>;

struct FitOptions {
  /// bobyqa (local, default), neldermead, cobyla (local); direct (global DIRECT-L in batches, then
  /// a local polish by local_algorithm), mlsl (global multi-level single linkage with shifted
  /// Sobol points and local_algorithm searches, in batches). The local ones are NLopt's.
  std::string algorithm = "bobyqa";
  std::string local_algorithm = "bobyqa";  ///< bobyqa or neldermead (direct, mlsl)
  double xtol = 1e-6;         ///< (0, 0.1]: stop when a step moves every u by less (unit box)
  double ftol_rel = 1e-10;    ///< [0, 0.1]: stop when S changes by less, relatively
  int max_evaluations = 400;  ///< ≥ 1: per start (direct: global phase, again the polish; mlsl:
                              ///< samples and local searches together)
  int starts = 1;             ///< ≥ 1: the given start, then Latin-hypercube points
  unsigned seed = 1;          ///< Latin hypercube and MLSL's shift of the Sobol points
  double penalty = 0.0;  ///< ≥ 0: S of a failed evaluation; 0: 10 max(m, largest S of the same
                         ///< start so far), 1e12 before that start's first successful evaluation
  double initial_step = 0.1;    ///< (0, 0.5]: first step of the local searches (unit box)
  double jacobian_step = 1e-3;  ///< (0, 0.1]: h of the central differences in u
  [[nodiscard]] std::string validate() const;
};

/// One evaluation, as recorded in the history.
struct HistoryRow {
  int eval = 0;                ///< 1-based sequence number
  int start = 0;  ///< index of the start (mlsl: 0 the sample, 1, 2, … its local searches); -1 the Jacobian
  double objective = 0.0;      ///< S, or the penalty when failed
  std::vector<double> values;  ///< physical parameter values
  bool failed = false;
  std::vector<double> residuals;  ///< empty when failed
};
using HistorySink = std::function<void(const HistoryRow&)>;

/// A direction the data do not resolve.
struct UnresolvedDirection {
  std::vector<double> components;  ///< v_k in the unit box (unit length), parameter order
  double singular_value = 0.0;     ///< σ_k
  double standard_error = 0.0;     ///< s / σ_k (unit box; ∞ when σ_k = 0)
  std::string description;         ///< "0.71 contacts[0].mu + 0.71 contacts[0].normal_force"
};

struct StartSummary {
  int start = 0;
  std::vector<double> from;  ///< physical start values
  double objective = 0.0;    ///< best S of this start
  int evaluations = 0;
  std::string stop_reason;  ///< NLopt's result
};

/// Where the searches run. The result does not depend on it (bit for bit).
struct ParallelOptions {
  /// Local workers (≥ 1). More than one: the starts, when there are several (each one task: its
  /// whole local search), and then the Jacobian's points run in that many child processes of this
  /// process (of rank 0), each taking the next when free; not threads (study/worker_processes.hpp).
  int jobs = 1;
  /// With size > 1, the other ranks take starts too (rank 0 coordinates, and its `jobs` children
  /// compute); every rank calls fit() with the same problem. nullptr: this process alone.
  const study::Communicator* communicator = nullptr;
};

struct FitResult {
  bool root = true;               ///< false on ranks > 0, which hold no result
  std::vector<double> best;       ///< θ̂
  double objective = 0.0;         ///< S(θ̂)
  std::vector<double> residuals;  ///< r(θ̂)
  /// A successful evaluation exists (best, objective and residuals are valid). Not how the search
  /// ended: that is status() (a fit found at MAXEVAL_REACHED is ok with status() no_convergence).
  bool ok = false;
  int evaluations = 0;            ///< all, including replayed ones and the Jacobian's
  int model_evaluations = 0;      ///< calls of the model (not replayed)
  int replayed = 0;               ///< answered from the history
  int failed_evaluations = 0;
  double seconds = 0.0;
  std::string stop_reason;  ///< of the start that found θ̂
  std::vector<StartSummary> starts;
  // Uncertainty (when has_jacobian):
  bool has_jacobian = false;
  std::string jacobian_message;     ///< why not, when !has_jacobian
  Eigen::MatrixXd jacobian;         ///< ∂r/∂u (m × p)
  double s2 = 0.0;                  ///< S / (m − p) (0 when m ≤ p)
  int degrees_of_freedom = 0;       ///< m − p
  Eigen::MatrixXd covariance;       ///< of θ (physical); ∞ on rows of unresolved parameters
  Eigen::VectorXd standard_errors;  ///< √diag; ∞ for parameters in a rank-deficient direction
  Eigen::MatrixXd correlation;      ///< NaN where a standard error is ∞
  Eigen::VectorXd singular_values;  ///< of J (unit box), descending
  Eigen::MatrixXd right_singular_vectors;  ///< columns v_k
  std::vector<UnresolvedDirection> unresolved;
  std::vector<std::string> warnings;  ///< one line each, for the user
  /// The status convention (contact/termination.hpp), from `ok` and NLopt's `stop_reason` of the
  /// start that found θ̂: no successful evaluation → failed; SUCCESS, STOPVAL_REACHED, FTOL_REACHED,
  /// XTOL_REACHED → converged; MAXEVAL_REACHED, MAXTIME_REACHED → no_convergence; FORCED_STOP →
  /// stopped_by_user; NLopt's failures (FAILURE, ROUNDOFF_LIMITED, ...) → failed.
  [[nodiscard]] Status status() const;
};

/// Runs the fit. Throws std::invalid_argument for invalid parameters or options. `replay`: rows
/// of an earlier run of the same problem (resume); `sink` sees each new (not replayed) row, in the
/// order start 0, 1, …, then the Jacobian's (−1), numbered so: as it is made with one job, a
/// start's rows when it and every start before it have finished with several.
FitResult fit(const Model& model, const std::vector<FitParameter>& parameters,
              const FitOptions& options, const HistorySink& sink = {},
              const std::vector<HistoryRow>& replay = {}, const ParallelOptions& parallel = {});

/// The Latin-hypercube starts 1.. count−1 in the unit box (start 0 is the user's): deterministic
/// for a seed (std::mt19937_64), one point per stratum of width 1/(count−1) in each coordinate.
std::vector<std::vector<double>> latin_hypercube(int count, int dimensions, unsigned seed);

}  // namespace jointhb::fit
