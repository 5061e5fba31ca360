#include "jointhb/fit/fitter.hpp"

#include <fmt/format.h>
#include <nlopt.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <random>
#include <optional>
#include <set>
#include <stdexcept>

#include "../study/task_farm.hpp"
#include "global_fit.hpp"
#include "jointhb/study/distributed.hpp"
#include "start_search.hpp"

namespace jointhb::fit {

std::string FitOptions::validate() const {
  static const std::set<std::string> algorithms = {"bobyqa", "neldermead", "cobyla", "direct",
                                                   "mlsl"};
  if (!algorithms.count(algorithm)) {
    return "algorithm: must be one of bobyqa, cobyla, direct, mlsl, neldermead, got '" + algorithm +
           "'";
  }
  if (local_algorithm != "bobyqa" && local_algorithm != "neldermead") {
    return "local_algorithm: must be bobyqa or neldermead, got '" + local_algorithm + "'";
  }
  if (!(xtol > 0.0 && xtol <= 0.1)) return fmt::format("xtol: must be in (0, 0.1], got {}", xtol);
  if (!(ftol_rel >= 0.0 && ftol_rel <= 0.1)) {
    return fmt::format("ftol_rel: must be in [0, 0.1], got {}", ftol_rel);
  }
  if (max_evaluations < 1) {
    return fmt::format("max_evaluations: must be >= 1, got {}", max_evaluations);
  }
  if (starts < 1) return fmt::format("starts: must be >= 1, got {}", starts);
  if (!(penalty >= 0.0) || !std::isfinite(penalty)) {
    return fmt::format("penalty: must be >= 0 and finite, got {}", penalty);
  }
  if (!(initial_step > 0.0 && initial_step <= 0.5)) {
    return fmt::format("initial_step: must be in (0, 0.5], got {}", initial_step);
  }
  if (!(jacobian_step > 0.0 && jacobian_step <= 0.1)) {
    return fmt::format("jacobian_step: must be in (0, 0.1], got {}", jacobian_step);
  }
  return "";
}

Status FitResult::status() const {
  // The one translation of NLopt's result names (nlopt_result_to_string) to the status convention.
  const std::string line =
      fmt::format("{} after {} evaluations, S = {:.6g}", stop_reason, evaluations, objective);
  if (!ok) return {Termination::failed, stop_reason};
  if (stop_reason == "SUCCESS" || stop_reason == "STOPVAL_REACHED" || stop_reason == "FTOL_REACHED" ||
      stop_reason == "XTOL_REACHED")
    return {Termination::converged, line};
  if (stop_reason == "MAXEVAL_REACHED" || stop_reason == "MAXTIME_REACHED")
    return {Termination::no_convergence, line};
  if (stop_reason == "FORCED_STOP") return {Termination::stopped_by_user, line};
  return {Termination::failed, line};  // FAILURE, INVALID_ARGS, OUT_OF_MEMORY, ROUNDOFF_LIMITED
}

std::vector<std::vector<double>> latin_hypercube(int count, int dimensions, unsigned seed) {
  std::vector<std::vector<double>> points;
  const int n = count - 1;
  if (n <= 0) return points;
  std::mt19937_64 rng(seed);
  const auto uniform = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  points.assign(static_cast<std::size_t>(n), std::vector<double>(dimensions));
  for (int d = 0; d < dimensions; ++d) {
    std::vector<int> strata(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) strata[k] = k;
    for (int k = n - 1; k > 0; --k) {  // Fisher–Yates with the engine's own (portable) output
      const auto j = static_cast<int>(rng() % static_cast<std::uint64_t>(k + 1));
      std::swap(strata[k], strata[j]);
    }
    for (int k = 0; k < n; ++k) points[k][d] = (strata[k] + uniform()) / n;
  }
  return points;
}

namespace {

using Clock = std::chrono::steady_clock;
std::string describe(const std::vector<FitParameter>& parameters, const Eigen::VectorXd& v) {
  std::string s;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (std::abs(v[i]) < 0.05) continue;
    const std::string name =
        parameters[i].log_scale ? "log " + parameters[i].name : parameters[i].name;
    s += fmt::format("{}{:.2f} {}", s.empty() ? (v[i] < 0 ? "-" : "") : (v[i] < 0 ? " - " : " + "),
                     std::abs(v[i]), name);
  }
  return s;
}

// The points of the central differences at u0 (§4): per parameter u0 + h e_i, then u0 − h e_i, each
// only inside the box.
struct JacobianPoint {
  Eigen::Index parameter = 0;
  bool up = true;
  std::vector<double> u;
  bool ok = false;                ///< evaluated successfully
  std::vector<double> residuals;  ///< when ok
};

std::vector<JacobianPoint> jacobian_points(const std::vector<double>& u0, double h) {
  std::vector<JacobianPoint> points;
  for (std::size_t i = 0; i < u0.size(); ++i) {
    for (const bool up : {true, false}) {
      const double ui = up ? u0[i] + h : u0[i] - h;
      if (ui > 1.0 || ui < 0.0) continue;
      JacobianPoint pt;
      pt.parameter = static_cast<Eigen::Index>(i);
      pt.up = up;
      pt.u = u0;
      pt.u[i] = ui;
      points.push_back(std::move(pt));
    }
  }
  return points;
}

// J = ∂r/∂u from the evaluated points (central, or one-sided where a side is missing or failed),
// then the covariance, standard errors and unresolved directions at θ̂ (§4, §5).
void uncertainty(FitResult& r, const std::vector<FitParameter>& parameters, const FitOptions& options,
                 const std::vector<double>& u0, const std::vector<JacobianPoint>& points) {
  const auto p = static_cast<Eigen::Index>(parameters.size());
  const auto m = static_cast<Eigen::Index>(r.residuals.size());
  const double h = options.jacobian_step;
  Eigen::MatrixXd j(m, p);
  const auto side = [&](Eigen::Index i, bool up) -> const JacobianPoint* {
    for (const auto& pt : points) {
      if (pt.parameter == i && pt.up == up && pt.ok && static_cast<Eigen::Index>(pt.residuals.size()) == m)
        return &pt;
    }
    return nullptr;
  };
  const auto vec = [&](const JacobianPoint* pt) { return Eigen::Map<const Eigen::VectorXd>(pt->residuals.data(), m); };
  const Eigen::VectorXd r0 = Eigen::Map<const Eigen::VectorXd>(r.residuals.data(), m);
  for (Eigen::Index i = 0; i < p; ++i) {
    const JacobianPoint* plus = side(i, true);
    const JacobianPoint* minus = side(i, false);
    if (plus && minus) {
      j.col(i) = (vec(plus) - vec(minus)) / (2.0 * h);
    } else if (plus) {
      j.col(i) = (vec(plus) - r0) / h;
    } else if (minus) {
      j.col(i) = (r0 - vec(minus)) / h;
    } else {
      r.jacobian_message = fmt::format(
          "the model failed on both sides of the optimum in {}: no uncertainty estimate",
          parameters[i].name);
      r.warnings.push_back(r.jacobian_message);
      return;
    }
  }
  r.has_jacobian = true;
  r.jacobian = j;
  r.degrees_of_freedom = static_cast<int>(m - p);
  r.s2 = m > p ? r.objective / static_cast<double>(m - p) : 0.0;
  if (m <= p) {
    r.warnings.push_back(fmt::format(
        "{} residuals for {} parameters: no degrees of freedom left for s^2; the standard errors "
        "assume s^2 = 1 (residuals scaled by their true sigma)",
        m, p));
  }
  const double s2 = m > p ? r.s2 : 1.0;
  const double s = std::sqrt(s2);

  Eigen::JacobiSVD<Eigen::MatrixXd> svd(j, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();
  const Eigen::MatrixXd v = svd.matrixV();
  r.singular_values = Eigen::VectorXd::Zero(p);
  r.singular_values.head(sv.size()) = sv;
  r.right_singular_vectors = v;
  const double smax = r.singular_values.size() ? r.singular_values.maxCoeff() : 0.0;
  constexpr double rank_tolerance = 1e-3;
  const double inf = std::numeric_limits<double>::infinity();

  Eigen::MatrixXd cov_u = Eigen::MatrixXd::Zero(p, p);
  std::vector<bool> deficient_parameter(static_cast<std::size_t>(p), false);
  for (Eigen::Index k = 0; k < p; ++k) {
    const double sk = r.singular_values[k];
    const bool deficient = !(sk >= rank_tolerance * smax) || sk == 0.0;
    const double se = sk > 0.0 ? s / sk : inf;
    if (!deficient) cov_u += (s2 / (sk * sk)) * v.col(k) * v.col(k).transpose();
    if (deficient) {
      for (Eigen::Index i = 0; i < p; ++i) {
        if (std::abs(v(i, k)) > 1e-2) deficient_parameter[i] = true;
      }
    }
    if (deficient || se > 1.0) {
      UnresolvedDirection d;
      d.components.assign(v.col(k).data(), v.col(k).data() + p);
      d.singular_value = sk;
      d.standard_error = se;
      d.description = describe(parameters, v.col(k));
      r.unresolved.push_back(d);
      r.warnings.push_back(fmt::format(
          "the data do not determine the combination {} (unit-box direction; singular value "
          "{:.3g} of {:.3g}, standard error {:.3g} of the search range): {}",
          d.description, sk, smax, se,
          deficient ? "the parameters in it are not separately identifiable; fix all but one of "
                      "them or add data that separates them"
                    : "its uncertainty exceeds the bounds; the value found is arbitrary within "
                      "them"));
    }
  }
  Eigen::VectorXd d(p);
  for (Eigen::Index i = 0; i < p; ++i) d[i] = parameters[i].derivative(u0[i]);
  r.covariance = d.asDiagonal() * cov_u * d.asDiagonal();
  r.standard_errors.resize(p);
  for (Eigen::Index i = 0; i < p; ++i) {
    if (deficient_parameter[i]) {
      r.covariance.row(i).setConstant(inf);
      r.covariance.col(i).setConstant(inf);
    }
    r.standard_errors[i] = deficient_parameter[i] ? inf : std::sqrt(r.covariance(i, i));
  }
  r.correlation.resize(p, p);
  for (Eigen::Index i = 0; i < p; ++i) {
    for (Eigen::Index k = 0; k < p; ++k) {
      r.correlation(i, k) =
          deficient_parameter[i] || deficient_parameter[k]
              ? std::numeric_limits<double>::quiet_NaN()
              : r.covariance(i, k) / (r.standard_errors[i] * r.standard_errors[k]);
    }
  }
}

}  // namespace
namespace {

using detail::StartOutcome;
using detail::StartSearch;

// Everything that one fit's searches share: the problem, the starts, where they run.
struct Problem {
  const Model& model;
  const std::vector<FitParameter>& parameters;
  const FitOptions& options;
  const std::vector<HistoryRow>& replay;
  std::vector<std::vector<double>> starts;  ///< unit box; start 0 is the user's
};

// Start k's whole search: the local algorithm from its point (direct and mlsl: run_global).
// `stream` sees each new row.
StartOutcome run_start(const Problem& pb, std::size_t k,
                       std::function<void(const HistoryRow&)> stream = {}) {
  const FitOptions& o = pb.options;
  const auto n = static_cast<unsigned>(pb.parameters.size());
  const int start = static_cast<int>(k);
  StartSearch search(pb.model, pb.parameters, o, start,
                     detail::replay_rows(pb.replay, start, pb.parameters.size()), 0.0, 0,
                     std::move(stream));
  detail::Optimizer local(detail::local_algorithm_id(o.algorithm), n);
  detail::configure(local.opt, n, o, o.max_evaluations);
  search.run(local.opt, pb.starts[k], pb.starts[k]);
  return search.outcome();
}

// The outcomes of the searches gathered into one result, in a fixed order whatever order they
// finished in: starts 0, 1, …, then the Jacobian's points. Each new row is numbered after all rows
// before it (replayed ones included) and goes to the sink, unless it was streamed already.
class Gather {
 public:
  Gather(FitResult& r, const HistorySink& sink) : r_(r), sink_(sink) {}

