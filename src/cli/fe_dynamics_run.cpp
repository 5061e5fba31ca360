// The dynamic stage of an FE case: condensation, damping curves, FRFs (fe_dynamics_run.hpp).
#include "fe_dynamics_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include "backbone_columns.hpp"
#include "cli_support.hpp"
#include "interface_fields.hpp"
#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/hb/fourier.hpp"
#include "jointhb/io/fe_dynamics_case.hpp"
#include "jointhb/io/csv_writer.hpp"
#include "run_support.hpp"
#include "status_json.hpp"

namespace jointhb::cli {
namespace {

using nlohmann::ordered_json;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

const std::vector<std::string> kFeFrfColumns = {
    "level",        "force_amplitude", "omega",           "frequency_hz", "amplitude_h1", "amplitude_max",
    "dissipation",  "slipping_points", "open_points",     "newton_iterations",
    "stuck_points", "microslip_points", "gross_slip_points", "gapping_points",
    // estimated relative errors of amplitude_h1 and amplitude_max (as the discrete frf.csv)
    "amplitude_error_truncation", "amplitude_error_aliasing", "amplitude_max_error_truncation",
    "amplitude_max_error_aliasing",
    "harmonics", "time_samples"};  // the point's level (per point with `accuracy`)

// Contact points per state at every point of a damping curve (hb/contact_state.hpp):
// {"amplitude": [q...], "stuck": [n...], "microslip": [...], "gross_slip": [...], "gapping": [...], "open": [...]}.
ordered_json contact_states_along(const std::vector<pipeline::BackbonePoint>& points) {
  ordered_json out = {{"amplitude", ordered_json::array()}};
  for (int k = 0; k < hb::kContactStateCount; ++k)
    out[std::string(hb::contact_state_name(static_cast<hb::ContactState>(k)))] = ordered_json::array();
  for (const pipeline::BackbonePoint& p : points) {
    out["amplitude"].push_back(p.amplitude);
    for (int k = 0; k < hb::kContactStateCount; ++k) {
      const auto s = static_cast<hb::ContactState>(k);
      out[std::string(hb::contact_state_name(s))].push_back(p.states[s]);
    }
  }
  return out;
}

// Stability of an FE FRF for summary.json: computed or not, the points known and unstable, the
// bifurcations (type, point, Ω, the Ω of the point before), and one line naming them.
ordered_json fe_stability_json(const std::vector<pipeline::FrfPoint>& points, bool computed,
                               continuation::StabilityMethod method) {
  const StabilityCounts counts = stability_counts(points);
  std::string line;
  for (const pipeline::FrfPoint& p : points)
    if (p.bifurcation != hb::Bifurcation::none)
      line += fmt::format("{}{} at {:.6g} Hz", line.empty() ? "" : ", ", hb::to_string(p.bifurcation), p.frequency_hz);
  return {{"computed", computed},
          {"method", continuation::to_string(method)},
          {"points_known", counts.known},
          {"unstable_points", counts.unstable},
          {"bifurcations", bifurcations_json(points)},
          {"line", fmt::format("{} of {} points known ({}), {} unstable{}{}", counts.known, points.size(),
                               method == continuation::StabilityMethod::hill ? "Hill's method" : "monodromy",
                               counts.unstable, line.empty() ? "" : "; ", line)}};
}

ordered_json timings_json(const continuation::InterfaceTimings& t) {
  return {{"aft", t.aft},
          {"assembly", t.assembly},
          {"linear_solve", t.linear_solve},
          {"products", t.products},
          {"preconditioner_build", t.preconditioner},
          {"preconditioner_apply", t.preconditioner_apply},
          {"error_estimate", t.error_estimate},
          {"stability", t.stability},
          {"refinement", t.refinement},
          {"total", t.total},
          {"evaluations", t.evaluations},
          {"jacobians", t.jacobians},
          {"product_calls", t.product_calls},
          {"preconditioner_builds", t.factorisations},
          {"gmres_iterations", t.krylov_iterations}};
}

ordered_json interface_json(const pipeline::InterfaceStage& st, const io::FeDynamicsSpec& d) {
  const hb::InterfaceModel& im = st.model;
  ordered_json ij;
  ij["cache"] = st.info.from_store ? "hit" : "miss";
  ij["cache_seconds"] = st.info.store_seconds;
  if (!st.info.from_store) {
    ij["truncated_by_max_modes"] = st.truncated_by_max_modes;
    ij["seconds"] = {{"modes", st.modes_seconds}, {"factor", st.factor_seconds}, {"residual", st.residual_seconds},
                     {"total", st.seconds}};
  }
  ij["contact_patch"] = {{"size", d.contact_patch},
                         {"exact", d.contact_patch == 0.0},
                         {"points_before", st.fine_points},
                         {"points_after", im.num_points()},
                         {"seconds", st.merge_seconds}};
  ij["key"] = st.info.key;
  ij["cutoff_hz"] = st.settings.options.cutoff_hz;
  ij["cutoff_source"] = st.settings.cutoff_source;
  ij["rayleigh"] = {{"alpha", im.rayleigh_mass}, {"beta", im.rayleigh_stiffness}, {"source", st.settings.damping_source}};
  ij["kept_modes"] = im.num_modes();
  ij["rigid_modes"] = im.rigid_modes;
  ij["contact_points"] = im.num_points();
  ij["excitation"] = {{"node", d.excitation.node}, {"distance", d.excitation.distance},
                      {"direction", {d.excitation.direction.x(), d.excitation.direction.y(), d.excitation.direction.z()}}};
  ij["outputs"] = ordered_json::array();
  for (const auto& o : d.outputs) ij["outputs"].push_back({{"name", o.name}, {"node", o.node}, {"distance", o.distance}});
  return ij;
}

// The VTK snapshots of a damping curve (eq. T-33 for the volume).
ordered_json write_fields(pipeline::FePipeline& pipe, const pipeline::BackboneCurve& b, int count,
                          const std::filesystem::path& dir) {
  const pipeline::InterfaceStage& st = pipe.interface_stage();
  std::vector<double> amplitudes;
  for (const auto& p : b.curve.points) amplitudes.push_back(p.state.amplitude);
  // One balance for every snapshot: at the highest level (H, N_t) among them (points of a curve
  // with `accuracy` differ), the others' coefficients carried over with zero higher harmonics.
  const std::vector<std::size_t> picked = snapshot_indices(amplitudes, count);
  hb::InterfaceBalanceOptions level = pipe.analysis().dynamics->nonlinear_modes->balance;
  for (std::size_t i : picked) {
    level.harmonics = std::max(level.harmonics, b.curve.points[i].harmonics);
    level.time_samples = std::max(level.time_samples, b.curve.points[i].time_samples);
  }
  const hb::InterfaceBalance balance(st.model, level);
  const int dofs = balance.modes() + 3 * balance.points();
  std::vector<FieldSnapshot> snapshots;
  for (std::size_t i : picked) {
    const auto& p = b.curve.points[i];
    const hb::FourierBasis own(p.harmonics, p.time_samples, false);
    const Eigen::Index U = static_cast<Eigen::Index>(dofs) * own.size();
    snapshots.push_back({p.state.amplitude, p.state.omega, p.unknowns[U + 1],
                         p.state.amplitude * hb::transfer_coefficients(own, balance.basis(), p.unknowns.head(U), dofs)});
  }
  const FieldFiles files = write_damping_fields(dir, b.mode, pipe.model().mesh, pipe.structure(), st.patch_of_point,
                                                balance, st.recovery, snapshots);
  std::fprintf(stderr, "fields of mode %d: %zu snapshots -> %s (%.2f s)\n", b.mode, snapshots.size(),
               (dir / fmt::format("mode{}_*.pvd", b.mode)).string().c_str(), files.seconds);
  ordered_json fields_json = {{"snapshots", snapshots.size()}, {"volume", !st.recovery.empty()}, {"seconds", files.seconds}};
  fields_json["files"] = ordered_json::array();
  for (const auto& f : files.files)
    if (f.extension() != ".vtu") fields_json["files"].push_back(f.string());
  return fields_json;
}

}  // namespace

std::vector<NamedStatus> run_fe_dynamics(pipeline::FePipeline& pipe, const std::filesystem::path& dir,
                                         ordered_json& summary) {
  const io::FeDynamicsSpec& d = *pipe.analysis().dynamics;
  const bool tty = stderr_is_terminal();  // a line per point on a terminal, the heartbeat's in a log
  std::vector<NamedStatus> curves;

  // ---- condensation ------------------------------------------------------------------------
  progress_activity("condensation to the interface");
  const pipeline::InterfaceStage& stage = pipe.interface_stage();
  const hb::InterfaceModel& im = stage.model;
  if (stage.info.from_store)
    std::fprintf(stderr, "interface model: from cache (%s): %s\n", stage.info.location.c_str(), stage.brief.c_str());
  else
    std::fprintf(stderr, "interface model: %s\n", stage.brief.c_str());
  std::fprintf(stderr, "contact points: %d merged into %d %s (%.2f s)\n", stage.fine_points, im.num_points(),
               d.contact_patch == 0.0 ? "node pairs (coincident points, exact)"
                                      : fmt::format("patches of {} m", d.contact_patch).c_str(),
               stage.merge_seconds);
  {
    io::CsvWriter csv(dir / "interface_model.csv", {"mode", "frequency_hz", "rigid"});
    for (int j = 0; j < im.num_modes(); ++j)
      csv.write_row({static_cast<double>(j + 1), std::sqrt(im.omega2[j]) / kTwoPi, j < im.rigid_modes ? 1.0 : 0.0});
  }
  summary["interface_model"] = interface_json(stage, d);
  write_summary(dir / "summary.json", summary);
  const int points = im.num_points();

  // ---- damping curves ------------------------------------------------------------------------
  if (d.nonlinear_modes) {
    const io::FeNonlinearModesSpec& nm = *d.nonlinear_modes;
    io::CsvWriter csv(dir / "backbone.csv", kBackboneColumns);
    summary["outputs"]["backbone"] = "backbone.csv";
    summary["columns"]["backbone"] = kBackboneColumns;
    summary["backbones"] = ordered_json::array();
    for (int mode : nm.modes) {
      const auto on_point = [&](const pipeline::BackbonePoint& s) {
        const double slip_fraction =
            s.contact_points > 0 ? static_cast<double>(s.slipping_points) / s.contact_points : 0.0;
        std::vector<std::optional<double>> row = {
            static_cast<double>(mode), s.amplitude, s.output_amplitude, s.omega, s.frequency_hz,
            s.damping_ratio, s.dissipation, s.viscous_dissipation, s.damping_ratio_energy, slip_fraction,
            static_cast<double>(s.slipping_points), static_cast<double>(s.open_points)};
        for (const auto& field : contact_state_fields(s.states)) row.push_back(field);
        row.push_back(static_cast<double>(s.newton_iterations));
        row.push_back(s.step);
        const continuation::BackboneError& e = s.error;
        for (const auto& field : backbone_error_fields(e))
          row.push_back(field);
        row.push_back(static_cast<double>(s.harmonics));
        row.push_back(static_cast<double>(s.time_samples));
        csv.write_row(std::span<const std::optional<double>>(row));
        if (tty)
          std::fprintf(stderr, "\rmode %d: q = %.3e  f = %.6g Hz  zeta = %.4g  slipping %d/%d   ", mode, s.amplitude,
                       s.frequency_hz, s.damping_ratio, s.slipping_points, points);
        else
          progress_activity("damping curve of mode {}: q = {:.3e}  f = {:.6g} Hz  zeta = {:.4g}  slipping {}/{}", mode,
                            s.amplitude, s.frequency_hz, s.damping_ratio, s.slipping_points, points);
        return true;
      };
      const pipeline::BackboneCurve b = pipe.backbone(mode, on_point);
      if (tty) std::fprintf(stderr, "\n");
      const ordered_json fields_json =
          nm.fields > 0 && !b.points.empty() ? write_fields(pipe, b, nm.fields, dir) : ordered_json();
      if (!b.energy_warning.empty())
        std::fprintf(stderr, "warning: damping curve of mode %d: %s\n", mode, b.energy_warning.c_str());
      curves.push_back({fmt::format("nonlinear mode {}", mode), b.status()});
      const auto& bb = b.curve;
      const pipeline::BackbonePoint last = b.points.empty() ? pipeline::BackbonePoint{} : b.points.back();
      std::fprintf(stderr, "damping curve of mode %d: %zu points, f %.6g -> %.6g Hz, zeta %.4g -> %.4g (%s; %.2f s)\n",
                   mode, b.points.size(), bb.linear_omega / kTwoPi, last.frequency_hz, bb.linear_damping_ratio,
                   last.damping_ratio, b.stop_message.c_str(), bb.timings.total);
      std::fprintf(stderr, "  time of the curve: %s\n", bb.timings.breakdown().c_str());
      ordered_json entry = {{"mode", mode}};
      put_status(entry, b.status());
      entry.update(ordered_json{{"energy_gap", b.energy_gap},
                                      {"energy_warning", b.energy_warning},
                                      {"points", b.points.size()},
                                      {"linear_frequency_hz", bb.linear_omega / kTwoPi},
                                      {"linear_damping_ratio", bb.linear_damping_ratio},
                                      {"unknowns", bb.unknowns},
                                      {"harmonics", nm.balance.harmonics},
                                      {"time_samples", nm.balance.time_samples},
                                      {"tangential_stiffness", nm.balance.preloaded_tangential_stiffness ? "preloaded" : "instantaneous"},
                                      {"newton_iterations", bb.newton_iterations},
                                      {"rejected_steps", bb.rejected_steps},
                                      {"seconds", timings_json(bb.timings)}});
      if (!fields_json.is_null()) entry["fields"] = fields_json;
      entry["contact_states"] = contact_states_along(b.points);
      WorstErrors worst;
      for (const auto& p : b.points) worst.add(p.error);
      entry["error_estimate"] = worst.json("omega", "damping");
      entry["error_estimate"]["seconds"] = bb.timings.error_estimate;
      entry["accuracy"] = accuracy_json(nm.accuracy, b.points, bb.level_changes, bb.short_of_accuracy);
      entry["turn_points"] = turns_json(bb.turns);
      if (!bb.turns.empty()) std::fprintf(stderr, "damping curve of mode %d: %s\n", mode, turns_line(bb.turns).c_str());
      summary["backbones"].push_back(std::move(entry));
      write_summary(dir / "summary.json", summary);
    }
  }

  // ---- frequency responses -------------------------------------------------------------------
  if (d.frf) {
    const io::FeFrfSpec& fs = *d.frf;
    const bool stability = continuation::computes_interface_stability(fs.stability, points, fs.stability_method,
                                                                      fs.balance.harmonics);
    io::CsvWriter csv(dir / "frf.csv", frf_columns_with_stability(kFeFrfColumns, stability));
    summary["outputs"]["frf"] = "frf.csv";
    summary["frfs"] = ordered_json::array();
    for (std::size_t level = 0; level < fs.forces.size(); ++level) {
      const auto on_point = [&](const pipeline::FrfPoint& p) {
        std::vector<std::optional<double>> row = {
            static_cast<double>(level), p.force, p.omega, p.frequency_hz, p.amplitude_h1, p.amplitude_max,
            p.dissipation, static_cast<double>(p.slipping_points), static_cast<double>(p.open_points),
            static_cast<double>(p.newton_iterations)};
        for (const auto& field : contact_state_fields(p.states)) row.push_back(field);
        for (const auto& field : frf_error_fields(p.error)) row.push_back(field);
        row.push_back(static_cast<double>(p.harmonics));
        row.push_back(static_cast<double>(p.time_samples));
        if (stability) {
          row.push_back(p.stability_known ? (p.stable ? 1.0 : 0.0) : -1.0);
          row.push_back(p.stability_known ? p.max_multiplier : -1.0);
        }
        const std::string bifurcation(hb::to_string(p.bifurcation));
        csv.write_row(std::span<const std::optional<double>>(row), std::span<const std::string>(&bifurcation, 1));
        if (tty)
          std::fprintf(stderr, "\rfrf F = %g N: f = %.6g Hz  |u| = %.4e m  slipping %d/%d   ", p.force, p.frequency_hz,
                       p.amplitude_h1, p.slipping_points, points);
        else
          progress_activity("frf F = {} N: f = {:.6g} Hz  |u| = {:.4e} m  slipping {}/{}", p.force, p.frequency_hz,
                            p.amplitude_h1, p.slipping_points, points);
        return true;
      };
      const pipeline::FrfCurve r = pipe.frf(level, on_point);
      if (tty) std::fprintf(stderr, "\n");
      curves.push_back({fmt::format("frf level {}", level), r.status()});
      std::fprintf(stderr, "frf F = %g N: %zu points, peak %.4e m at %.6g Hz (%s; %.2f s)\n", r.force, r.points.size(),
                   r.peak_amplitude, r.peak_frequency_hz, r.curve.message.c_str(), r.curve.timings.total);
      std::fprintf(stderr, "  time of the curve: %s\n", r.curve.timings.breakdown().c_str());
      ordered_json entry = {{"level", level}, {"force", r.force}, {"output", r.output}};
      put_status(entry, r.status());
      entry.update(ordered_json{{"points", r.points.size()},
                                 {"peak_amplitude", r.peak_amplitude},
                                 {"peak_frequency_hz", r.peak_frequency_hz},
                                 {"unknowns", r.curve.unknowns},
                                 {"harmonics", fs.balance.harmonics},
                                 {"newton_iterations", r.curve.newton_iterations},
                                 {"rejected_steps", r.curve.rejected_steps},
                                 {"seconds", timings_json(r.curve.timings)}});
      WorstErrors worst;
      for (const auto& p : r.points) worst.add(p.error);
      entry["error_estimate"] = worst.json("amplitude_h1", "amplitude_max");
      entry["error_estimate"]["seconds"] = r.curve.timings.error_estimate;
      entry["accuracy"] = accuracy_json(fs.accuracy, r.points, r.curve.level_changes, r.curve.short_of_accuracy);
      if (!r.points.empty()) {
        const auto highest = std::max_element(r.points.begin(), r.points.end(), [](const auto& a, const auto& b) {
          return a.amplitude_h1 < b.amplitude_h1;
        });
        entry["peak"] = peak_json(r.curve.peak, *highest);
      }
      entry["fold_points"] = fold_points_json(r.curve.folds);
      entry["stability"] = fe_stability_json(r.points, stability, fs.stability_method);
      if (stability) std::fprintf(stderr, "  stability: %s\n", entry["stability"]["line"].get<std::string>().c_str());
      summary["frfs"].push_back(std::move(entry));
      write_summary(dir / "summary.json", summary);
    }
  }
  return curves;
}

}  // namespace jointhb::cli
