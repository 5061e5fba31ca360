// The finite-element model of the identification (pipeline/fe_fit_model.hpp).
#include "jointhb/pipeline/fe_fit_model.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <numbers>

#include "../support/gmres.hpp"
#include "../support/numeric_constants.hpp"
#include "jointhb/hb/interface_mode.hpp"

namespace jointhb::pipeline {
namespace {

using support::kTwoPi;

// Above this many unknowns the on-curve correction is matrix-free (GMRES on the EPMC Jacobian's
// products, preconditioned point-locally, as the damping curve itself is solved) instead of a
// dense LU per Newton step. On case 12's lap (~1400 unknowns) both give the same residuals to
// 3e-13 relative and the matrix-free one halves the fit's time; the BRB (21 000 unknowns) was not
// corrected at all before.
constexpr Eigen::Index kDenseCorrectionLimit = 1000;
// GMRES iterations per Newton step of the matrix-free correction, and its relative tolerance.
constexpr int kCorrectionKrylovIterations = 200;
constexpr double kCorrectionKrylovTolerance = 1e-10;
// Newton iterations of the on-curve correction.
constexpr int kCorrectionIterations = 20;

fit::PredictedCurve failed(std::string message) {
  fit::PredictedCurve c;
  c.ok = false;
  c.message = std::move(message);
  return c;
}

// The curve's point at exactly λ = log10 q: Newton's method on the EPMC residual at fixed λ
// (dense Jacobian), from the unknowns interpolated linearly in λ between the bracketing
// continuation points. Returns false (and leaves the caller to interpolate) when it does not
// converge to the continuation's tolerance.
// With a matrix-free epmc (balance.dense_jacobian = false) each Newton step is solved by GMRES
// with epmc.apply_jacobian and the point-local preconditioner (eq. T-34), to a true relative
// residual of kCorrectionKrylovTolerance.
bool point_on_curve(const hb::InterfaceModeResidual& epmc, double lambda, double tolerance, Eigen::VectorXd& y) {
  hb::InterfaceModeResidual::Evaluation e;
  const bool dense = epmc.balance().options().dense_jacobian;
  for (int it = 0; it < kCorrectionIterations; ++it) {
    epmc.evaluate(y, lambda, true, e);
    if (!e.ok || !e.residual.allFinite()) return false;
    if (e.residual.lpNorm<Eigen::Infinity>() <= tolerance) return true;
    Eigen::VectorXd dy;
    if (dense) {
      dy = e.d_state.partialPivLu().solve(-e.residual);
    } else {
      const auto apply = [&](const Eigen::VectorXd& v) { return epmc.apply_jacobian(e, y, lambda, v); };
      const auto precondition = epmc.preconditioner(e, y, lambda, hb::InterfacePreconditioner::point_local);
      support::gmres(apply, precondition, -e.residual, kCorrectionKrylovIterations, kCorrectionKrylovTolerance, dy);
      if (!((apply(dy) + e.residual).norm() <= 1e-6 * e.residual.norm())) return false;  // true residual
    }
    if (!dy.allFinite()) return false;
    y += dy;
  }
  epmc.evaluate(y, lambda, false, e);
  return e.ok && e.residual.lpNorm<Eigen::Infinity>() <= tolerance;
}

bool is_friction(const std::string& name) {
  return name.rfind("interfaces.", 0) == 0 && (name.ends_with(".mu") || name.ends_with(".n"));
}

}  // namespace

FeFitModel::FeFitModel(FePipeline& pipeline, std::vector<std::string> names, std::vector<fit::Target> targets,
                       bool friction_in_dynamics_only)
    : pipeline_(pipeline),
      names_(std::move(names)),
      targets_(std::move(targets)),
      friction_in_dynamics_only_(friction_in_dynamics_only) {}

void FeFitModel::set(const std::vector<double>& values) {
  if (values.size() != names_.size())
    throw std::invalid_argument(fmt::format("fit: {} values for {} parameters", values.size(), names_.size()));
  for (std::size_t k = 0; k < names_.size(); ++k) {
    const ParameterScope scope = friction_in_dynamics_only_ && is_friction(names_[k]) ? ParameterScope::dynamics
                                                                                       : ParameterScope::everywhere;
    pipeline_.set_parameter(names_[k], values[k], scope);
  }
}

fit::PredictedCurve FeFitModel::modal_curve() {
  fit::PredictedCurve curve;
  const modal::ModalResult& m = pipeline_.modes();
  if (m.termination != Termination::converged) return failed("modes: " + m.message);
  double a = 0.0, b = 0.0;  // Rayleigh damping as the dynamic stage resolves it
  if (pipeline_.analysis().dynamics) {
    const InterfaceSettings s = resolve_interface_settings(*pipeline_.analysis().dynamics, pipeline_.modal_options(), m);
    a = s.options.rayleigh_mass;
    b = s.options.rayleigh_stiffness;
  }
  const std::vector<double> elastic = elastic_frequencies(m);
  for (std::size_t k = 0; k < elastic.size(); ++k) {
    const double w = kTwoPi * elastic[k];
    curve.abscissa.push_back(static_cast<double>(k + 1));
    curve.frequency_hz.push_back(elastic[k]);
    curve.damping_ratio.push_back(0.5 * (a / w + b * w));
  }
  return curve;
}

fit::PredictedCurve FeFitModel::backbone_curve(const fit::Target& t) {
  FeNonlinearModesSpec nm = *pipeline_.analysis().dynamics->nonlinear_modes;
  double q_max = 0.0;
  for (const auto& pt : t.points) q_max = std::max(q_max, pt.abscissa);
  nm.log10_amplitude_end = std::min(nm.log10_amplitude_end, std::log10(q_max) + 0.1);
  nm.frequency_drop = 0.0;
  nm.error_estimate = false;  // a fit uses the points alone: the estimates would cost for nothing
  // A fit interpolates the unknowns between points and needs an objective that is smooth in the
  // parameters: one level (the case's starting harmonics), not levels that switch per point.
  nm.accuracy = continuation::Accuracy{};
  if (!(nm.log10_amplitude_end > nm.log10_amplitude_start))
    return failed(fmt::format("{}: the measured amplitudes lie below the curve's start", t.name));
  const BackboneCurve bb = pipeline_.backbone(t.mode, nm);
  fit::PredictedCurve curve;
  std::vector<double> lambdas;
  for (const auto& pt : bb.curve.points) {
    curve.abscissa.push_back(pt.state.amplitude);
    curve.frequency_hz.push_back(pt.state.omega / kTwoPi);
    curve.damping_ratio.push_back(pt.state.damping_ratio);
    lambdas.push_back(std::log10(pt.state.amplitude));
  }
  if (!bb.status().ok()) curve.message = bb.stop_message;  // points beyond the last one fail in residuals()
  // The values at the measured amplitudes on the curve itself (not interpolated between
  // continuation points, whose error would move with the parameters).
  hb::InterfaceModeOptions mo;
  mo.mode = t.mode;
  mo.balance = nm.balance;
  mo.balance.dense_jacobian = true;
  {
    const hb::InterfaceModeResidual probe(pipeline_.interface_stage().model, mo);
    mo.balance.dense_jacobian = probe.unknowns() <= kDenseCorrectionLimit;
  }
  const hb::InterfaceModeResidual epmc(pipeline_.interface_stage().model, mo);
  // One Newton correction per measured amplitude: a frequency and a damping target at the same
  // amplitude share it.
  std::map<double, std::optional<hb::InterfaceModeState>> on_curve;
  for (const fit::TargetPoint& tp : t.points) {
    const double at = std::log10(tp.abscissa);
    const auto hi = std::upper_bound(lambdas.begin(), lambdas.end(), at);
    if (hi == lambdas.begin() || hi == lambdas.end()) {  // outside: residuals() reports it
      curve.at_points.clear();
      break;
    }
    const std::size_t k1 = static_cast<std::size_t>(hi - lambdas.begin()), k = k1 - 1;
    const double w = (at - lambdas[k]) / (lambdas[k1] - lambdas[k]);
    const bool damping = tp.quantity == fit::Quantity::damping_ratio;
    double value = damping ? (1.0 - w) * curve.damping_ratio[k] + w * curve.damping_ratio[k1]
                           : (1.0 - w) * curve.frequency_hz[k] + w * curve.frequency_hz[k1];
    auto found = on_curve.find(at);
    if (found == on_curve.end()) {
      Eigen::VectorXd y = (1.0 - w) * bb.curve.points[k].unknowns + w * bb.curve.points[k1].unknowns;
      std::optional<hb::InterfaceModeState> st;
      if (point_on_curve(epmc, at, nm.continuation.residual_tolerance, y)) st = epmc.state(y, at);
      found = on_curve.emplace(at, st).first;
    }
    if (const std::optional<hb::InterfaceModeState>& st = found->second) {
      value = damping ? st->damping_ratio : st->omega / kTwoPi;
      ++corrected_;
    }
    curve.at_points.push_back(value);
  }
  return curve;
}

fit::PredictedCurve FeFitModel::frf_curve(const fit::Target& t) {
  FeFrfSpec fs = *pipeline_.analysis().dynamics->frf;
  fs.error_estimate = false;  // as for the damping curves
  const FrfCurve r = pipeline_.frf(static_cast<std::size_t>(t.level), fs);
  fit::PredictedCurve curve;
  for (const auto& pt : r.points) {
    curve.abscissa.push_back(pt.frequency_hz);
    curve.amplitude.push_back(pt.amplitude_h1);
  }
  if (!r.status().ok()) curve.message = r.curve.message;
  return curve;
}

fit::ModelPrediction FeFitModel::predict(const std::vector<double>& values) {
  fit::ModelPrediction out;
  try {
    set(values);
    if (pipeline_.needs_preload() && !pipeline_.preload().status().ok())
      throw StageError("preload: " + pipeline_.preload().message);
    if (pipeline_.modes().termination != Termination::converged) throw StageError("modes: " + pipeline_.modes().message);
    for (const fit::Target& t : targets_) {
      if (t.kind == fit::TargetKind::modal)
        out.curves.push_back(modal_curve());
      else if (t.kind == fit::TargetKind::backbone)
        out.curves.push_back(backbone_curve(t));
      else
        out.curves.push_back(frf_curve(t));
    }
  } catch (const std::exception& e) {
    out.ok = false;
    out.message = e.what();
    out.curves.assign(targets_.size(), failed(e.what()));
  }
  return out;
}

fit::Model FeFitModel::model() {
  return [this](const std::vector<double>& values) {
    fit::Evaluation e;
    const fit::ModelPrediction pred = predict(values);
    const fit::ResidualEvaluation r = fit::residuals(targets_, pred);
    e.ok = r.ok;
    e.message = r.ok ? std::string() : (r.message.empty() ? pred.message : r.message);
    e.residuals = r.residuals;
    return e;
  };
}

}  // namespace jointhb::pipeline
