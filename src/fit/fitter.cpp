#include "jointhb/fit/fitter.hpp"

#include <fmt/format.h>
#include <nlopt.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <stdexcept>

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

/// The automatic penalty before any evaluation has succeeded (FitOptions::penalty).
constexpr double no_success_penalty = 1e12;

struct Known {
  HistoryRow row;
  bool from_file = false;
  bool consumed = false;
};

// Evaluations with their bookkeeping: cache, replay, penalty, best point, history.
class Evaluator {
 public:
  Evaluator(const Model& model, const std::vector<FitParameter>& parameters,
            const FitOptions& options, const HistorySink& sink,
            const std::vector<HistoryRow>& replay)
      : model_(model), parameters_(parameters), options_(options), sink_(sink) {
    for (const auto& row : replay) {
      if (row.values.size() != parameters.size()) continue;
      known_.emplace(row.values, Known{row, true, false});
    }
  }

  /// S at u (unit box) for start `start` (-1: Jacobian); fills `residuals` and `ok`.
  double operator()(const std::vector<double>& u, int start,
                    std::vector<double>* residuals = nullptr, bool* ok = nullptr) {
    const std::vector<double> values = from_unit(parameters_, u);
    auto it = known_.find(values);
    if (it != known_.end()) {
      Known& k = it->second;
      if (k.from_file && !k.consumed) {
        k.consumed = true;
        ++count_;
        ++result.replayed;
        account(k.row);
      }
      if (residuals) *residuals = k.row.residuals;
      if (ok) *ok = !k.row.failed;
      return k.row.objective;
    }
    HistoryRow row;
    row.eval = ++count_;
    row.start = start;
    row.values = values;
    Evaluation e;
    try {
      e = model_(values);
    } catch (const std::exception& ex) {
      e.ok = false;
      e.message = ex.what();
    }
    ++result.model_evaluations;
    if (e.ok) {
      if (m_ > 0 && e.residuals.size() != m_) {
        e.ok = false;
        e.message =
            fmt::format("the model returned {} residuals, earlier {}", e.residuals.size(), m_);
      }
      for (double r : e.residuals) {
        if (!std::isfinite(r)) {
          e.ok = false;
          e.message = "a residual is not finite";
          break;
        }
      }
      if (e.residuals.empty()) {
        e.ok = false;
        e.message = "the model returned no residuals";
      }
    }
    if (e.ok) {
      double s = 0.0;
      for (double r : e.residuals) s += r * r;
      row.objective = s;
      row.residuals = e.residuals;
    } else {
      row.failed = true;
      row.objective = penalty();
      last_failure = e.message;
    }
    row.eval = count_;
    account(row);
    if (sink_) sink_(row);
    known_.emplace(values, Known{row, false, true});
    if (residuals) *residuals = row.residuals;
    if (ok) *ok = !row.failed;
    return row.objective;
  }

  double penalty() const {
    if (options_.penalty > 0.0) return options_.penalty;
    if (m_ == 0) return no_success_penalty;  // the scale of S is not known yet
    return 10.0 * std::max(static_cast<double>(m_), largest_);
  }

  std::size_t residual_count() const { return m_; }

  FitResult result;
  std::vector<double> best_unit;
  std::string last_failure;
  int current_start = 0;
  double start_best = std::numeric_limits<double>::infinity();
  int start_evaluations = 0;

 private:
  void account(const HistoryRow& row) {
    ++start_evaluations;
    if (row.failed) {
      ++result.failed_evaluations;
      return;
    }
    if (m_ == 0) m_ = row.residuals.size();
    largest_ = std::max(largest_, row.objective);
    start_best = std::min(start_best, row.objective);
    if (row.start >= 0 && (!result.ok || row.objective < result.objective)) {
      result.ok = true;
      result.objective = row.objective;
      result.best = row.values;
      result.residuals = row.residuals;
      best_unit = to_unit(parameters_, row.values);
    }
  }

  const Model& model_;
  const std::vector<FitParameter>& parameters_;
  const FitOptions& options_;
  const HistorySink& sink_;
  std::map<std::vector<double>, Known> known_;
  int count_ = 0;
  std::size_t m_ = 0;
  double largest_ = 0.0;
};

struct Callback {
  Evaluator* evaluator;
  int start;
  nlopt_opt opt;
  std::exception_ptr error;  // thrown by the history sink: rethrown after NLopt returns
};

double objective(unsigned n, const double* x, double* gradient, void* data) {
  (void)gradient;  // derivative-free algorithms only
  auto* c = static_cast<Callback*>(data);
  std::vector<double> u(x, x + n);
  for (double& v : u) v = std::clamp(v, 0.0, 1.0);
  try {  // no exception may cross NLopt's C code
    return (*c->evaluator)(u, c->start);
  } catch (...) {
    c->error = std::current_exception();
    nlopt_force_stop(c->opt);
    return 0.0;
  }
}

nlopt_algorithm local_id(const std::string& name) {
  if (name == "neldermead") return NLOPT_LN_NELDERMEAD;
  if (name == "cobyla") return NLOPT_LN_COBYLA;
  return NLOPT_LN_BOBYQA;
}

struct Optimizer {
  nlopt_opt opt;
  explicit Optimizer(nlopt_algorithm a, unsigned n) : opt(nlopt_create(a, n)) {
    if (!opt) throw std::runtime_error("NLopt could not create the optimizer");
  }
  ~Optimizer() { nlopt_destroy(opt); }
  Optimizer(const Optimizer&) = delete;
  Optimizer& operator=(const Optimizer&) = delete;
};

