#pragma once
// One start of a fit's search (private to src/fit; fit/fitter.hpp): NLopt's local search from one
// point with its own evaluations — its own cache, its own replayed history rows and its own
// automatic penalty
//   P = 10 max(m, largest successful S of this start),   1e12 before this start's first success
// (FitOptions::penalty, when given, instead). A start thus sees nothing of the others, and its
// result is the same whether it runs first, last, alone in a worker process or on another MPI rank
// (docs/identification.md §2, "parallel starts"). The Jacobian at the optimum is a search of its
// own (start −1) with the fixed penalty 10 max(m, S(θ̂)), so that each of its points can be
// evaluated anywhere too.
//
// A start's outcome travels between processes as one line of JSON whose doubles read back
// bit-identical (nlohmann::json writes the shortest representation that round-trips).

#include <nlopt.h>

#include <nlohmann/json_fwd.hpp>

#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "jointhb/fit/fitter.hpp"

namespace jointhb::fit::detail {

/// What one start's search produced.
struct StartOutcome {
  int start = 0;
  std::vector<StartSummary> runs;  ///< one per NLopt run (two for direct/mlsl: global, polish)
  /// The new rows (not replayed), eval numbered 1, 2, ... within the start, replayed ones counted.
  std::vector<HistoryRow> rows;
  int evaluations = 0;        ///< new and replayed
  int model_evaluations = 0;  ///< new
  int replayed = 0;
  int failed = 0;
  bool ok = false;  ///< a successful evaluation exists
  double best_objective = std::numeric_limits<double>::infinity();
  std::vector<double> best_values, best_residuals;  ///< the first evaluation with the least S
  std::string last_failure;
  std::string worker_failure;  ///< the worker died during this start (set by the coordinator)
};

/// NLopt's local algorithm of that name (bobyqa, neldermead, cobyla; bobyqa otherwise).
[[nodiscard]] nlopt_algorithm local_algorithm_id(const std::string& name);

/// An NLopt optimizer, destroyed with its scope.
struct Optimizer {
  nlopt_opt opt;
  explicit Optimizer(nlopt_algorithm a, unsigned n);
  ~Optimizer() { nlopt_destroy(opt); }
  Optimizer(const Optimizer&) = delete;
  Optimizer& operator=(const Optimizer&) = delete;
};

/// The unit box, xtol, ftol_rel, initial step of `o`, and the evaluation budget.
void configure(nlopt_opt opt, unsigned n, const FitOptions& o, int max_evaluations);

/// The rows of an earlier run that a start may replay: those of start `start`, by values.
using ReplayRows = std::map<std::vector<double>, HistoryRow>;
[[nodiscard]] ReplayRows replay_rows(const std::vector<HistoryRow>& replay, int start,
                                     std::size_t parameters);

/// The model at each of a batch of parameter vectors (physical values), in order; exceptions
/// already turned into !ok evaluations.
using BatchModel =
    std::function<std::vector<Evaluation>(const std::vector<std::vector<double>>& values)>;

class StartSearch {
 public:
  /// `penalty` > 0: the S of every failed evaluation (the Jacobian's); 0: options.penalty or the
  /// automatic per-start penalty. `residual_count`: m when known (else that of the first success).
  /// `stream` sees each new row as it is made (eval within the start).
  StartSearch(const Model& model, const std::vector<FitParameter>& parameters,
              const FitOptions& options, int start, ReplayRows replay, double penalty = 0.0,
              std::size_t residual_count = 0, std::function<void(const HistoryRow&)> stream = {});

  /// S at u (unit box); `residuals` and `ok` when given. Rethrows what `stream` threw.
  double evaluate(const std::vector<double>& u, std::vector<double>* residuals = nullptr,
                  bool* ok = nullptr);
  /// S at each of `points` (unit box), in order. The points that are neither known nor replayed
  /// go to `batch` in one call (duplicates once; the call is made even when none is new, so that
  /// a collective batch model runs on every rank alike); their rows are then made in the order of
  /// `points`, as evaluate() would make them one by one.
  std::vector<double> evaluate_batch(const std::vector<std::vector<double>>& points,
                                     const BatchModel& batch);
  /// Rows numbered by `next` (called once per evaluation, replayed ones included) instead of
  /// 1, 2, … within the start: for a search whose rows interleave with other searches'.
  void number_rows_by(std::function<int()> next) { number_ = std::move(next); }
  /// A run not made by NLopt (the global phase): begin_run(), evaluations, end_run() appends its
  /// StartSummary.
  void begin_run();
  void end_run(const std::vector<double>& from, const std::string& stop_reason);
  /// Runs `opt` (configured, without objective) from u = `x`; appends its StartSummary (from:
  /// the physical values of `from`). Rethrows what `stream` threw.
  void run(nlopt_opt opt, std::vector<double> x, const std::vector<double>& from);

  [[nodiscard]] const StartOutcome& outcome() const { return outcome_; }

 private:
  double penalty() const;
  HistoryRow row_of(const std::vector<double>& values, Evaluation e);
  void add_row(std::vector<double> values, HistoryRow row, bool replayed);
  void account(const HistoryRow& row);

  const Model& model_;
  const std::vector<FitParameter>& parameters_;
  const FitOptions& options_;
  ReplayRows replay_;
  std::map<std::vector<double>, HistoryRow> known_;  ///< this start's evaluations (cache)
  double fixed_penalty_ = 0.0;
  std::size_t m_ = 0;
  double largest_ = 0.0;
  std::function<void(const HistoryRow&)> stream_;
  std::function<int()> number_;
  StartOutcome outcome_;
  double run_best_ = std::numeric_limits<double>::infinity();
  int run_evaluations_ = 0;
};

/// Doubles in JSON that read back bit-identical, ±∞ and NaN included (as the strings "inf",
/// "-inf", "nan": they are not JSON numbers).
[[nodiscard]] nlohmann::json exact_json(const std::vector<double>& values);
[[nodiscard]] std::vector<double> exact_values(const nlohmann::json& array);

/// The model at `values`, an exception turned into !ok with its message.
[[nodiscard]] Evaluation evaluate_model(const Model& model, const std::vector<double>& values);
/// An evaluation as one line of JSON, and back (doubles bit-identical; throws std::runtime_error).
[[nodiscard]] std::string evaluation_to_json(const Evaluation& e);
[[nodiscard]] Evaluation evaluation_from_json(const std::string& text);

/// The outcome as one line of JSON, and back (throws std::runtime_error when it does not parse).
[[nodiscard]] std::string outcome_to_json(const StartOutcome& outcome);
[[nodiscard]] StartOutcome outcome_from_json(const std::string& text);

}  // namespace jointhb::fit::detail
