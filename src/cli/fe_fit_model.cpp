// The finite-element adapter of the identification (fe_fit_model.hpp).
#include "fe_fit_model.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "fe_dynamics_run.hpp"
#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/hb/interface_mode.hpp"
#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/fe_fit_parameters.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/contact_patches.hpp"
#include "jointhb/reduction/modal_interface.hpp"

namespace jointhb::cli {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

fit::PredictedCurve failed(std::string message) {
  fit::PredictedCurve c;
  c.ok = false;
  c.message = std::move(message);
  return c;
}

// Above this many unknowns the on-curve correction (a dense LU per Newton step) is skipped and the
// curve is interpolated.
constexpr Eigen::Index kDenseCorrectionLimit = 4000;

// The curve's point at exactly λ = log10 q: Newton's method on the EPMC residual at fixed λ
// (dense Jacobian), from the unknowns interpolated linearly in λ between the bracketing
// continuation points. Returns false (and leaves the caller to interpolate) when it does not
// converge to the continuation's tolerance in 20 iterations.
bool point_on_curve(const hb::InterfaceModeResidual& epmc, double lambda, double tolerance, Eigen::VectorXd& y) {
  hb::InterfaceModeResidual::Evaluation e;
  for (int it = 0; it < 20; ++it) {
    epmc.evaluate(y, lambda, true, e);
    if (!e.ok || !e.residual.allFinite()) return false;
    if (e.residual.lpNorm<Eigen::Infinity>() <= tolerance) return true;
    const Eigen::VectorXd dy = e.d_state.partialPivLu().solve(-e.residual);
    if (!dy.allFinite()) return false;
    y += dy;
  }
  epmc.evaluate(y, lambda, false, e);
  return e.ok && e.residual.lpNorm<Eigen::Infinity>() <= tolerance;
}

}  // namespace

FeFitModel::FeFitModel(std::string case_text, std::string file_name, std::vector<std::string> names,
                       std::vector<fit::Target> targets, const std::filesystem::path& cache_dir,
                       bool friction_in_dynamics_only)
    : text_(std::move(case_text)),
      file_(std::move(file_name)),
      names_(std::move(names)),
      targets_(std::move(targets)),
      friction_in_dynamics_only_(friction_in_dynamics_only),
      cache_(cache_dir, true) {}

io::FeCase FeFitModel::case_at(const std::vector<double>& values) const {
  return io::parse_fe_case(io::set_fe_fit_parameters(text_, names_, values), file_);
}

