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

// A new evaluation: the model, its residuals checked (count, finiteness), S or the penalty.
HistoryRow StartSearch::call_model(const std::vector<double>& values) {
  HistoryRow row;
  row.start = outcome_.start;
  row.values = values;
  Evaluation e;
  try {
    e = model_(values);
  } catch (const std::exception& ex) {
    e.ok = false;
    e.message = ex.what();
  }
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

double StartSearch::evaluate(const std::vector<double>& u, std::vector<double>* residuals,
                             bool* ok) {
  std::vector<double> values = from_unit(parameters_, u);
  auto it = known_.find(values);
  if (it == known_.end()) {
    HistoryRow row;
    if (auto r = replay_.find(values); r != replay_.end()) {
      row = r->second;
      ++outcome_.replayed;
      row.eval = ++outcome_.evaluations;
      account(row);
    } else {
      row = call_model(values);
      ++outcome_.model_evaluations;
      row.eval = ++outcome_.evaluations;
      account(row);
      outcome_.rows.push_back(row);
      if (stream_) stream_(row);
    }
    it = known_.emplace(std::move(values), std::move(row)).first;
  }
  if (residuals) *residuals = it->second.residuals;
  if (ok) *ok = !it->second.failed;
  return it->second.objective;
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

std::vector<double> StartSearch::best_unit() const {
  return to_unit(parameters_, outcome_.best_values);
}

void StartSearch::run(nlopt_opt opt, std::vector<double> x, const std::vector<double>& from) {
  Callback cb{this, opt, nullptr};
  nlopt_set_min_objective(opt, objective, &cb);
  run_best_ = std::numeric_limits<double>::infinity();
  run_evaluations_ = 0;
  double f = 0.0;
  const nlopt_result res = nlopt_optimize(opt, x.data(), &f);
  if (cb.error) std::rethrow_exception(cb.error);
  StartSummary s;
  s.start = outcome_.start;
  s.from = from_unit(parameters_, from);
  s.objective = run_best_;
  s.evaluations = run_evaluations_;
  s.stop_reason = nlopt_result_to_string(res);
  outcome_.runs.push_back(s);
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
