// One start of a fit's search (start_search.hpp).
#include "start_search.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>

namespace jointhb::fit::detail {
namespace {

/// The automatic penalty before this start's first success (FitOptions::penalty).
constexpr double no_success_penalty = 1e12;

using Json = nlohmann::json;

// Doubles of a start's outcome in JSON: ±∞ and NaN are not JSON numbers, so they go as strings.
Json exact(double v) {
  if (std::isfinite(v)) return v;
  return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
}
double exact_of(const Json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string s = j.get<std::string>();
  if (s == "nan") return std::nan("");
  return s == "inf" ? std::numeric_limits<double>::infinity()
                    : -std::numeric_limits<double>::infinity();
}
Json exact_array(const std::vector<double>& v) {
  Json a = Json::array();
  for (double x : v) a.push_back(exact(x));
  return a;
}
std::vector<double> exact_array_of(const Json& a) {
  std::vector<double> v;
  for (const auto& x : a) v.push_back(exact_of(x));
  return v;
}

struct Callback {
  StartSearch* search;
  nlopt_opt opt;
  std::exception_ptr error;  // thrown by the stream: rethrown after NLopt returns
};

double objective(unsigned n, const double* x, double* gradient, void* data) {
  (void)gradient;  // derivative-free algorithms only
  auto* c = static_cast<Callback*>(data);
  std::vector<double> u(x, x + n);
  for (double& v : u) v = std::clamp(v, 0.0, 1.0);
  try {
    return c->search->evaluate(u);
  } catch (...) {
    c->error = std::current_exception();
    nlopt_force_stop(c->opt);
    return no_success_penalty;
  }
}

}  // namespace

nlohmann::json exact_json(const std::vector<double>& values) { return exact_array(values); }
std::vector<double> exact_values(const nlohmann::json& array) { return exact_array_of(array); }

nlopt_algorithm local_algorithm_id(const std::string& name) {
  if (name == "neldermead") return NLOPT_LN_NELDERMEAD;
  if (name == "cobyla") return NLOPT_LN_COBYLA;
  return NLOPT_LN_BOBYQA;
}

Optimizer::Optimizer(nlopt_algorithm a, unsigned n) : opt(nlopt_create(a, n)) {
  if (!opt) throw std::runtime_error("NLopt could not create the optimizer");
}

void configure(nlopt_opt opt, unsigned n, const FitOptions& o, int max_evaluations) {
  const std::vector<double> lo(n, 0.0), hi(n, 1.0), step(n, o.initial_step);
  nlopt_set_lower_bounds(opt, lo.data());
  nlopt_set_upper_bounds(opt, hi.data());
  nlopt_set_xtol_abs1(opt, o.xtol);
  nlopt_set_ftol_rel(opt, o.ftol_rel);
  nlopt_set_maxeval(opt, max_evaluations);
  nlopt_set_initial_step(opt, step.data());
}

ReplayRows replay_rows(const std::vector<HistoryRow>& replay, int start, std::size_t parameters) {
  ReplayRows rows;
  for (const auto& row : replay) {
    if (row.start == start && row.values.size() == parameters) rows.emplace(row.values, row);
  }
  return rows;
}

StartSearch::StartSearch(const Model& model, const std::vector<FitParameter>& parameters,
                         const FitOptions& options, int start, ReplayRows replay, double penalty,
                         std::size_t residual_count, std::function<void(const HistoryRow&)> stream)
    : model_(model),
      parameters_(parameters),
      options_(options),
      replay_(std::move(replay)),
      fixed_penalty_(penalty),
      m_(residual_count),
      stream_(std::move(stream)) {
  outcome_.start = start;
}

double StartSearch::penalty() const {
  if (fixed_penalty_ > 0.0) return fixed_penalty_;
  if (options_.penalty > 0.0) return options_.penalty;
  if (!outcome_.ok) return no_success_penalty;  // the scale of this start's S is not known yet
  return 10.0 * std::max(static_cast<double>(m_), largest_);
}

Evaluation evaluate_model(const Model& model, const std::vector<double>& values) {
  try {
    return model(values);
  } catch (const std::exception& ex) {
    Evaluation e;
    e.ok = false;
    e.message = ex.what();
    return e;
  }
}

// A new evaluation's row: its residuals checked (count, finiteness), S or the penalty.
HistoryRow StartSearch::row_of(const std::vector<double>& values, Evaluation e) {
  HistoryRow row;
  row.start = outcome_.start;
  row.values = values;
  if (e.ok && m_ > 0 && e.residuals.size() != m_) {
    e.ok = false;
    e.message = fmt::format("the model returned {} residuals, earlier {}", e.residuals.size(), m_);
  }
  if (e.ok && std::any_of(e.residuals.begin(), e.residuals.end(),
                          [](double r) { return !std::isfinite(r); })) {
    e.ok = false;
    e.message = "a residual is not finite";
  }
  if (e.ok && e.residuals.empty()) {
    e.ok = false;
    e.message = "the model returned no residuals";
  }
  if (e.ok) {
    double s = 0.0;
    for (double r : e.residuals) s += r * r;
    row.objective = s;
    row.residuals = e.residuals;
  } else {
    row.failed = true;
    row.objective = penalty();
    outcome_.last_failure = e.message;
  }
  return row;
}

// Numbers, accounts, streams (when new) and caches one evaluation's row.
void StartSearch::add_row(std::vector<double> values, HistoryRow row, bool replayed) {
  ++outcome_.evaluations;
  row.eval = number_ ? number_() : outcome_.evaluations;
  if (replayed) {
    ++outcome_.replayed;
    account(row);
  } else {
    ++outcome_.model_evaluations;
    account(row);
    outcome_.rows.push_back(row);
    if (stream_) stream_(row);
  }
  known_.emplace(std::move(values), std::move(row));
}

double StartSearch::evaluate(const std::vector<double>& u, std::vector<double>* residuals,
                             bool* ok) {
  const double s = evaluate_batch({u}, [this](const std::vector<std::vector<double>>& values) {
    std::vector<Evaluation> e;
    for (const auto& v : values) e.push_back(evaluate_model(model_, v));
    return e;
  })[0];
  const HistoryRow& row = known_.at(from_unit(parameters_, u));
  if (residuals) *residuals = row.residuals;
  if (ok) *ok = !row.failed;
  return s;
}

std::vector<double> StartSearch::evaluate_batch(const std::vector<std::vector<double>>& points,
                                                const BatchModel& batch) {
  std::vector<std::vector<double>> values, fresh;
  for (const auto& u : points) {
    values.push_back(from_unit(parameters_, u));
    const auto& v = values.back();
    if (!known_.count(v) && !replay_.count(v) &&
        std::find(fresh.begin(), fresh.end(), v) == fresh.end()) {
      fresh.push_back(v);
    }
  }
  std::vector<Evaluation> evaluations = batch(fresh);
  if (evaluations.size() != fresh.size()) {
    throw std::logic_error("the batch model returned a different number of evaluations");
  }
  std::vector<double> objectives;
  for (auto& v : values) {
    if (!known_.count(v)) {
      if (auto r = replay_.find(v); r != replay_.end()) {
        add_row(v, r->second, true);
      } else {
        const auto k =
            static_cast<std::size_t>(std::find(fresh.begin(), fresh.end(), v) - fresh.begin());
        add_row(v, row_of(v, std::move(evaluations[k])), false);
      }
    }
    objectives.push_back(known_.at(v).objective);
  }
  return objectives;
}

void StartSearch::account(const HistoryRow& row) {
  ++run_evaluations_;
  if (row.failed) {
    ++outcome_.failed;
    return;
  }
  if (m_ == 0) m_ = row.residuals.size();
  largest_ = std::max(largest_, row.objective);
  run_best_ = std::min(run_best_, row.objective);
  if (!outcome_.ok || row.objective < outcome_.best_objective) {
    outcome_.ok = true;
    outcome_.best_objective = row.objective;
    outcome_.best_values = row.values;
    outcome_.best_residuals = row.residuals;
  }
}

void StartSearch::begin_run() {
  run_best_ = std::numeric_limits<double>::infinity();
  run_evaluations_ = 0;
}

void StartSearch::end_run(const std::vector<double>& from, const std::string& stop_reason) {
  StartSummary s;
  s.start = outcome_.start;
  s.from = from_unit(parameters_, from);
  s.objective = run_best_;
  s.evaluations = run_evaluations_;
  s.stop_reason = stop_reason;
  outcome_.runs.push_back(s);
}

void StartSearch::run(nlopt_opt opt, std::vector<double> x, const std::vector<double>& from) {
  Callback cb{this, opt, nullptr};
  nlopt_set_min_objective(opt, objective, &cb);
  begin_run();
  double f = 0.0;
  const nlopt_result res = nlopt_optimize(opt, x.data(), &f);
  if (cb.error) std::rethrow_exception(cb.error);
  end_run(from, nlopt_result_to_string(res));
}

std::string evaluation_to_json(const Evaluation& e) {
  const Json j = {{"ok", e.ok}, {"message", e.message}, {"residuals", exact_array(e.residuals)}};
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

Evaluation evaluation_from_json(const std::string& text) {
  try {
    const Json j = Json::parse(text);
    Evaluation e;
    e.ok = j.at("ok").get<bool>();
    e.message = j.at("message").get<std::string>();
    e.residuals = exact_array_of(j.at("residuals"));
    return e;
  } catch (const nlohmann::json::exception& ex) {
    throw std::runtime_error(std::string("an evaluation's record does not parse: ") + ex.what());
  }
}

std::string outcome_to_json(const StartOutcome& o) {
  Json runs = Json::array();
  for (const auto& s : o.runs) {
    runs.push_back({{"start", s.start},
                    {"from", exact_array(s.from)},
                    {"objective", exact(s.objective)},
                    {"evaluations", s.evaluations},
                    {"stop_reason", s.stop_reason}});
  }
  Json rows = Json::array();
  for (const auto& r : o.rows) {
    rows.push_back({r.eval, r.start, exact(r.objective), r.failed, exact_array(r.values),
                    exact_array(r.residuals)});
  }
  const Json j = {{"start", o.start},
                  {"runs", runs},
                  {"rows", rows},
                  {"counts", {o.evaluations, o.model_evaluations, o.replayed, o.failed}},
                  {"ok", o.ok},
                  {"best", {exact(o.best_objective), exact_array(o.best_values),
                            exact_array(o.best_residuals)}},
                  {"last_failure", o.last_failure}};
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

StartOutcome outcome_from_json(const std::string& text) {
  try {
    const Json j = Json::parse(text);
    StartOutcome o;
    o.start = j.at("start").get<int>();
    for (const auto& s : j.at("runs")) {
      o.runs.push_back({s.at("start").get<int>(), exact_array_of(s.at("from")),
                        exact_of(s.at("objective")), s.at("evaluations").get<int>(),
                        s.at("stop_reason").get<std::string>()});
    }
    for (const auto& r : j.at("rows")) {
      o.rows.push_back({r.at(0).get<int>(), r.at(1).get<int>(), exact_of(r.at(2)),
                        exact_array_of(r.at(4)), r.at(3).get<bool>(), exact_array_of(r.at(5))});
    }
    const Json& c = j.at("counts");
    o.evaluations = c.at(0).get<int>();
    o.model_evaluations = c.at(1).get<int>();
    o.replayed = c.at(2).get<int>();
    o.failed = c.at(3).get<int>();
    o.ok = j.at("ok").get<bool>();
    o.best_objective = exact_of(j.at("best").at(0));
    o.best_values = exact_array_of(j.at("best").at(1));
    o.best_residuals = exact_array_of(j.at("best").at(2));
    o.last_failure = j.at("last_failure").get<std::string>();
    return o;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("a start's record does not parse: ") + e.what());
  }
}

}  // namespace jointhb::fit::detail
