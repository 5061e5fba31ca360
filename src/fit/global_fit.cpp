// A fit's direct or mlsl search on the workers (global_fit.hpp).
#include "global_fit.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <limits>
#include <string>

#include "../study/task_farm.hpp"
#include "global_search.hpp"
#include "jointhb/study/distributed.hpp"

namespace jointhb::fit::detail {
namespace {

using Points = std::vector<std::vector<double>>;
using Json = nlohmann::json;

// The collectives of one global search (global_fit.hpp).

class GlobalRun {
 public:
  GlobalRun(const GlobalProblem& pb, const ParallelOptions& parallel, const HistorySink& sink)
      : pb_(pb),
        jobs_(parallel.jobs),
        communicator_(parallel.communicator && parallel.communicator->size() > 1
                          ? parallel.communicator
                          : nullptr),
        root_(!parallel.communicator || parallel.communicator->rank() == 0),
        search_(pb.model, pb.parameters, pb.options, 0,
                replay_rows(pb.replay, 0, pb.parameters.size()), 0.0, 0,
                root_ ? std::function<void(const HistoryRow&)>(sink) : nullptr),
        sink_(sink) {
    search_.number_rows_by([this] { return ++rows_; });
  }

  [[nodiscard]] bool root() const { return root_; }
  [[nodiscard]] StartSearch& start_search() { return search_; }
  [[nodiscard]] const std::vector<StartOutcome>& local_outcomes() const { return locals_; }

  /// S at each point: start 0's evaluations, the new ones on the workers.
  std::vector<double> objective(const Points& points) {
    std::vector<double> s;
    if (root_) {
      s = search_.evaluate_batch(points, [this](const Points& values) {
        Json list_json = Json::array();
        for (const auto& v : values) list_json.push_back(exact_json(v));
        std::string list = list_json.dump();
        broadcast(list);
        return evaluations(values);
      });
    } else {
      std::string list;
      broadcast(list);
      Points values;
      for (const auto& v : Json::parse(list)) values.push_back(exact_values(v));
      (void)evaluations(values);
    }
    std::string text = root_ ? exact_json(s).dump() : "";
    broadcast(text);
    return root_ ? s : exact_values(Json::parse(text));
  }

  /// Rank 0's `value` on every rank.
  bool agree(bool value) const {
    std::string text = value ? "1" : "0";
    broadcast(text);
    return text == "1";
  }

  /// Local searches (starts 1, 2, … in the order made) from `starts`, on the workers.
  std::vector<LocalMinimum> local(const Points& starts, int budget) {
    const int first = next_start_;
    next_start_ += static_cast<int>(starts.size());
    const auto records = run_tasks(starts.size(), [&](std::size_t k) {
      return outcome_to_json(local_search(first + static_cast<int>(k), starts[k], budget));
    });
    std::vector<LocalMinimum> minima;
    if (root_) {
      for (std::size_t k = 0; k < starts.size(); ++k) {
        StartOutcome o;
        if (records[k].failure.empty()) {
          o = outcome_from_json(records[k].record);
        } else {
          o.start = first + static_cast<int>(k);
          o.runs.push_back({o.start, from_unit(pb_.parameters, starts[k]),
                            std::numeric_limits<double>::infinity(), 0,
                            "worker failed: " + records[k].failure});
          o.last_failure = records[k].failure;
        }
        for (HistoryRow row : o.rows) {  // numbered after every row before this search's
          row.eval += rows_;
          if (sink_) sink_(row);
        }
        rows_ += o.evaluations;
        minima.push_back({o.ok ? to_unit(pb_.parameters, o.best_values) : starts[k],
                          o.ok ? o.best_objective : std::numeric_limits<double>::infinity(),
                          o.evaluations});
        locals_.push_back(std::move(o));
      }
    }
    Json all = Json::array();
    for (const auto& m : minima) {
      all.push_back({exact_json(m.u), exact_json({m.objective}), m.evaluations});
    }
    std::string text = root_ ? all.dump() : "";
    broadcast(text);
    if (!root_) {
      for (const auto& m : Json::parse(text)) {
        minima.push_back({exact_values(m.at(0)), exact_values(m.at(1)).at(0),
                          m.at(2).get<int>()});
      }
    }
    return minima;
  }