fit::ModelPrediction FeFitModel::predict(const std::vector<double>& values) const {
  fit::ModelPrediction out;
  const auto fail_all = [&](const std::string& message) {
    out.ok = false;
    out.message = message;
    out.curves.assign(targets_.size(), failed(message));
    return out;
  };
  try {
    // The case the stages see: with friction_in_dynamics_only, without the interfaces' mu and n.
    std::vector<std::string> stage_names;
    std::vector<double> stage_values;
    bool dynamic_only = false;
    for (std::size_t k = 0; k < names_.size(); ++k) {
      const bool friction = names_[k].rfind("interfaces.", 0) == 0 &&
                            (names_[k].ends_with(".mu") || names_[k].ends_with(".n"));
      if (friction_in_dynamics_only_ && friction) {
        dynamic_only = true;
      } else {
        stage_names.push_back(names_[k]);
        stage_values.push_back(values[k]);
      }
    }
    const io::FeCase c = io::parse_fe_case(io::set_fe_fit_parameters(text_, stage_names, stage_values), file_);
    const std::optional<io::FeCase> dynamic = dynamic_only ? std::optional<io::FeCase>(case_at(values)) : std::nullopt;
    // ---- preload (stage cache: recomputed only when the model or analysis.preload changed) -------
    const preload::PreloadModel model = io::preload_model(c);
    std::optional<preload::PreloadResult> p = cache_.load_preload(c.fingerprints.preload);
    if (p && p->displacement.size() == c.mesh.num_dofs()) {
      ++counters_.preload_cached;
    } else {
      p = preload::solve_preload(model, c.preload);
      ++counters_.preload_solved;
      if (!p->converged) return fail_all("preload: " + p->message);
      cache_.store_preload(c.fingerprints.preload, *p);
    }
    // ---- modes of K_t ------------------------------------------------------------------------------
    const fe::DofMap dofs = fe::DofMap::from_fixed_nodes(c.mesh.num_nodes(), c.constraints);
    std::optional<modal::ModalResult> m = cache_.load_modes(c.fingerprints.modes);
    if (m && m->shapes.rows() == dofs.num_free()) {
      ++counters_.modes_cached;
    } else {
      m = modal::compute_modes(dofs.restrict(p->dynamic_stiffness), dofs.restrict(model.structure.mass),
                               c.modes.value_or(modal::ModalOptions{}));
      ++counters_.modes_solved;
      if (m->status != modal::ModalStatus::converged) return fail_all("modes: " + m->message);
      cache_.store_modes(c.fingerprints.modes, *m);
    }
    const std::vector<double> elastic = elastic_frequencies(*m);
    double a = 0.0, b = 0.0;  // Rayleigh damping as the dynamic stage resolves it
    std::optional<InterfaceSettings> settings;
    if (c.dynamics) {
      settings = resolve_interface_settings(c, *m);
      a = settings->options.rayleigh_mass;
      b = settings->options.rayleigh_stiffness;
    }
    // ---- condensed model, built when a backbone target needs it --------------------------------------
    std::optional<hb::InterfaceModel> im;
    const auto interface_model = [&]() -> const hb::InterfaceModel& {
      if (im) return *im;
      const io::FeDynamicsSpec& d = *c.dynamics;
      const int n = c.mesh.num_dofs();
      const reduction::ModalLoad load{d.excitation.name.empty() ? "none" : d.excitation.name,
                                      d.excitation.name.empty() ? Eigen::VectorXd::Zero(n) : d.excitation.functional(n)};
      std::vector<reduction::ModalOutputSpec> outputs;
      for (const io::FeNodeDirection& o : d.outputs) outputs.push_back({o.name, o.functional(n)});
      const std::string key = interface_model_key(c, settings->options, load, outputs);
      std::vector<contact::ContactPoint> laws;
      for (const auto& ci : model.interfaces) laws.push_back(ci.law);
      im = cache_.load_interface_model(key, laws);
      if (im) {
        ++counters_.condensation_cached;
      } else {
        im = reduction::build_modal_interface(model, *p, load, outputs, settings->options).model;
        ++counters_.condensed;
        cache_.store_interface_model(key, *im);
      }
      im->rayleigh_mass = a;
      im->rayleigh_stiffness = b;
      if (dynamic)  // the fitted friction in the laws of the dynamics only
        for (std::size_t g = 0; g < im->groups.size(); ++g) im->groups[g].law = dynamic->interfaces[g].law;
      im = reduction::merge_contact_patches(*im, model, {.size = d.contact_patch}).model;
      return *im;
    };
    // ---- the curves ------------------------------------------------------------------------------------
    for (const fit::Target& t : targets_) {
      fit::PredictedCurve curve;
      if (t.kind == fit::TargetKind::modal) {
        for (std::size_t k = 0; k < elastic.size(); ++k) {
          const double w = kTwoPi * elastic[k];
          curve.abscissa.push_back(static_cast<double>(k + 1));
          curve.frequency_hz.push_back(elastic[k]);
          curve.damping_ratio.push_back(0.5 * (a / w + b * w));
        }
      } else if (t.kind == fit::TargetKind::backbone) {
        const io::FeNonlinearModesSpec& nm = *c.dynamics->nonlinear_modes;
        double q_max = 0.0;
        for (const auto& pt : t.points) q_max = std::max(q_max, pt.abscissa);
        continuation::InterfaceBackboneOptions o;
        o.mode.mode = t.mode;
        o.mode.balance = nm.balance;
        o.log10_amplitude_start = nm.log10_amplitude_start;
        o.log10_amplitude_end = std::min(nm.log10_amplitude_end, std::log10(q_max) + 0.1);
        o.continuation = nm.continuation;
        if (!(o.log10_amplitude_end > o.log10_amplitude_start)) {
          curve = failed(fmt::format("{}: the measured amplitudes lie below the curve's start", t.name));
        } else {
          const continuation::InterfaceBackbone bb = continuation::trace_interface_backbone(interface_model(), o);
          ++counters_.curves;
          std::vector<double> lambdas;
          for (const auto& pt : bb.points) {
            curve.abscissa.push_back(pt.state.amplitude);
            curve.frequency_hz.push_back(pt.state.omega / kTwoPi);
            curve.damping_ratio.push_back(pt.state.damping_ratio);
            lambdas.push_back(std::log10(pt.state.amplitude));
          }
          if (!bb.completed()) curve.message = bb.message;  // points beyond the last one fail in residuals()
          // The values at the measured amplitudes on the curve itself (not interpolated between
          // continuation points, whose error would move with the parameters).
          hb::InterfaceModeOptions mo;
          mo.mode = t.mode;
          mo.balance = nm.balance;
          mo.balance.dense_jacobian = true;
          const hb::InterfaceModeResidual epmc(interface_model(), mo);
          if (epmc.unknowns() <= kDenseCorrectionLimit) {
            for (const fit::TargetPoint& tp : t.points) {
              const double at = std::log10(tp.abscissa);
              const auto hi = std::upper_bound(lambdas.begin(), lambdas.end(), at);
              if (hi == lambdas.begin() || hi == lambdas.end()) {  // outside: residuals() reports it
                curve.at_points.clear();
                break;
              }
              const std::size_t k1 = static_cast<std::size_t>(hi - lambdas.begin()), k = k1 - 1;
              const double w = (at - lambdas[k]) / (lambdas[k1] - lambdas[k]);
              Eigen::VectorXd y = (1.0 - w) * bb.points[k].unknowns + w * bb.points[k1].unknowns;
              const bool damping = tp.quantity == fit::Quantity::damping_ratio;
              double value = damping ? (1.0 - w) * curve.damping_ratio[k] + w * curve.damping_ratio[k1]
                                     : (1.0 - w) * curve.frequency_hz[k] + w * curve.frequency_hz[k1];
              if (point_on_curve(epmc, at, nm.continuation.residual_tolerance, y)) {
                const hb::InterfaceModeState st = epmc.state(y, at);
                value = damping ? st.damping_ratio : st.omega / kTwoPi;
                ++counters_.corrected;
              }
              curve.at_points.push_back(value);
            }
          }
        }
      } else {  // frf: the case's analysis.frf at the target's force level, its output's |fundamental|
        const io::FeFrfSpec& fs = *c.dynamics->frf;
        continuation::InterfaceFrfOptions o;
        o.omega_start = fs.omega_start;
        o.omega_end = fs.omega_end;
        o.load_amplitude = fs.forces[static_cast<std::size_t>(t.level)];
        o.output = fs.output;
        o.balance = fs.balance;
        o.continuation = fs.continuation;
        const continuation::InterfaceFrf r = continuation::trace_interface_frf(interface_model(), o);
        ++counters_.curves;
        for (const auto& pt : r.points) {
          curve.abscissa.push_back(pt.omega / kTwoPi);
          curve.amplitude.push_back(pt.amplitude_h1);
        }
        if (!r.completed()) curve.message = r.message;
      }
      out.curves.push_back(std::move(curve));
    }
  } catch (const std::exception& e) {
    return fail_all(e.what());
  }
  return out;
}

fit::Model FeFitModel::model() const {
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

}  // namespace jointhb::cli
