// The finite-element pipeline (pipeline/fe_pipeline.hpp): stages on demand, memoised by key.
#include "jointhb/pipeline/fe_pipeline.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "jointhb/fe/rigid_body_modes.hpp"
#include "jointhb/hb/interface_balance.hpp"
#include "jointhb/pipeline/stage_names.hpp"
#include "jointhb/reduction/contact_patches.hpp"
#include "jointhb/reduction/modal_interface.hpp"

#include "../support/numeric_constants.hpp"
#include "../support/stopwatch.hpp"

namespace jointhb::pipeline {
namespace {

using support::Clock;
using support::kTwoPi;
using support::seconds_since;

bool all_finite(std::initializer_list<double> values) {
  for (const double v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace

FePipeline::FePipeline(FeModel model, FeAnalysis analysis, std::shared_ptr<StageStore> store)
    : model_(std::move(model)),
      analysis_(std::move(analysis)),
      store_(store ? std::move(store) : std::make_shared<NullStageStore>()),
      dynamic_laws_(model_.interfaces.size()) {}

const FeStageKeys& FePipeline::current_keys() {
  if (!keys_) keys_ = fe_stage_keys(model_, analysis_);
  return *keys_;
}

FeStageKeys FePipeline::keys() const { return keys_ ? *keys_ : fe_stage_keys(model_, analysis_); }

bool FePipeline::needs_preload() const {
  const bool stages_after = analysis_.modes.has_value() || analysis_.dynamics.has_value();
  return analysis_.preload_requested || (stages_after && (!model_.interfaces.empty() || !model_.bolts.empty()));
}

std::optional<modal::ModalOptions> FePipeline::modal_options() const {
  std::optional<modal::ModalOptions> o = analysis_.modes;
  if (!o && analysis_.dynamics) o = modal::ModalOptions{};
  if (o) {
    o->linear_solver = analysis_.solvers.linear;
    o->eigen_solver = analysis_.solvers.eigen;
    o->iterative = analysis_.solvers.iterative;
    if (o->linear_solver == fe::LinearSolver::cg && o->iterative.near_null_space.size() == 0) {
      // GAMG's near-null space, the rigid-body motions on the free DOFs: made once (the mesh and
      // the constraints never change; parameters set later touch laws, bolts and damping).
      if (!rigid_body_modes_) {
        rigid_body_modes_ = fe::rigid_body_modes(
            model_.mesh, fe::DofMap::from_fixed_nodes(model_.mesh.num_nodes(), model_.constraints));
      }
      o->iterative.near_null_space = *rigid_body_modes_;
    }
  }
  return o;
}

// ---- stages ----------------------------------------------------------------------------------------

const preload::PreloadModel& FePipeline::structure() {
  if (!structure_) {
    structure_ = preload_model(model_);
    ++counters_.assembled;
  }
  return *structure_;
}

const fe::DofMap& FePipeline::dofs() {
  if (!dofs_) dofs_ = fe::DofMap::from_fixed_nodes(model_.mesh.num_nodes(), model_.constraints);
  return *dofs_;
}

const preload::PreloadResult& FePipeline::preload() {
  const std::string& key = current_keys().preload;
  if (preload_ && preload_info_.key == key) {
    ++counters_.preload_reused;
    return *preload_;
  }
  StageInfo info;
  info.key = key;
  info.location = store_->location(stage_names::preload, key);
  const auto start = Clock::now();
  std::optional<preload::PreloadResult> stored = store_->load_preload(key);
  if (stored && (stored->interfaces.size() != model_.interfaces.size() ||
                 stored->bolt_forces.size() != model_.bolts.size() ||
                 stored->displacement.size() != model_.mesh.num_dofs())) {
    info.warning = fmt::format("{} does not fit this model; preload recomputed", info.location);
    stored.reset();
  }
  if (stored) {
    preload_ = std::move(stored);
    info.from_store = true;
    info.store_seconds = seconds_since(start);
    ++counters_.preload_read;
  } else {
    preload::PreloadOptions options = analysis_.preload;
    options.linear_solver = analysis_.solvers.linear;
    options.iterative = analysis_.solvers.iterative;
    preload_ = preload::solve_preload(structure(), options);
    ++counters_.preload_solved;
    if (preload_->status().ok()) {
      const auto store_start = Clock::now();
      store_->store_preload(key, *preload_);
      info.store_seconds = seconds_since(store_start);
    }
  }
  preload_info_ = std::move(info);
  return *preload_;
}

const modal::ModalResult& FePipeline::modes() {
  const std::string& key = current_keys().modes;
  if (modes_ && modes_info_.key == key) {
    ++counters_.modes_reused;
    return *modes_;
  }
  const bool preloaded = needs_preload();
  if (preloaded && !preload().status().ok()) throw StageError("preload: " + preload_->message);
  StageInfo info;
  info.key = key;
  info.location = store_->location(stage_names::modes, key);
  const auto start = Clock::now();
  std::optional<modal::ModalResult> stored = store_->load_modes(key);
  if (stored && stored->shapes.rows() != dofs().num_free()) {
    info.warning = fmt::format("{} does not fit this model; modes recomputed", info.location);
    stored.reset();
  }
  if (stored) {
    modes_ = std::move(stored);
    info.from_store = true;
    info.store_seconds = seconds_since(start);
    ++counters_.modes_read;
  } else {
    const Eigen::SparseMatrix<double>& stiffness = preloaded ? preload_->dynamic_stiffness : structure().structure.stiffness;
    modes_ = modal::compute_modes(dofs().restrict(stiffness), dofs().restrict(structure().structure.mass),
                                  modal_options().value_or(modal::ModalOptions{}));
    ++counters_.modes_solved;
    if (modes_->termination == Termination::converged) {
      const auto store_start = Clock::now();
      store_->store_modes(key, *modes_);
      info.store_seconds = seconds_since(store_start);
    }
  }
  modes_info_ = std::move(info);
  return *modes_;
}

reduction::ModalLoad FePipeline::load_vector() const {
  const FeDynamicsSpec& d = *analysis_.dynamics;
  const int n = model_.mesh.num_dofs();
  return {d.excitation.name.empty() ? "none" : d.excitation.name,
          d.excitation.name.empty() ? Eigen::VectorXd::Zero(n) : d.excitation.functional(n)};
}

std::vector<reduction::ModalOutputSpec> FePipeline::output_vectors() const {
  std::vector<reduction::ModalOutputSpec> outputs;
  for (const FeNodeDirection& o : analysis_.dynamics->outputs)
    outputs.push_back({o.name, o.functional(model_.mesh.num_dofs())});
  return outputs;
}

// The damping and the dynamics' contact laws: set on the kept model, they need no recondensation.
void FePipeline::refresh_dynamics(InterfaceStage& stage) const {
  stage.model.rayleigh_mass = stage.settings.options.rayleigh_mass;
  stage.model.rayleigh_stiffness = stage.settings.options.rayleigh_stiffness;
  stage.recovery.rayleigh_stiffness = stage.settings.options.rayleigh_stiffness;  // eq. T-33 uses b too
  for (std::size_t g = 0; g < stage.model.groups.size() && g < model_.interfaces.size(); ++g)
    stage.model.groups[g].law = dynamic_laws_[g] ? *dynamic_laws_[g] : model_.interfaces[g].law;
}

const InterfaceStage& FePipeline::interface_stage() {
  if (!analysis_.dynamics) throw std::invalid_argument("the analysis has no dynamics (nonlinear_modes or frf)");
  if (model_.interfaces.empty())
    throw std::invalid_argument("analysis.nonlinear_modes / frf need a model with interfaces (model.interfaces)");
  const FeDynamicsSpec& d = *analysis_.dynamics;
  const modal::ModalResult& m = modes();
  if (m.termination != Termination::converged) throw StageError("modes: " + m.message);
  InterfaceSettings settings = resolve_interface_settings(d, modal_options(), m);
  const reduction::ModalLoad load = load_vector();
  const std::vector<reduction::ModalOutputSpec> outputs = output_vectors();
  const std::string key = interface_model_key(current_keys().modes, settings.options, load, outputs);
  // Full fields (eq. T-33) need Φ and the deflated solves, stored beside the model.
  const bool want_recovery = d.nonlinear_modes && d.nonlinear_modes->fields > 0 && d.nonlinear_modes->volume_fields;
  const std::string memo = fmt::format("{} patch {:.17g} recovery {}", key, d.contact_patch, want_recovery);
  if (interface_ && interface_memo_ == memo) {
    ++counters_.condensation_reused;
    interface_->settings = settings;  // the damping may have changed; it is not in the key
    refresh_dynamics(*interface_);
    return *interface_;
  }
  interface_.reset();  // release the old model before building a new one
  settings.options.keep_field_recovery = want_recovery;
  InterfaceStage stage;
  stage.info.key = key;
  stage.info.location = store_->location(stage_names::interface_model, key);
  std::vector<contact::ContactPoint> laws;
  for (const auto& ci : model_.interfaces) laws.push_back(ci.law);
  const auto start = Clock::now();
  std::optional<hb::InterfaceModel> stored = store_->load_interface_model(key, laws);
  reduction::FieldRecovery recovery;
  if (stored && want_recovery) {
    if (std::optional<reduction::FieldRecovery> fr = store_->load_field_recovery(key))
      recovery = std::move(*fr);
    else
      stored.reset();  // the model without its recovery: condense again
  }
  hb::InterfaceModel condensed;
  if (stored) {
    condensed = std::move(*stored);
    stage.info.from_store = true;
    stage.info.store_seconds = seconds_since(start);
    ++counters_.condensation_read;
    stage.brief = fmt::format("{} kept modes ({} rigid), {} contact points", condensed.num_modes(),
                              condensed.rigid_modes, condensed.num_points());
  } else {
    reduction::ModalInterfaceResult r =
        reduction::build_modal_interface(structure(), preload(), load, outputs, settings.options);
    ++counters_.condensed;
    stage.brief = r.brief();
    stage.truncated_by_max_modes = r.truncated_by_max_modes;
    stage.modes_seconds = r.modes_seconds;
    stage.factor_seconds = r.factor_seconds;
    stage.residual_seconds = r.residual_seconds;
    stage.seconds = r.seconds;
    condensed = std::move(r.model);
    recovery = std::move(r.recovery);
    const auto store_start = Clock::now();
    store_->store_interface_model(key, condensed);
    if (want_recovery) store_->store_field_recovery(key, recovery);
    stage.info.store_seconds = seconds_since(store_start);
  }
  // Contact patches (eq. T-31): by default only the coincident node pairs, which is exact.
  {
    reduction::ContactPatchResult patches = reduction::merge_contact_patches(condensed, structure(), {.size = d.contact_patch});
    condensed = hb::InterfaceModel{};
    stage.patch_of_point = patches.patch_of_point;
    stage.fine_points = patches.fine_points;
    stage.merge_seconds = patches.seconds;
    if (!recovery.empty()) recovery = recovery.merged(patches.patch_of_point, patches.point_weights, patches.patches);
    stage.model = std::move(patches.model);
  }
  stage.recovery = std::move(recovery);
  stage.settings = std::move(settings);
  refresh_dynamics(stage);
  interface_ = std::move(stage);
  interface_memo_ = memo;
  return *interface_;
}

// ---- curves ----------------------------------------------------------------------------------------

BackboneCurve FePipeline::backbone(int mode, const BackboneCallback& on_point) {
  if (!analysis_.dynamics || !analysis_.dynamics->nonlinear_modes)
    throw std::invalid_argument("the analysis has no nonlinear_modes settings");
  return backbone(mode, *analysis_.dynamics->nonlinear_modes, on_point);
}

BackboneCurve FePipeline::backbone(int mode, const FeNonlinearModesSpec& nm, const BackboneCallback& on_point) {
  const hb::InterfaceModel& im = interface_stage().model;
  continuation::InterfaceBackboneOptions o;
  o.mode.mode = mode;
  o.mode.balance = nm.balance;
  o.log10_amplitude_start = nm.log10_amplitude_start;
  o.log10_amplitude_end = nm.log10_amplitude_end;
  o.continuation = nm.continuation;
  o.error_estimate = nm.error_estimate;
  o.accuracy = nm.accuracy;
  BackboneCurve out;
  out.mode = mode;
  out.harmonics = nm.balance.harmonics;
  out.time_samples = nm.balance.time_samples;
  // Output amplitudes: one more evaluation per accepted point on a balance of its own, one per
  // level (H, N_t) the curve uses (one unless o.accuracy is active).
  std::map<std::pair<int, int>, hb::InterfaceBalance> output_balances;
  const auto output_balance_at = [&](int harmonics, int time_samples) -> const hb::InterfaceBalance& {
    const std::pair<int, int> key{harmonics, time_samples};
    auto it = output_balances.find(key);
    if (it == output_balances.end()) {
      hb::InterfaceBalanceOptions bo = nm.balance;
      bo.harmonics = harmonics;
      bo.time_samples = time_samples;
      it = output_balances.emplace(key, hb::InterfaceBalance(im, bo)).first;
    }
    return it->second;
  };
  double linear_hz = 0.0;
  std::string failure;
  const auto accept = [&](const continuation::InterfaceBackbonePoint& p) {
    const hb::InterfaceModeState& s = p.state;
    double out_amp = 0.0;
    if (!im.outputs.empty()) {
      const hb::InterfaceBalance* output_balance = &output_balance_at(p.harmonics, p.time_samples);
      const Eigen::Index U = output_balance->unknowns();
      const Eigen::VectorXd y = s.amplitude * p.unknowns.head(U);
      const double xi = p.unknowns[U + 1];
      hb::InterfaceBalanceEvaluation e;
      output_balance->evaluate(y, s.omega, xi, {}, false, e);
      const Eigen::VectorXd u = output_balance->output_coefficients(0, y, s.omega, xi, {}, e.contact_force);
      const int a1 = output_balance->basis().cosine_index(1);
      out_amp = std::hypot(u[a1], u[a1 + 1]);
    }
    if (!all_finite({s.amplitude, s.omega, s.damping_ratio, s.dissipation, out_amp})) {
      failure = fmt::format("a point is not finite (q = {:g}, omega = {:g}, zeta = {:g}); the curve ends before it",
                            s.amplitude, s.omega, s.damping_ratio);
      return false;
    }
    BackbonePoint b;
    b.mode = mode;
    b.amplitude = s.amplitude;
    b.output_amplitude = out_amp;
    b.omega = s.omega;
    b.frequency_hz = s.omega / kTwoPi;
    b.damping_ratio = s.damping_ratio;
    b.dissipation = s.dissipation;
    b.damping_ratio_energy = s.damping_ratio_energy;
    b.slipping_points = s.slipping_points;
    b.states = s.states;
    b.open_points = s.open_points;
    b.viscous_dissipation = s.viscous_dissipation;
    b.contact_points = im.num_points();
    b.newton_iterations = p.iterations;
    b.step = p.step;
    b.error = p.error;
    b.harmonics = p.harmonics;
    b.time_samples = p.time_samples;
    out.points.push_back(b);
    if (linear_hz == 0.0) linear_hz = b.frequency_hz;
    // ζ (what the balance needs) against ζ_E (the sampled loops' W_D + viscous work): apart from
    // the residual modes' viscous share they differ by the harmonic truncation and the aliasing
    // of the contact forces. Differences below 1e-6 in ζ (the periodic-state tolerance at
    // vanishing amplitude) do not count.
    if (s.damping_ratio_energy > 0.0 && std::abs(s.damping_ratio - s.damping_ratio_energy) > 1e-6)
      out.energy_gap = std::max(out.energy_gap, std::abs(s.damping_ratio / s.damping_ratio_energy - 1.0));
    if (on_point && !on_point(b)) {
      out.stopped_by_callback = true;
      return false;
    }
    if (nm.frequency_drop > 0.0 && std::abs(b.frequency_hz / linear_hz - 1.0) >= nm.frequency_drop) {
      out.reached_frequency_drop = true;
      return false;
    }
    return true;
  };
  out.curve = continuation::trace_interface_backbone(im, o, accept);
  ++counters_.curves;
  if (!failure.empty()) {
    out.stop_message = failure;
  } else if (out.reached_frequency_drop) {
    out.stop_message = fmt::format("frequency shift of {} reached", nm.frequency_drop);
  } else if (out.stopped_by_callback) {
    out.stop_message = "stopped by the caller";
  } else {
    out.stop_message = out.curve.message;
  }
  if (out.energy_gap > energy_gap_warning)
    out.energy_warning =
        nm.accuracy.active()
            ? fmt::format("zeta differs from the loops' energy ratio by up to {:.0f} %: the contact forces are not "
                          "resolved by the harmonics and time samples the accuracy request chose (tighten "
                          "accuracy, or raise max_harmonics = {})",
                          100.0 * out.energy_gap, nm.accuracy.max_harmonics)
            : fmt::format("zeta differs from the loops' energy ratio by up to {:.0f} %: the contact forces are not "
                          "resolved by harmonics = {} and time_samples = {} (raise them)",
                          100.0 * out.energy_gap, nm.balance.harmonics, nm.balance.time_samples);
  return out;
}

Status BackboneCurve::status() const {
  // The pipeline's accept stops the continuation for three reasons of its own, which the
  // continuation records alike as stopped_by_user; the flags and the failure message tell them
  // apart. A point on the end is complete whatever the callback said (as in ok()).
  if (curve.completed() || reached_frequency_drop) return {Termination::reached_end, stop_message};
  if (stopped_by_callback) return {Termination::stopped_by_user, stop_message};
  if (curve.reason == continuation::StopReason::stopped_by_user)  // a non-finite point
    return {Termination::failed, stop_message};
  return {continuation::termination(curve.reason), stop_message};
}

Status FrfCurve::status() const {
  if (curve.completed()) return {Termination::reached_end, curve.message};
  if (stopped_by_callback) return {Termination::stopped_by_user, curve.message};
  if (curve.reason == continuation::StopReason::stopped_by_user)  // a non-finite point
    return {Termination::failed, curve.message};
  return {continuation::termination(curve.reason), curve.message};
}

FrfCurve FePipeline::frf(std::size_t level, const FrfCallback& on_point) {
  if (!analysis_.dynamics || !analysis_.dynamics->frf) throw std::invalid_argument("the analysis has no frf settings");
  return frf(level, *analysis_.dynamics->frf, on_point);
}

FrfCurve FePipeline::frf(std::size_t level, const FeFrfSpec& fs, const FrfCallback& on_point) {
  if (level >= fs.forces.size())
    throw std::invalid_argument(fmt::format("frf level {}: the analysis has {} force levels", level, fs.forces.size()));
  const hb::InterfaceModel& im = interface_stage().model;
  continuation::InterfaceFrfOptions o;
  o.omega_start = fs.omega_start;
  o.omega_end = fs.omega_end;
  o.load_amplitude = fs.forces[level];
  o.output = fs.output;
  o.balance = fs.balance;
  o.continuation = fs.continuation;
  o.error_estimate = fs.error_estimate;
  o.accuracy = fs.accuracy;
  o.stability = fs.stability;
  o.stability_method = fs.stability_method;
  FrfCurve out;
  out.level = level;
  out.force = fs.forces[level];
  const auto& outputs = analysis_.dynamics->outputs;
  if (fs.output >= 0 && static_cast<std::size_t>(fs.output) < outputs.size())
    out.output = outputs[static_cast<std::size_t>(fs.output)].name;
  std::string failure;
  const auto accept = [&](const continuation::InterfaceFrfPoint& p) {
    if (!all_finite({p.omega, p.amplitude_h1, p.amplitude_max, p.dissipation})) {
      failure = fmt::format("a point is not finite (omega = {:g}, |u| = {:g}); the curve ends before it", p.omega,
                            p.amplitude_h1);
      return false;
    }
    FrfPoint f;
    f.level = level;
    f.force = out.force;
    f.omega = p.omega;
    f.frequency_hz = p.omega / kTwoPi;
    f.amplitude_h1 = p.amplitude_h1;
    f.amplitude_max = p.amplitude_max;
    f.dissipation = p.dissipation;
    f.slipping_points = p.slipping_points;
    f.states = p.states;
    f.open_points = p.open_points;
    f.newton_iterations = p.iterations;
    f.error = p.error;
    f.harmonics = p.harmonics;
    f.time_samples = p.time_samples;
    f.stability_known = p.stability_known;
    f.stable = p.stable;
    f.max_multiplier = p.max_multiplier;
    f.bifurcation = p.bifurcation;
    out.points.push_back(f);
    if (f.amplitude_h1 > out.peak_amplitude) out.peak_amplitude = f.amplitude_h1, out.peak_frequency_hz = f.frequency_hz;
    if (on_point && !on_point(f)) {
      out.stopped_by_callback = true;
      return false;
    }
    return true;
  };
  out.curve = continuation::trace_interface_frf(im, o, accept);
  if (const auto& peak = out.curve.peak; peak && peak->refined && failure.empty()) {
    out.peak_amplitude = peak->amplitude_h1;  // located between the points (frf_extrema.hpp)
    out.peak_frequency_hz = peak->omega / kTwoPi;
    out.peak_refined = true;
  }
  ++counters_.curves;
  if (!failure.empty()) out.curve.message = failure;
  return out;
}

}  // namespace jointhb::pipeline