 private:
  struct Record {
    std::string record, failure;
  };

  void broadcast(std::string& text) const {
    if (communicator_) communicator_->broadcast(text);
  }

  // Tasks 0 … count−1 on the workers (in this process when it is alone), records in task order.
  std::vector<Record> run_tasks(std::size_t count, const study::TaskRun& run) const {
    std::vector<Record> records(count);
    if (count == 0) return records;
    if (jobs_ <= 1 && !communicator_) {
      for (std::size_t k = 0; k < count; ++k) records[k].record = run(k);
      return records;
    }
    study::farm_tasks(
        count, run,
        [&](study::TaskDone d) {
          if (d.task < count) records[d.task] = {d.record, d.failure};
        },
        {std::min<int>(jobs_, static_cast<int>(count)), communicator_});
    return records;
  }

  std::vector<Evaluation> evaluations(const Points& values) const {
    const auto records = run_tasks(values.size(), [&](std::size_t k) {
      return evaluation_to_json(evaluate_model(pb_.model, values[k]));
    });
    std::vector<Evaluation> e;
    for (const auto& r : records) {
      if (!r.failure.empty() || r.record.empty()) {
        e.push_back({false, "worker failed: " + (r.failure.empty() ? std::string("no record") : r.failure), {}});
      } else {
        e.push_back(evaluation_from_json(r.record));
      }
    }
    return e;
  }

  StartOutcome local_search(int start, const std::vector<double>& u, int budget) const {
    const FitOptions& o = pb_.options;
    const auto n = static_cast<unsigned>(pb_.parameters.size());
    StartSearch search(pb_.model, pb_.parameters, o, start,
                       replay_rows(pb_.replay, start, pb_.parameters.size()));
    Optimizer opt(local_algorithm_id(o.local_algorithm), n);
    configure(opt.opt, n, o, budget);
    search.run(opt.opt, u, u);
    return search.outcome();
  }

  const GlobalProblem& pb_;
  int jobs_;
  const study::Communicator* communicator_;
  bool root_;
  StartSearch search_;
  HistorySink sink_;
  int rows_ = 0;         ///< rows numbered so far (replayed ones included)
  int next_start_ = 1;   ///< the next local search's start index
  std::vector<StartOutcome> locals_;
};

}  // namespace

std::optional<std::vector<StartOutcome>> run_global(const GlobalProblem& pb,
                                                    const ParallelOptions& parallel,
                                                    const HistorySink& sink) {
  const FitOptions& o = pb.options;
  const int n = static_cast<int>(pb.parameters.size());
  GlobalRun run(pb, parallel, sink);
  const BatchObjective objective = [&](const Points& p) { return run.objective(p); };
  StartSearch& search = run.start_search();
  search.begin_run();
  GlobalOutcome g;
  if (o.algorithm == "direct") {
    g = direct_l(n, objective, o.max_evaluations, o.xtol);
  } else {
    MlslOptions m;
    m.max_evaluations = o.max_evaluations;
    m.seed = o.seed;
    g = mlsl(n, objective,
             [&](const Points& starts, int budget) { return run.local(starts, budget); }, m);
  }
  if (run.root()) search.end_run(pb.start, g.stop_reason);
  // DIRECT's polish: a local search from the best point (start 1), on a worker like MLSL's, so
  // that rank 0's process never computes while it has children (a process that ran OpenMP
  // regions and then forks leaves libgomp deadlocked in the child: CHOLMOD hung so).
  if (o.algorithm == "direct" && run.agree(search.outcome().ok)) {
    (void)run.local({g.best}, o.max_evaluations);
  }
  if (!run.root()) return std::nullopt;
  std::vector<StartOutcome> outcomes{search.outcome()};
  for (const auto& l : run.local_outcomes()) outcomes.push_back(l);
  return outcomes;
}

}  // namespace jointhb::fit::detail