  /// The number the next row gets minus one: where a streamed start's rows begin.
  [[nodiscard]] int offset() const { return offset_; }

  void add(const StartOutcome& o, bool streamed) {
    for (HistoryRow row : o.rows) {
      row.eval += offset_;
      if (!streamed && sink_) sink_(row);
    }
    offset_ += o.evaluations;
    r_.model_evaluations += o.model_evaluations;
    r_.replayed += o.replayed;
    r_.failed_evaluations += o.failed;
    if (!o.last_failure.empty()) last_failure = o.last_failure;
    if (o.start < 0) return;  // the Jacobian's points
    for (const auto& s : o.runs) r_.starts.push_back(s);
    if (o.ok && (!r_.ok || o.best_objective < r_.objective)) {
      r_.ok = true;
      r_.objective = o.best_objective;
      r_.best = o.best_values;
      r_.residuals = o.best_residuals;
    }
  }

  std::string last_failure;

 private:
  FitResult& r_;
  const HistorySink& sink_;
  int offset_ = 0;
};

// A stream that numbers a search's rows after the `offset` rows before it and passes them on.
std::function<void(const HistoryRow&)> numbered(const HistorySink& sink, int offset) {
  if (!sink) return {};
  return [&sink, offset](const HistoryRow& row) {
    HistoryRow copy = row;
    copy.eval += offset;
    sink(copy);
  };
}

// A start whose worker died: no evaluation, the reason as its stop reason and a warning.
StartOutcome failed_start(const Problem& pb, std::size_t k, const std::string& why, FitResult& r) {
  StartOutcome o;
  o.start = static_cast<int>(k);
  StartSummary s;
  s.start = o.start;
  s.from = from_unit(pb.parameters, pb.starts[k]);
  s.objective = std::numeric_limits<double>::infinity();
  s.stop_reason = "worker failed: " + why;
  o.runs.push_back(s);
  r.warnings.push_back(fmt::format("start {}: {}; the start was not searched", k, why));
  return o;
}

// The starts on the workers of `parallel`; their outcomes gathered in start order as they come
// (a start's rows reach the sink once every start before it has finished). False on ranks > 0.
bool farm_starts(const Problem& pb, const ParallelOptions& parallel, Gather& gather, FitResult& r) {
  std::vector<std::optional<StartOutcome>> outcomes(pb.starts.size());
  std::size_t next = 0;
  const auto flush = [&] {
    while (next < outcomes.size() && outcomes[next]) gather.add(*outcomes[next++], false);
  };
  study::farm_tasks(
      pb.starts.size(), [&](std::size_t k) { return detail::outcome_to_json(run_start(pb, k)); },
      [&](study::TaskDone d) {
        if (d.task >= outcomes.size() || outcomes[d.task]) return;
        outcomes[d.task] = d.failure.empty() ? detail::outcome_from_json(d.record)
                                             : failed_start(pb, d.task, d.failure, r);
        flush();
      },
      {std::min<int>(parallel.jobs, static_cast<int>(pb.starts.size())), parallel.communicator});
  if (parallel.communicator && parallel.communicator->rank() != 0) return false;
  for (std::size_t k = 0; k < outcomes.size(); ++k) {
    if (!outcomes[k]) outcomes[k] = failed_start(pb, k, "no worker was left to run it", r);
  }
  flush();
  return true;
}

// The Jacobian's points evaluated (§4): in sequence, or with jobs > 1 on rank 0's child processes,
// one point a task. Their penalty is fixed (10 max(m, S(θ̂))) so that it does not depend on the order.
void evaluate_jacobian(const Problem& pb, int jobs, Gather& gather, const HistorySink& sink,
                       const FitResult& r, std::vector<JacobianPoint>& points) {
  const FitOptions& o = pb.options;
  const double penalty = o.penalty > 0.0 ? o.penalty
                                         : 10.0 * std::max(static_cast<double>(r.residuals.size()), r.objective);
  const auto search = [&](std::function<void(const HistoryRow&)> stream) {
    return StartSearch(pb.model, pb.parameters, o, -1,
                       detail::replay_rows(pb.replay, -1, pb.parameters.size()), penalty,
                       r.residuals.size(), std::move(stream));
  };
  if (jobs <= 1 || points.empty()) {
    StartSearch s = search(numbered(sink, gather.offset()));
    for (auto& pt : points) s.evaluate(pt.u, &pt.residuals, &pt.ok);
    gather.add(s.outcome(), true);
    return;
  }
  std::vector<std::optional<StartOutcome>> outcomes(points.size());
  study::farm_tasks(
      points.size(),
      [&](std::size_t k) {
        StartSearch s = search({});
        s.evaluate(points[k].u);
        return detail::outcome_to_json(s.outcome());
      },
      [&](study::TaskDone d) {
        if (d.task >= outcomes.size()) return;
        StartOutcome failed;
        failed.start = -1;
        failed.last_failure = d.failure;
        outcomes[d.task] = d.failure.empty() ? detail::outcome_from_json(d.record) : failed;
      },
      {std::min<int>(jobs, static_cast<int>(points.size())), nullptr});
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!outcomes[k]) continue;  // no worker was left: the side counts as failed
    points[k].ok = outcomes[k]->ok;
    points[k].residuals = outcomes[k]->best_residuals;
    gather.add(*outcomes[k], false);
  }
}

}  // namespace

