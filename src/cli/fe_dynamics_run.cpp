// The dynamic stage of an FE case: condensation, damping curves, FRFs (fe_dynamics_run.hpp).
#include "fe_dynamics_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include "cli_support.hpp"
#include "interface_fields.hpp"
#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/io/csv_writer.hpp"
#include "jointhb/reduction/contact_patches.hpp"
#include "jointhb/reduction/modal_interface.hpp"
#include "run_support.hpp"

namespace jointhb::cli {
namespace {

using nlohmann::ordered_json;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kRigidHz = 1.0;  // |f| below this: a rigid-body mode (build_modal_interface's default)

const std::vector<std::string> kBackboneColumns = {
    "mode",          "amplitude",       "output_amplitude", "omega",   "frequency_hz",     "damping_ratio",
    "W_D",           "damping_ratio_energy", "slipping_points", "open_points", "newton_iterations"};
const std::vector<std::string> kFrfColumns = {
    "level",        "force_amplitude", "omega",           "frequency_hz", "amplitude_h1", "amplitude_max",
    "dissipation",  "slipping_points", "open_points",     "newton_iterations"};

ordered_json timings_json(const continuation::InterfaceTimings& t) {
  return {{"aft", t.aft},
          {"assembly", t.assembly},
          {"linear_solve", t.linear_solve},
          {"products", t.products},
          {"preconditioner_build", t.preconditioner},
          {"preconditioner_apply", t.preconditioner_apply},
          {"total", t.total},
          {"evaluations", t.evaluations},
          {"jacobians", t.jacobians},
          {"product_calls", t.product_calls},
          {"preconditioner_builds", t.factorisations},
          {"gmres_iterations", t.krylov_iterations}};
}

}  // namespace

// Frequencies [Hz] of the elastic modes among `modes` (rigid-body modes skipped).
std::vector<double> elastic_frequencies(const modal::ModalResult& modes) {
  std::vector<double> f;
  for (Eigen::Index j = 0; j < modes.frequencies_hz.size(); ++j)
    if (std::abs(modes.frequencies_hz[j]) >= kRigidHz) f.push_back(modes.frequencies_hz[j]);
  return f;
}

// Cutoff and Rayleigh coefficients from the case and the modes of K_t.
InterfaceSettings resolve_interface_settings(const io::FeCase& c, const modal::ModalResult& modes) {
  const io::FeDynamicsSpec& d = *c.dynamics;
  const std::vector<double> f = elastic_frequencies(modes);
  InterfaceSettings s;
  s.options.modal = c.modes.value_or(modal::ModalOptions{});
  s.options.rigid_tolerance_hz = kRigidHz;
  int highest_mode = 0;
  if (d.nonlinear_modes) highest_mode = *std::max_element(d.nonlinear_modes->modes.begin(), d.nonlinear_modes->modes.end());
  if (highest_mode > static_cast<int>(f.size()))
    throw std::runtime_error(fmt::format(
        "analysis.nonlinear_modes: mode {} asked for, but the modes stage found {} elastic modes "
        "(raise analysis.modes.count)", highest_mode, f.size()));
  if (f.empty()) throw std::runtime_error("the modes stage found no elastic mode (raise analysis.modes.count)");
  s.followed_hz = highest_mode > 0 ? f[static_cast<std::size_t>(highest_mode - 1)] : f.front();
  if (d.frf) s.followed_hz = std::max(s.followed_hz, std::max(d.frf->omega_start, d.frf->omega_end) / kTwoPi);
  if (d.cutoff_hz > 0.0) {
    s.options.cutoff_hz = d.cutoff_hz;
    s.cutoff_source = "analysis.reduction.cutoff_hz";
  } else {
    s.options.cutoff_hz = d.cutoff_factor * s.followed_hz;
    s.cutoff_source = fmt::format("{} x {:.6g} Hz (the highest frequency of interest)", d.cutoff_factor, s.followed_hz);
  }
  if (d.damping_ratio > 0.0) {
    const double fd = d.damping_frequency_hz > 0.0
                          ? d.damping_frequency_hz
                          : f[static_cast<std::size_t>(std::max(1, d.nonlinear_modes ? d.nonlinear_modes->modes.front() : 1) - 1)];
    s.options.rayleigh_stiffness = 2.0 * d.damping_ratio / (kTwoPi * fd);
    s.damping_source = fmt::format("ratio {} at {:.6g} Hz, stiffness-proportional", d.damping_ratio, fd);
  } else {
    s.options.rayleigh_mass = d.rayleigh_mass;
    s.options.rayleigh_stiffness = d.rayleigh_stiffness;
    s.damping_source = d.rayleigh_mass > 0.0 || d.rayleigh_stiffness > 0.0 ? "rayleigh" : "none";
  }
  return s;
}

// Stage-cache key of the condensed model (io/stage_cache.hpp): the modes key + every option but
// the damping, and the load and output vectors.
std::string interface_model_key(const io::FeCase& c, const reduction::ModalInterfaceOptions& o,
                          const reduction::ModalLoad& load, const std::vector<reduction::ModalOutputSpec>& outputs) {
  io::Fingerprint k = io::Fingerprint::chain(c.fingerprints.modes);
  // The Rayleigh coefficients are not part of it: the condensation only copies them into the
  // model (T-23 uses them at evaluation time), so they are set after a cache hit.
  k.add("interface model").add(o.cutoff_hz).add(o.initial_count).add(o.max_modes).add(o.rigid_tolerance_hz);
  k.add(o.modal.shift).add(o.modal.tolerance).add(o.modal.ncv);
  k.add(load.name).add(load.force);
  for (const auto& out : outputs) k.add(out.name).add(out.functional);
  return k.hex();
}

int run_fe_dynamics(const io::FeCase& c, const preload::PreloadModel& model, const preload::PreloadResult& preload,
                    const modal::ModalResult& modes, const std::filesystem::path& dir, io::StageCache& cache,
                    ordered_json& summary) {
  const io::FeDynamicsSpec& d = *c.dynamics;
  const bool tty = stderr_is_terminal();
  const int n = c.mesh.num_dofs();
  int code = 0;

  // ---- condensation ------------------------------------------------------------------------
  InterfaceSettings settings = resolve_interface_settings(c, modes);
  const reduction::ModalLoad load{d.excitation.name.empty() ? "none" : d.excitation.name,
                                  d.excitation.name.empty() ? Eigen::VectorXd::Zero(n) : d.excitation.functional(n)};
  std::vector<reduction::ModalOutputSpec> outputs;
  for (const io::FeNodeDirection& o : d.outputs) outputs.push_back({o.name, o.functional(n)});
  const std::string key = interface_model_key(c, settings.options, load, outputs);
  std::vector<contact::ContactPoint> laws;
  for (const auto& ci : model.interfaces) laws.push_back(ci.law);
  // Full fields (eq. T-33) need Φ and the deflated solves, cached beside the model.
  const bool want_recovery = d.nonlinear_modes && d.nonlinear_modes->fields > 0 && d.nonlinear_modes->volume_fields;
  settings.options.keep_field_recovery = want_recovery;  // not part of the key: the model is the same
  const auto cache_start = Clock::now();
  std::optional<hb::InterfaceModel> cached = cache.load_interface_model(key, laws);
  reduction::FieldRecovery recovery;
  if (cached && want_recovery) {
    if (std::optional<reduction::FieldRecovery> fr = cache.load_field_recovery(key)) {
      recovery = std::move(*fr);
      recovery.rayleigh_stiffness = settings.options.rayleigh_stiffness;
    } else {
      cached.reset();  // the model without its recovery: condense again
    }
  }
  ordered_json ij;
  hb::InterfaceModel im;
  if (cached) {
    im = std::move(*cached);
    im.rayleigh_mass = settings.options.rayleigh_mass;
    im.rayleigh_stiffness = settings.options.rayleigh_stiffness;
    ij["cache"] = "hit";
    ij["cache_seconds"] = seconds_since(cache_start);
    std::fprintf(stderr, "interface model: from cache (%s): %d kept modes (%d rigid), %d contact points\n",
                 cache.file("interface", key).string().c_str(), im.num_modes(), im.rigid_modes, im.num_points());
  } else {
    reduction::ModalInterfaceResult r = reduction::build_modal_interface(model, preload, load, outputs, settings.options);
    std::fprintf(stderr, "interface model: %s\n", r.brief().c_str());
    im = std::move(r.model);
    recovery = std::move(r.recovery);
    ij["cache"] = "miss";
    ij["truncated_by_max_modes"] = r.truncated_by_max_modes;
    ij["seconds"] = {{"modes", r.modes_seconds}, {"factor", r.factor_seconds}, {"residual", r.residual_seconds},
                     {"total", r.seconds}};
    const auto store_start = Clock::now();
    cache.store_interface_model(key, im);
    if (want_recovery) cache.store_field_recovery(key, recovery);
    ij["cache_seconds"] = seconds_since(store_start);
  }
  // Contact patches (eq. T-31): by default only the coincident node pairs, which is exact.
  std::vector<int> patch_of_point;
  {
    const reduction::ContactPatchResult patches = reduction::merge_contact_patches(im, model, {.size = d.contact_patch});
    patch_of_point = patches.patch_of_point;
    if (!recovery.empty()) recovery = recovery.merged(patches.patch_of_point, patches.point_weights, patches.patches);
    ij["contact_patch"] = {{"size", d.contact_patch},
                           {"exact", d.contact_patch == 0.0},
                           {"points_before", patches.fine_points},
                           {"points_after", patches.patches},
                           {"seconds", patches.seconds}};
    std::fprintf(stderr, "contact points: %d merged into %d %s (%.2f s)\n", patches.fine_points, patches.patches,
                 d.contact_patch == 0.0 ? "node pairs (coincident points, exact)"
                                        : fmt::format("patches of {} m", d.contact_patch).c_str(),
                 patches.seconds);
    im = patches.model;
  }
  ij["key"] = key;
  ij["cutoff_hz"] = settings.options.cutoff_hz;
  ij["cutoff_source"] = settings.cutoff_source;
  ij["rayleigh"] = {{"alpha", im.rayleigh_mass}, {"beta", im.rayleigh_stiffness}, {"source", settings.damping_source}};
  ij["kept_modes"] = im.num_modes();
  ij["rigid_modes"] = im.rigid_modes;
  ij["contact_points"] = im.num_points();
  ij["excitation"] = {{"node", d.excitation.node}, {"distance", d.excitation.distance},
                      {"direction", {d.excitation.direction.x(), d.excitation.direction.y(), d.excitation.direction.z()}}};
  ij["outputs"] = ordered_json::array();
  for (const auto& o : d.outputs) ij["outputs"].push_back({{"name", o.name}, {"node", o.node}, {"distance", o.distance}});
  {
    io::CsvWriter csv(dir / "interface_model.csv", {"mode", "frequency_hz", "rigid"});
    for (int j = 0; j < im.num_modes(); ++j)
      csv.write_row({static_cast<double>(j + 1), std::sqrt(im.omega2[j]) / kTwoPi, j < im.rigid_modes ? 1.0 : 0.0});
  }
  summary["interface_model"] = ij;
  write_summary(dir / "summary.json", summary);

  // ---- damping curves ------------------------------------------------------------------------
  if (d.nonlinear_modes) {
    const io::FeNonlinearModesSpec& nm = *d.nonlinear_modes;
    io::CsvWriter csv(dir / "backbone.csv", kBackboneColumns);
    summary["outputs"]["backbone"] = "backbone.csv";
    summary["backbones"] = ordered_json::array();
    for (int mode : nm.modes) {
      continuation::InterfaceBackboneOptions o;
      o.mode.mode = mode;
      o.mode.balance = nm.balance;
      o.log10_amplitude_start = nm.log10_amplitude_start;
      o.log10_amplitude_end = nm.log10_amplitude_end;
      o.continuation = nm.continuation;
      // Output amplitudes: one more evaluation per accepted point on a balance of its own.
      const std::optional<hb::InterfaceBalance> output_balance =
          im.outputs.empty() ? std::nullopt : std::optional<hb::InterfaceBalance>(hb::InterfaceBalance(im, nm.balance));
      double linear_hz = 0.0, energy_gap = 0.0;
      const auto on_point = [&](const continuation::InterfaceBackbonePoint& p) {
        const hb::InterfaceModeState& s = p.state;
        double out_amp = 0.0;
        if (output_balance) {
          const Eigen::Index U = output_balance->unknowns();
          const Eigen::VectorXd y = s.amplitude * p.unknowns.head(U);
          const double xi = p.unknowns[U + 1];
          hb::InterfaceBalanceEvaluation e;
          output_balance->evaluate(y, s.omega, xi, {}, false, e);
          const Eigen::VectorXd u = output_balance->output_coefficients(0, y, s.omega, xi, {}, e.contact_force);
          const int a1 = output_balance->basis().cosine_index(1);
          out_amp = std::hypot(u[a1], u[a1 + 1]);
        }
        const double f = s.omega / kTwoPi;
        for (double v : {s.amplitude, s.omega, s.damping_ratio, s.dissipation, out_amp})
          require_finite_result("backbone point", v);
        csv.write_row({static_cast<double>(mode), s.amplitude, out_amp, s.omega, f, s.damping_ratio, s.dissipation,
                       s.damping_ratio_energy, static_cast<double>(s.slipping_points),
                       static_cast<double>(s.open_points), static_cast<double>(p.iterations)});
        if (linear_hz == 0.0) linear_hz = f;
        // ζ (what the balance needs) against ζ_E (the sampled loops' W_D + viscous work): apart
        // from the residual modes' viscous share they differ by the harmonic truncation and the
        // aliasing of the contact forces. Differences below 1e-6 in ζ (the periodic-state
        // tolerance at vanishing amplitude) do not count.
        if (s.damping_ratio_energy > 0.0 && std::abs(s.damping_ratio - s.damping_ratio_energy) > 1e-6)
          energy_gap = std::max(energy_gap, std::abs(s.damping_ratio / s.damping_ratio_energy - 1.0));
        if (tty)
          std::fprintf(stderr, "\rmode %d: q = %.3e  f = %.6g Hz  zeta = %.4g  slipping %d/%d   ", mode, s.amplitude, f,
                       s.damping_ratio, s.slipping_points, im.num_points());
        return !(nm.frequency_drop > 0.0 && std::abs(f / linear_hz - 1.0) >= nm.frequency_drop);
      };
      const continuation::InterfaceBackbone b = continuation::trace_interface_backbone(im, o, on_point);
      if (tty) std::fprintf(stderr, "\n");
      ordered_json fields_json;
      if (nm.fields > 0 && !b.points.empty()) {
        std::vector<double> amplitudes;
        for (const auto& p : b.points) amplitudes.push_back(p.state.amplitude);
        const hb::InterfaceBalance balance(im, nm.balance);
        std::vector<FieldSnapshot> snapshots;
        for (std::size_t i : snapshot_indices(amplitudes, nm.fields)) {
          const auto& p = b.points[i];
          const Eigen::Index U = balance.unknowns();
          snapshots.push_back({p.state.amplitude, p.state.omega, p.unknowns[U + 1], p.state.amplitude * p.unknowns.head(U)});
        }
        const FieldFiles files = write_damping_fields(dir, mode, c.mesh, model, patch_of_point, balance, recovery, snapshots);
        std::fprintf(stderr, "fields of mode %d: %zu snapshots -> %s (%.2f s)\n", mode, snapshots.size(),
                     (dir / fmt::format("mode{}_*.pvd", mode)).string().c_str(), files.seconds);
        fields_json = {{"snapshots", snapshots.size()}, {"volume", !recovery.empty()}, {"seconds", files.seconds}};
        fields_json["files"] = ordered_json::array();
        for (const auto& f : files.files)
          if (f.extension() != ".vtu") fields_json["files"].push_back(f.string());
      }
      const bool by_drop = b.reason == continuation::StopReason::stopped_by_user;
      const std::string stop = by_drop ? fmt::format("frequency shift of {} reached", nm.frequency_drop) : b.message;
      std::string energy_warning;
      if (energy_gap > 0.1) {
        energy_warning = fmt::format(
            "zeta differs from the loops' energy ratio by up to {:.0f} %: the contact forces are not resolved by "
            "harmonics = {} and time_samples = {} (raise them)", 100.0 * energy_gap, nm.balance.harmonics,
            nm.balance.time_samples);
        std::fprintf(stderr, "warning: damping curve of mode %d: %s\n", mode, energy_warning.c_str());
      }
      const bool ok = b.completed() || by_drop;
      if (!ok) code = 1;
      const auto& last = b.points.empty() ? hb::InterfaceModeState{} : b.points.back().state;
      std::fprintf(stderr, "damping curve of mode %d: %zu points, f %.6g -> %.6g Hz, zeta %.4g -> %.4g (%s; %.2f s)\n",
                   mode, b.points.size(), b.linear_omega / kTwoPi, last.omega / kTwoPi, b.linear_damping_ratio,
                   last.damping_ratio, stop.c_str(), b.timings.total);
      std::fprintf(stderr, "  time of the curve: %s\n", b.timings.breakdown().c_str());
      summary["backbones"].push_back({{"mode", mode},
                                      {"status", ok ? "ok" : "stopped"},
                                      {"message", stop},
                                      {"energy_gap", energy_gap},
                                      {"energy_warning", energy_warning},
                                      {"points", b.points.size()},
                                      {"linear_frequency_hz", b.linear_omega / kTwoPi},
                                      {"linear_damping_ratio", b.linear_damping_ratio},
                                      {"unknowns", b.unknowns},
                                      {"harmonics", nm.balance.harmonics},
                                      {"time_samples", nm.balance.time_samples},
                                      {"tangential_stiffness", nm.balance.preloaded_tangential_stiffness ? "preloaded" : "instantaneous"},
                                      {"newton_iterations", b.newton_iterations},
                                      {"rejected_steps", b.rejected_steps},
                                      {"seconds", timings_json(b.timings)}});
      if (!fields_json.is_null()) summary["backbones"].back()["fields"] = fields_json;
      write_summary(dir / "summary.json", summary);
    }
  }

  // ---- frequency responses -------------------------------------------------------------------
  if (d.frf) {
    const io::FeFrfSpec& fs = *d.frf;
    io::CsvWriter csv(dir / "frf.csv", kFrfColumns);
    summary["outputs"]["frf"] = "frf.csv";
    summary["frfs"] = ordered_json::array();
    for (std::size_t level = 0; level < fs.forces.size(); ++level) {
      continuation::InterfaceFrfOptions o;
      o.omega_start = fs.omega_start;
      o.omega_end = fs.omega_end;
      o.load_amplitude = fs.forces[level];
      o.output = fs.output;
      o.balance = fs.balance;
      o.continuation = fs.continuation;
      const auto on_point = [&](const continuation::InterfaceFrfPoint& p) {
        for (double v : {p.omega, p.amplitude_h1, p.amplitude_max, p.dissipation}) require_finite_result("frf point", v);
        csv.write_row({static_cast<double>(level), fs.forces[level], p.omega, p.omega / kTwoPi, p.amplitude_h1,
                       p.amplitude_max, p.dissipation, static_cast<double>(p.slipping_points),
                       static_cast<double>(p.open_points), static_cast<double>(p.iterations)});
        if (tty)
          std::fprintf(stderr, "\rfrf F = %g N: f = %.6g Hz  |u| = %.4e m  slipping %d/%d   ", fs.forces[level],
                       p.omega / kTwoPi, p.amplitude_h1, p.slipping_points, im.num_points());
        return true;
      };
      const continuation::InterfaceFrf r = continuation::trace_interface_frf(im, o, on_point);
      if (tty) std::fprintf(stderr, "\n");
      if (!r.completed()) code = 1;
      double peak = 0.0, peak_hz = 0.0;
      for (const auto& p : r.points)
        if (p.amplitude_h1 > peak) peak = p.amplitude_h1, peak_hz = p.omega / kTwoPi;
      std::fprintf(stderr, "frf F = %g N: %zu points, peak %.4e m at %.6g Hz (%s; %.2f s)\n", fs.forces[level],
                   r.points.size(), peak, peak_hz, r.message.c_str(), r.timings.total);
      std::fprintf(stderr, "  time of the curve: %s\n", r.timings.breakdown().c_str());
      summary["frfs"].push_back({{"level", level},
                                 {"force", fs.forces[level]},
                                 {"output", d.outputs[static_cast<std::size_t>(fs.output)].name},
                                 {"status", r.completed() ? "ok" : "stopped"},
                                 {"message", r.message},
                                 {"points", r.points.size()},
                                 {"peak_amplitude", peak},
                                 {"peak_frequency_hz", peak_hz},
                                 {"unknowns", r.unknowns},
                                 {"harmonics", fs.balance.harmonics},
                                 {"newton_iterations", r.newton_iterations},
                                 {"rejected_steps", r.rejected_steps},
                                 {"seconds", timings_json(r.timings)}});
      write_summary(dir / "summary.json", summary);
    }
  }
  return code;
}

}  // namespace jointhb::cli
