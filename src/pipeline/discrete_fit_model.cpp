#include "jointhb/pipeline/discrete_fit_model.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

#include "jointhb/continuation/backbone.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/hb/harmonic_balance.hpp"
#include "jointhb/hb/nonlinear_mode.hpp"

namespace jointhb::pipeline {

using namespace jointhb::fit;  // the adapter speaks the identification's types

namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;
constexpr int max_newton_iterations = 20;

std::string name_list(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// "contacts[3].mu" -> (3, "mu"); false when not of that form.
bool indexed(const std::string& name, const std::string& prefix, std::size_t& index,
             std::string& field) {
  if (name.rfind(prefix + "[", 0) != 0) return false;
  const auto close = name.find(']', prefix.size());
  if (close == std::string::npos) return false;
  const std::string digits = name.substr(prefix.size() + 1, close - prefix.size() - 1);
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) return false;
  index = std::stoul(digits);
  field = close + 1 < name.size() && name[close + 1] == '.' ? name.substr(close + 2) : "";
  return close + 1 == name.size() || name[close + 1] == '.';
}

// Newton's method on a square system F(y) = 0 with Jacobian J(y).
template <class Evaluate>
bool newton(Eigen::VectorXd& y, const Evaluate& evaluate) {
  for (int it = 0; it < max_newton_iterations; ++it) {
    Eigen::VectorXd r;
    Eigen::MatrixXd j;
    if (!evaluate(y, r, j)) return false;
    const Eigen::VectorXd dy = j.partialPivLu().solve(-r);
    if (!dy.allFinite()) return false;
    y += dy;
    if (dy.lpNorm<Eigen::Infinity>() <= 1e-11 * std::max(1.0, y.lpNorm<Eigen::Infinity>())) {
      return true;
    }
  }
  return false;
}

// The segment k of a polyline x_k containing `at` (the first; the largest `score` with folds).
bool bracket(const std::vector<double>& x, double at, const std::vector<double>* score,
             std::size_t& k, double& t) {
  bool found = false;
  double best = 0.0;
  for (std::size_t i = 0; i + 1 < x.size(); ++i) {
    const double lo = std::min(x[i], x[i + 1]);
    const double hi = std::max(x[i], x[i + 1]);
    if (at < lo || at > hi) continue;
    const double ti = hi > lo ? (at - x[i]) / (x[i + 1] - x[i]) : 0.0;
    const double s = score ? (*score)[i] + ti * ((*score)[i + 1] - (*score)[i]) : 0.0;
    if (!found || (score && s > best)) {
      k = i;
      t = ti;
      best = s;
    }
    found = true;
    if (!score) break;
  }
  return found;
}

PredictedCurve predict_backbone(const DiscreteProblem& c, const Target& target) {
  PredictedCurve out;
  if (!c.nonlinear_modes) {
    out.ok = false;
    out.message = "a backbone target needs analysis.nonlinear_modes in the case";
    return out;
  }
  continuation::BackboneOptions options = *c.nonlinear_modes;
  options.mode.mode = target.mode;
  // One level (the case's starting harmonics): the unknowns are interpolated between points and the
  // objective must be smooth in the parameters, not switch levels per point.
  options.accuracy = continuation::Accuracy{};
  // Trace only as far as the measurements need (a tenth of a decade beyond the largest): less
  // work, and no failure beyond the data.
  double largest = 0.0;
  for (const auto& point : target.points) largest = std::max(largest, point.abscissa);
  if (options.log10_amplitude_end > options.log10_amplitude_start && largest > 0.0) {
    const double needed = std::log10(largest) + 0.1;
    if (needed > options.log10_amplitude_start && needed < options.log10_amplitude_end) {
      options.log10_amplitude_end = needed;
    }
  }
  options.error_estimate = false;  // a fit uses the points alone: the estimates would cost for nothing
  const continuation::BackboneCurve curve = continuation::trace_backbone(c.system, options);
  std::vector<double> lambda;
  for (const auto& p : curve.points) {
    out.abscissa.push_back(p.state.amplitude);
    out.frequency_hz.push_back(p.state.omega / two_pi);
    out.damping_ratio.push_back(p.state.damping_ratio);
    lambda.push_back(std::log10(p.state.amplitude));
  }
  const hb::NonlinearModeResidual epmc(c.system, options.mode);
  for (const auto& point : target.points) {
    const double at = std::log10(point.abscissa);
    std::size_t k = 0;
    double t = 0.0;
    if (!bracket(lambda, at, nullptr, k, t)) {
      out.ok = false;
      out.message =
          fmt::format("measured amplitude {} lies outside the predicted curve (q from {} to {}{})",
                      point.abscissa, out.abscissa.empty() ? 0.0 : out.abscissa.front(),
                      out.abscissa.empty() ? 0.0 : out.abscissa.back(),
                      curve.completed() ? "" : "; the continuation stopped: " + curve.message);
      return out;
    }
    Eigen::VectorXd y = (1.0 - t) * curve.points[k].unknowns + t * curve.points[k + 1].unknowns;
    const Eigen::VectorXd guess = y;
    const bool converged =
        newton(y, [&](const Eigen::VectorXd& v, Eigen::VectorXd& r, Eigen::MatrixXd& j) {
          hb::NonlinearModeResidual::Evaluation ev;
          epmc.evaluate(v, at, true, ev);
          if (!ev.ok) return false;
          r = ev.residual;
          j = ev.d_state;
          return r.allFinite();
        });
    double value = 0.0;
    if (converged) {
      const hb::NonlinearModeState s = epmc.state(y, at);
      value = point.quantity == Quantity::damping_ratio ? s.damping_ratio : s.omega / two_pi;
    } else {
      const std::size_t k1 = k + 1;
      const auto& a =
          point.quantity == Quantity::damping_ratio ? out.damping_ratio : out.frequency_hz;
      value = (1.0 - t) * a[k] + t * a[k1];
    }
    out.at_points.push_back(value);
  }
  return out;
}

PredictedCurve predict_frf(const DiscreteProblem& c, const Target& target) {
  PredictedCurve out;
  if (!c.frf) {
    out.ok = false;
    out.message = "an frf target needs analysis.frf in the case";
    return out;
  }
  if (target.level < 0 || target.level >= static_cast<int>(c.levels.size())) {
    out.ok = false;
    out.message =
        fmt::format("level {} does not exist (the case has {})", target.level, c.levels.size());
    return out;
  }
  // A fit compares amplitudes at the targets' frequencies: stability, the located extrema and the
  // error estimates would cost an eigenproblem or a monodromy per point of every evaluation for nothing.
  continuation::FrfOptions options = *c.frf;
  options.stability = continuation::Stability::never;
  options.refine_extrema = false;
  options.error_estimate = false;  // nor the error estimates (continuation/error_estimate.hpp)
  const hb::Excitation& level = c.levels[static_cast<std::size_t>(target.level)];
  const continuation::FrfCurve curve = continuation::trace_frf(c.system, level, options);
  std::vector<double> omega, amplitude;
  for (const auto& p : curve.points) {
    out.abscissa.push_back(p.omega / two_pi);
    out.amplitude.push_back(p.amplitude_h1);
    omega.push_back(p.omega);
    amplitude.push_back(p.amplitude_h1);
  }
  hb::HarmonicBalanceOptions ho;
  ho.harmonics = options.harmonics;
  ho.time_samples = options.time_samples;
  ho.selection = options.selection;
  ho.periodic_tolerance = options.periodic_tolerance;
  const hb::HarmonicBalance balance(c.system, level, ho);
  for (const auto& point : target.points) {
    const double at = two_pi * point.abscissa;
    std::size_t k = 0;
    double t = 0.0;
    if (!bracket(omega, at, &amplitude, k, t)) {
      out.ok = false;
      out.message = fmt::format(
          "measured frequency {} Hz lies outside the predicted curve{}", point.abscissa,
          curve.completed() ? "" : " (the continuation stopped: " + curve.message + ")");
      return out;
    }
    const auto& x0 = curve.points[k].coefficients;
    const auto& x1 = curve.points[k + 1].coefficients;
    double value = (1.0 - t) * amplitude[k] + t * amplitude[k + 1];
    if (x0.size() == balance.unknowns() && x1.size() == balance.unknowns()) {
      Eigen::VectorXd x = (1.0 - t) * x0 + t * x1;
      const bool converged =
          newton(x, [&](const Eigen::VectorXd& v, Eigen::VectorXd& r, Eigen::MatrixXd& j) {
            hb::HarmonicBalanceEvaluation ev;
            balance.evaluate(v, at, true, ev);
            r = ev.residual;
            j = ev.d_coefficients;
            return r.allFinite();
          });
      if (converged) value = balance.fundamental_amplitude(x, options.output_dof);
    }
    out.at_points.push_back(value);
  }
  return out;
}

PredictedCurve predict_modal(const DiscreteProblem& c) {
  PredictedCurve out;
  const hb::LinearModes modes = hb::linear_modes(c.system, true);
  const Eigen::MatrixXd damping = c.system.damping.rows()
                                      ? Eigen::MatrixXd(c.system.damping)
                                      : Eigen::MatrixXd::Zero(c.system.dofs(), c.system.dofs());
  for (Eigen::Index k = 0; k < modes.omega.size(); ++k) {
    const Eigen::VectorXd phi = modes.shapes.col(k);
    out.abscissa.push_back(static_cast<double>(k + 1));
    out.frequency_hz.push_back(modes.omega[k] / two_pi);
    out.damping_ratio.push_back(phi.dot(damping * phi) / (2.0 * modes.omega[k]));
  }
  return out;  // residuals() picks the modes by number
}

}  // namespace