FitResult fit(const Model& model, const std::vector<FitParameter>& parameters,
              const FitOptions& options, const HistorySink& sink,
              const std::vector<HistoryRow>& replay, const ParallelOptions& parallel) {
  if (auto e = validate(parameters); !e.empty()) throw std::invalid_argument(e);
  if (auto e = options.validate(); !e.empty()) throw std::invalid_argument(e);
  if (parallel.jobs < 1) throw std::invalid_argument(fmt::format("jobs: must be >= 1, got {}", parallel.jobs));
  const auto began = Clock::now();
  Problem pb{model, parameters, options, replay, {}};
  std::vector<double> start_values;
  for (const auto& p : parameters) start_values.push_back(p.start);
  pb.starts.push_back(to_unit(parameters, start_values));
  for (auto& u : latin_hypercube(options.starts, static_cast<int>(parameters.size()), options.seed)) {
    pb.starts.push_back(u);
  }
  // direct and mlsl search from start 0 only, their batches on the workers (GlobalRun); a single
  // local start runs in this process (of rank 0): its model's counters stay this process's.
  const bool global = options.algorithm == "direct" || options.algorithm == "mlsl";
  if (global) pb.starts.resize(1);
  const bool ranks = parallel.communicator && parallel.communicator->size() > 1;
  FitResult r;
  Gather gather(r, sink);
  if (global) {
    const auto outcomes = detail::run_global(
        {model, parameters, options, replay, pb.starts[0]}, parallel, sink);
    if (!outcomes) {
      r.root = false;
      return r;
    }
    for (const auto& o : *outcomes) gather.add(o, true);
  } else if (parallel.jobs > 1 || ranks) {  // even one start: rank 0's process computes nothing
    // while it has children (see run_global)
    if (!farm_starts(pb, parallel, gather, r)) {
      r.root = false;
      return r;
    }
  } else {
    for (std::size_t k = 0; k < pb.starts.size(); ++k) {
      gather.add(run_start(pb, k, numbered(sink, gather.offset())), true);
    }
  }
  if (r.ok) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& s : r.starts) {
      if (s.objective < best) {
        best = s.objective;
        r.stop_reason = s.stop_reason;
      }
    }
    const std::vector<double> u0 = to_unit(parameters, r.best);
    std::vector<JacobianPoint> points = jacobian_points(u0, options.jacobian_step);
    evaluate_jacobian(pb, parallel.jobs, gather, sink, r, points);
    uncertainty(r, parameters, options, u0, points);
  } else {
    r.stop_reason = "every evaluation failed";
    r.warnings.push_back("every model evaluation failed; last: " + gather.last_failure);
  }
  r.evaluations = r.model_evaluations + r.replayed;
  r.seconds = std::chrono::duration<double>(Clock::now() - began).count();
  return r;
}

}  // namespace jointhb::fit