void configure(nlopt_opt opt, unsigned n, const FitOptions& o, int max_evaluations) {
  const std::vector<double> lo(n, 0.0), hi(n, 1.0), step(n, o.initial_step);
  nlopt_set_lower_bounds(opt, lo.data());
  nlopt_set_upper_bounds(opt, hi.data());
  nlopt_set_xtol_abs1(opt, o.xtol);
  nlopt_set_ftol_rel(opt, o.ftol_rel);
  nlopt_set_maxeval(opt, max_evaluations);
  nlopt_set_initial_step(opt, step.data());
}

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

void uncertainty(Evaluator& ev, const std::vector<FitParameter>& parameters,
                 const FitOptions& options) {
  FitResult& r = ev.result;
  const auto p = static_cast<Eigen::Index>(parameters.size());
  const auto m = static_cast<Eigen::Index>(r.residuals.size());
  const std::vector<double> u0 = ev.best_unit;
  const double h = options.jacobian_step;
  Eigen::MatrixXd j(m, p);
  const auto at = [&](Eigen::Index i, double ui, Eigen::VectorXd& out) {
    std::vector<double> u = u0;
    u[i] = ui;
    std::vector<double> res;
    bool ok = false;
    ev(u, -1, &res, &ok);
    if (!ok) return false;
    out = Eigen::Map<const Eigen::VectorXd>(res.data(), m);
    return true;
  };
  const Eigen::VectorXd r0 = Eigen::Map<const Eigen::VectorXd>(r.residuals.data(), m);
  for (Eigen::Index i = 0; i < p; ++i) {
    Eigen::VectorXd plus, minus;
    const double ui = u0[i];
    const bool up = ui + h <= 1.0 && at(i, ui + h, plus);
    const bool down = ui - h >= 0.0 && at(i, ui - h, minus);
    if (up && down) {
      j.col(i) = (plus - minus) / (2.0 * h);
    } else if (up) {
      j.col(i) = (plus - r0) / h;
    } else if (down) {
      j.col(i) = (r0 - minus) / h;
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

FitResult fit(const Model& model, const std::vector<FitParameter>& parameters,
              const FitOptions& options, const HistorySink& sink,
              const std::vector<HistoryRow>& replay) {
  if (auto e = validate(parameters); !e.empty()) throw std::invalid_argument(e);
  if (auto e = options.validate(); !e.empty()) throw std::invalid_argument(e);
  const auto began = Clock::now();
  const auto n = static_cast<unsigned>(parameters.size());
  Evaluator ev(model, parameters, options, sink, replay);

  std::vector<double> start_values;
  for (const auto& p : parameters) start_values.push_back(p.start);
  std::vector<std::vector<double>> starts = {to_unit(parameters, start_values)};
  for (auto& u : latin_hypercube(options.starts, static_cast<int>(n), options.seed)) {
    starts.push_back(u);
  }

  const auto run = [&](nlopt_opt opt, int start, std::vector<double> x) {
    Callback cb{&ev, start, opt, nullptr};
    nlopt_set_min_objective(opt, objective, &cb);
    ev.start_best = std::numeric_limits<double>::infinity();
    ev.start_evaluations = 0;
    double f = 0.0;
    const nlopt_result res = nlopt_optimize(opt, x.data(), &f);
    if (cb.error) std::rethrow_exception(cb.error);
    StartSummary s;
    s.start = start;
    s.from = from_unit(parameters, starts[std::min<std::size_t>(start, starts.size() - 1)]);
    s.objective = ev.start_best;
    s.evaluations = ev.start_evaluations;
    s.stop_reason = nlopt_result_to_string(res);
    ev.result.starts.push_back(s);
    return s;
  };

  const std::string& a = options.algorithm;
  if (a == "direct" || a == "mlsl") {
    {
      Optimizer global(a == "direct" ? NLOPT_GN_DIRECT_L : NLOPT_G_MLSL_LDS, n);
      configure(global.opt, n, options, options.max_evaluations);
      Optimizer local(local_id(options.local_algorithm), n);
      if (a == "mlsl") {
        nlopt_srand(options.seed);
        configure(local.opt, n, options, options.max_evaluations);
        nlopt_set_local_optimizer(global.opt, local.opt);
      }
      run(global.opt, 0, starts[0]);
    }
    // Polish the global phase's best point with the local search.
    if (ev.result.ok) {
      Optimizer local(local_id(options.local_algorithm), n);
      configure(local.opt, n, options, options.max_evaluations);
      run(local.opt, 0, ev.best_unit);
    }
  } else {
    for (std::size_t k = 0; k < starts.size(); ++k) {
      Optimizer local(local_id(a), n);
      configure(local.opt, n, options, options.max_evaluations);
      run(local.opt, static_cast<int>(k), starts[k]);
    }
  }

  FitResult& r = ev.result;
  if (r.ok) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& s : r.starts) {
      if (s.objective < best) {
        best = s.objective;
        r.stop_reason = s.stop_reason;
      }
    }
    uncertainty(ev, parameters, options);
  } else {
    r.stop_reason = "every evaluation failed";
    r.warnings.push_back("every model evaluation failed; last: " + ev.last_failure);
  }
  r.evaluations = r.model_evaluations + r.replayed;
  r.seconds = std::chrono::duration<double>(Clock::now() - began).count();
  return r;
}

}  // namespace jointhb::fit