std::vector<std::string> discrete_parameter_names(const DiscreteProblem& c) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < c.system.contacts.size(); ++i) {
    if (c.system.contacts[i].normal()) {
      for (const char* field : {"kn", "normal_force"}) names.push_back(fmt::format("contacts[{}].{}", i, field));
      continue;
    }
    for (const char* field : {"kt0", "mu", "normal_force"}) {
      names.push_back(fmt::format("contacts[{}].{}", i, field));
    }
    if (c.system.contacts[i].law == "gaul-mayer") names.push_back(fmt::format("contacts[{}].n", i));
  }
  if (c.damping_model == "rayleigh") {
    names.emplace_back("damping.rayleigh.alpha");
    names.emplace_back("damping.rayleigh.beta");
  } else if (c.damping_model == "modal") {
    for (std::size_t k = 0; k < c.modal_damping_ratios.size(); ++k) {
      names.push_back(fmt::format("damping.modal[{}]", k));
    }
  }
  return names;
}

void set_model_parameters(DiscreteProblem& c, const std::vector<std::string>& names,
                          const std::vector<double>& values) {
  if (names.size() != values.size()) {
    throw std::invalid_argument(
        fmt::format("{} parameter names for {} values", names.size(), values.size()));
  }
  bool damping_changed = false;
  for (std::size_t p = 0; p < names.size(); ++p) {
    const std::string& name = names[p];
    const double v = values[p];
    std::size_t i = 0;
    std::string field;
    bool known = false;
    if (indexed(name, "contacts", i, field) && i < c.system.contacts.size()) {
      hb::ContactElement& e = c.system.contacts[i];
      known = true;
      if (field == (e.normal() ? "kn" : "kt0")) {
        e.stiffness = v;
      } else if (field == "mu" && !e.normal()) {
        e.friction_coefficient = v;
      } else if (field == "normal_force") {
        e.normal_force = v;
      } else if (field == "n" && e.law == "gaul-mayer") {
        e.exponent = v;
      } else {
        known = false;
      }
    } else if (c.damping_model == "rayleigh" && name == "damping.rayleigh.alpha") {
      known = damping_changed = true;
      c.rayleigh_alpha = v;
    } else if (c.damping_model == "rayleigh" && name == "damping.rayleigh.beta") {
      known = damping_changed = true;
      c.rayleigh_beta = v;
    } else if (c.damping_model == "modal" && indexed(name, "damping.modal", i, field) &&
               field.empty() && i < c.modal_damping_ratios.size()) {
      known = damping_changed = true;
      c.modal_damping_ratios[i] = v;
    }
    if (!known) {
      throw std::invalid_argument(fmt::format("unknown parameter '{}'; this case has: {}", name,
                                              name_list(discrete_parameter_names(c))));
    }
  }
  if (damping_changed) {
    if (c.damping_model == "rayleigh") {
      if (c.rayleigh_alpha < 0.0 || c.rayleigh_beta < 0.0) {
        throw std::invalid_argument("damping.rayleigh: alpha and beta must be >= 0");
      }
      c.system.damping = c.rayleigh_alpha * c.system.mass + c.rayleigh_beta * c.system.stiffness;
    } else {
      for (double z : c.modal_damping_ratios) {
        if (z < 0.0) throw std::invalid_argument("damping.modal: ratios must be >= 0");
      }
      c.system.damping =
          hb::modal_damping_matrix(c.system.mass, c.system.stiffness, c.modal_damping_ratios);
    }
  }
  if (const std::string message = c.system.validate(); !message.empty()) {
    throw std::invalid_argument(message);
  }
}

ModelPrediction predict(const DiscreteProblem& c, const std::vector<Target>& targets) {
  ModelPrediction out;
  for (const auto& target : targets) {
    switch (target.kind) {
      case TargetKind::backbone:
        out.curves.push_back(predict_backbone(c, target));
        break;
      case TargetKind::frf:
        out.curves.push_back(predict_frf(c, target));
        break;
      case TargetKind::modal:
        out.curves.push_back(predict_modal(c));
        break;
    }
  }
  return out;
}

Model discrete_model(const DiscreteProblem& base, const std::vector<std::string>& names,
                     const std::vector<Target>& targets) {
  return [base, names, targets](const std::vector<double>& values) {
    DiscreteProblem c = base;
    Evaluation e;
    try {
      set_model_parameters(c, names, values);
      const ResidualEvaluation r = residuals(targets, predict(c, targets));
      e.ok = r.ok;
      e.message = r.message;
      e.residuals = r.residuals;
    } catch (const std::exception& ex) {
      e.ok = false;
      e.message = ex.what();
    }
    return e;
  };
}

}  // namespace jointhb::pipeline
