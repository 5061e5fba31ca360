#include "frf_run.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <optional>
#include <span>
#include <algorithm>
#include <stdexcept>

#include "backbone_columns.hpp"
#include "cli_support.hpp"
#include "jointhb/continuation/backbone.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/io/csv_writer.hpp"
#include "jointhb/io/input_error.hpp"
#include "jointhb/pipeline/discrete_pipeline.hpp"
#include "status_json.hpp"

namespace jointhb::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// The numeric columns of frf.csv (the four error columns empty where the estimate is not computed:
// error_estimate: false or a failed estimate); with stability, "stable" (1, 0; −1 where Hill's method failed)
// and "max_floquet_multiplier" (max |ρ|; −1 where unknown) follow, and the word column
// "bifurcation" (hb::to_string(Bifurcation)) ends every row.
const std::vector<std::string> kFrfColumns = {
    "level",       "force_amplitude",   "omega", "frequency_hz", "amplitude_h1", "amplitude_max",
    "dissipation", "newton_iterations", "step",  "fold",
    // Estimated relative errors (continuation/error_estimate.hpp, docs/theory.md §13), signed:
    // harmonic truncation (T-41) and time sampling (T-42) of amplitude_h1 and amplitude_max
    "amplitude_error_truncation", "amplitude_error_aliasing", "amplitude_max_error_truncation",
    "amplitude_max_error_aliasing",
    // the harmonics H and time samples N_t of the point (per point with `accuracy`)
    "harmonics", "time_samples"};

std::vector<std::string> frf_columns(bool stability) { return frf_columns_with_stability(kFrfColumns, stability); }

Json matrix_json(const hb::SparseMatrix& a) {
  const Eigen::MatrixXd d(a);
  Json rows = Json::array();
  for (Eigen::Index i = 0; i < d.rows(); ++i) {
    Json row = Json::array();
    for (Eigen::Index j = 0; j < d.cols(); ++j) row.push_back(d(i, j));
    rows.push_back(row);
  }
  return rows;
}

std::string selection_name(hb::HarmonicSelection s) {
  switch (s) {
    case hb::HarmonicSelection::automatic:
      return "auto";
    case hb::HarmonicSelection::all:
      return "all";
    case hb::HarmonicSelection::odd:
      return "odd";
  }
  return "?";
}

Json inputs_json(const io::DiscreteCase& c) {
  const auto& s = c.system;
  Json damping = {{"model", c.damping_model}};
  if (c.damping_model == "rayleigh") {
    damping["alpha"] = c.rayleigh_alpha;
    damping["beta"] = c.rayleigh_beta;
  } else if (c.damping_model == "modal") {
    damping["ratios"] = c.modal_damping_ratios;
  }
  damping["matrix"] =
      matrix_json(s.damping.rows() ? s.damping : hb::SparseMatrix(s.dofs(), s.dofs()));
  Json contacts = Json::array();
  for (const auto& e : s.contacts) {
    Json j = {{"law", e.law}};
    if (e.law == "gaul-mayer") j["n"] = e.exponent;
    j["dofs"] = e.dof_b >= 0 ? Json::array({e.dof_a, e.dof_b}) : Json::array({e.dof_a});
    j["kt0"] = e.stiffness;
    j["mu"] = e.friction_coefficient;
    j["normal_force"] = e.normal_force;
    j["reference_force"] = e.reference_force;
    j["reference_slip"] = e.reference_slip;
    contacts.push_back(j);
  }
  Json levels = Json::array();
  for (std::size_t l = 0; l < c.levels.size(); ++l) {
    Json forces = Json::array();
    for (const auto& f : c.levels[l].forces) {
      forces.push_back({{"dof", f.dof}, {"amplitude", f.amplitude}, {"harmonic", f.harmonic}});
    }
    Json level = {{"level", l}, {"force_amplitude", c.level_amplitudes[l]}, {"forces", forces}};
    if (c.levels[l].has_static_part()) {
      level["static_force"] =
          std::vector<double>(c.levels[l].static_force.data(),
                              c.levels[l].static_force.data() + c.levels[l].static_force.size());
    }
    levels.push_back(level);
  }
  Json inputs = {{"model",
                  {{"type", "discrete"},
                   {"dofs", s.dofs()},
                   {"mass", matrix_json(s.mass)},
                   {"stiffness", matrix_json(s.stiffness)},
                   {"damping", damping}}},
                 {"contacts", contacts},
                 {"excitation", levels}};
  if (c.frf) {
    const auto& f = *c.frf;
    inputs["frf"] = {{"omega", {f.omega_start, f.omega_end}},
                     {"harmonics", f.harmonics},
                     {"time_samples", f.time_samples},
                     {"output_dof", f.output_dof},
                     {"harmonic_selection", selection_name(f.selection)},
                     {"periodic_tolerance", f.periodic_tolerance},
                     {"check_jacobian", f.check_jacobian},
                     {"error_estimate", f.error_estimate},
                     {"stability", f.stability == continuation::Stability::automatic ? "auto"
                                   : f.stability == continuation::Stability::always  ? "true"
                                                                                     : "false"},
                     {"stability_method", continuation::to_string(f.stability_method)},
                     {"continuation",
                      {{"initial_step", f.continuation.initial_step},
                       {"min_step", f.continuation.min_step},
                       {"max_step", f.continuation.max_step},
                       {"max_points", f.continuation.max_points},
                       {"residual_tolerance", f.continuation.residual_tolerance}}}};
  }
  if (c.nonlinear_modes) {
    const auto& b = *c.nonlinear_modes;
    inputs["nonlinear_modes"] = {
        {"mode", c.modes},
        {"log10_amplitude", {b.log10_amplitude_start, b.log10_amplitude_end}},
        {"harmonics", b.mode.harmonics},
        {"time_samples", b.mode.time_samples},
        {"harmonic_selection", selection_name(b.mode.selection)},
        {"periodic_tolerance", b.mode.periodic_tolerance},
        {"error_estimate", b.error_estimate},
        {"continuation",
         {{"initial_step", b.continuation.initial_step},
          {"min_step", b.continuation.min_step},
          {"max_step", b.continuation.max_step},
          {"max_points", b.continuation.max_points},
          {"residual_tolerance", b.continuation.residual_tolerance}}}};
  }
  return inputs;
}

Json curve_json(std::size_t level, double force, const continuation::FrfCurve& curve,
                bool check_jacobian, const continuation::Accuracy& accuracy) {
  Json j = {{"level", level}, {"force_amplitude", force}};
  put_status(j, curve.status());
  j["stop_reason"] = std::string(continuation::to_string(curve.reason));  // the detail of the status
  j["points"] = curve.points.size();
  j["newton_iterations"] = curve.newton_iterations;
  j["rejected_steps"] = curve.rejected_steps;
  j["kept_harmonics"] = curve.kept_harmonics;
  const continuation::FrfPoint* peak = nullptr;
  int folds = 0;
  for (const auto& p : curve.points) {
    if (!peak || p.amplitude_h1 > peak->amplitude_h1) peak = &p;
    folds += p.fold ? 1 : 0;
  }
  if (peak) j["peak"] = peak_json(curve.peak, *peak);
  j["folds"] = folds;
  j["fold_points"] = fold_points_json(curve.folds);
  j["bifurcations"] = bifurcations_json(curve.points);
  const StabilityCounts counts = stability_counts(curve.points);
  j["stability"] = {{"points_known", counts.known}, {"unstable_points", counts.unstable}};
  if (!curve.stability_note.empty()) j["stability"]["note"] = curve.stability_note;
  if (check_jacobian) {
    j["jacobian_check_error"] = curve.jacobian_check_error;
    j["jacobian_check_omega"] = curve.jacobian_check_omega;
  }
  WorstErrors worst;
  for (const auto& p : curve.points) worst.add(p.error);
  j["error_estimate"] = worst.json("amplitude_h1", "amplitude_max");
  j["accuracy"] = accuracy_json(accuracy, curve.points, curve.level_changes, curve.short_of_accuracy);
  j["seconds"] = {{"aft", curve.timings.aft},
                  {"assembly", curve.timings.assembly},
                  {"linear_solve", curve.timings.linear_solve},
                  {"stability", curve.timings.stability},
                  {"refinement", curve.timings.refinement},
                  {"error_estimate", curve.timings.error_estimate},
                  {"total", curve.timings.total}};
  return j;
}

// Set-up errors (e.g. a forcing harmonic outside the basis) are input errors: reported before any
// output exists.
void check_setup(const io::DiscreteCase& c) {
  try {
    if (c.frf) {
      for (const auto& level : c.levels) {
        const hb::HarmonicBalance check(c.system, level,
                                        {c.frf->harmonics, c.frf->time_samples, c.frf->selection,
                                         c.frf->periodic_tolerance, true});
      }
    }
    if (c.nonlinear_modes) {
      const hb::NonlinearModeResidual check(c.system, c.nonlinear_modes->mode);
    }
  } catch (const std::invalid_argument& e) {
    throw UsageError(c.source + ": " + e.what());
  }
}

// One line naming the bifurcations of a curve and where it is unstable, or empty when there are
// none: "2 folds (Ω = 3.01, 2.87 rad/s), unstable for Ω in [2.87, 3.01] (5 points)".
std::string bifurcation_line(const continuation::FrfCurve& curve) {
  std::vector<std::string> parts;
  if (!curve.folds.empty()) {
    std::string where;
    for (const auto& f : curve.folds) where += fmt::format("{}{:.6g}", where.empty() ? "" : ", ", f.omega);
    parts.push_back(fmt::format("{} fold{} (Ω = {} rad/s)", curve.folds.size(),
                                curve.folds.size() == 1 ? "" : "s", where));
  }
  for (const auto& p : curve.points) {
    if (p.bifurcation == hb::Bifurcation::none || p.bifurcation == hb::Bifurcation::fold) continue;
    parts.push_back(fmt::format("{} near Ω = {:.6g} rad/s", hb::to_string(p.bifurcation), p.omega));
  }
  if (const StabilityCounts counts = stability_counts(curve.points); counts.unstable > 0) {
    parts.push_back(fmt::format("unstable for Ω in [{:.6g}, {:.6g}] rad/s ({} point{})", counts.lo,
                                counts.hi, counts.unstable, counts.unstable == 1 ? "" : "s"));
  }
  std::string line;
  for (const auto& part : parts) line += (line.empty() ? "" : "; ") + part;
  return line;
}

struct AnalysisOutcome {
  std::vector<NamedStatus> curves;  // how each curve ended, for the run's status
  std::size_t rows = 0;
  std::string what;  // for the final line
};

AnalysisOutcome run_frf(const io::DiscreteCase& c, pipeline::DiscretePipeline& pipe, const fs::path& dir, Json& summary) {
  const continuation::FrfOptions& options = *c.frf;
  summary["outputs"]["frf"] = "frf.csv";
  const bool stability = continuation::computes_stability(options, c.system.dofs());
  const std::vector<std::string> columns = frf_columns(stability);
  summary["columns"]["frf"] = columns;
  summary["curves"] = Json::array();
  io::CsvWriter csv(dir / "frf.csv", columns);
  const bool progress = stderr_is_terminal();
  AnalysisOutcome outcome;
  const auto frf_start = Clock::now();
  for (std::size_t l = 0; l < c.levels.size(); ++l) {
    const double force = c.level_amplitudes[l];
    continuation::FrfCurve curve;
    // The curve's rows are written when it ends (from the returned points, whose bifurcations the
    // curve may still revise: a fold split over two points, continuation/frf.cpp), or from the
    // points received so far if an error ends it.
    std::vector<continuation::FrfPoint> received;
    const auto write_row = [&](const continuation::FrfPoint& p) {
      std::vector<std::optional<double>> row = {static_cast<double>(l), force, p.omega,
                                                p.omega / (2.0 * std::numbers::pi), p.amplitude_h1,
                                                p.amplitude_max, p.dissipation,
                                                static_cast<double>(p.iterations), p.step, p.fold ? 1.0 : 0.0};
      for (const auto& field : frf_error_fields(p.error)) row.push_back(field);
      row.push_back(static_cast<double>(p.harmonics));
      row.push_back(static_cast<double>(p.time_samples));
      if (stability) {
        row.push_back(p.stability_known ? (p.stable ? 1.0 : 0.0) : -1.0);
        row.push_back(p.stability_known ? p.max_multiplier : -1.0);
      }
      const std::string bifurcation = hb::to_string(p.bifurcation);
      csv.write_row(std::span<const std::optional<double>>(row), std::span<const std::string>(&bifurcation, 1));
      ++outcome.rows;
    };
    const auto on_point = [&](const continuation::FrfPoint& p) {
      for (double v : {p.omega, p.amplitude_h1, p.amplitude_max, p.dissipation}) {
        require_finite_result("frf point", v);
      }
      received.push_back(p);
      if (progress) {
        std::cerr << fmt::format("\rjointhb run: level {}/{}  Ω = {:.6g} rad/s  |x| = {:.4g}  ",
                                 l + 1, c.levels.size(), p.omega, p.amplitude_h1)
                  << std::flush;
      }
      progress_activity("frf level {}/{}: omega = {:.6g} rad/s  |x| = {:.4g}", l + 1, c.levels.size(), p.omega,
                        p.amplitude_h1);
      return true;
    };
    try {
      curve = pipe.frf(l, on_point);  // the problem's level l and frf options (= *c.frf)
    } catch (const std::exception& e) {
      // The summary then describes exactly the rows written before the error.
      curve = continuation::FrfCurve{};
      curve.points = std::move(received);
      curve.reason = continuation::StopReason::error;
      curve.message = e.what();
    }
    for (const auto& p : curve.points) write_row(p);
    outcome.curves.push_back({fmt::format("frf level {}", l), curve.status()});
    summary["curves"].push_back(curve_json(l, force, curve, options.check_jacobian, options.accuracy));
    if (progress) std::cerr << '\r' << std::string(72, ' ') << '\r';
    if (!curve.completed()) {
      std::cerr << fmt::format(
          "jointhb run: level {} (force {} N): curve stopped at {} points: {}\n", l, force,
          curve.points.size(), curve.message);
    }
    if (const std::string line = bifurcation_line(curve); !line.empty()) {
      std::cerr << fmt::format("jointhb run: level {} (force {} N): {}\n", l, force, line);
    }
  }
  summary["seconds"]["frf"] = seconds_since(frf_start);
  outcome.what = fmt::format("{} FRF curve(s) with {} points", c.levels.size(), outcome.rows);
  return outcome;
}

AnalysisOutcome run_backbone(const io::DiscreteCase& c, pipeline::DiscretePipeline& pipe, const fs::path& dir,
                             Json& summary) {
  summary["outputs"]["backbone"] = "backbone.csv";
  summary["columns"]["backbone"] = kBackboneColumns;
  summary["backbones"] = Json::array();
  io::CsvWriter csv(dir / "backbone.csv", kBackboneColumns);
  const bool progress = stderr_is_terminal();
  AnalysisOutcome outcome;
  const auto start = Clock::now();
  for (int mode : c.modes) {
    continuation::BackboneOptions options = *c.nonlinear_modes;
    options.mode.mode = mode;
    Json points = Json::array();
    WorstErrors worst;  // over the rows written
    // A row of backbone.csv and an entry of summary.json for each point of the curve, written once
    // the curve is traced: a curve completed from both ends is not the sequence of points accepted
    // (continuation/backbone.hpp).
    const auto write_point = [&](const continuation::BackbonePoint& p) {
      const hb::NonlinearModeState& s = p.state;
      // Discrete contacts carry a constant normal force: none is ever open.
      std::vector<std::optional<double>> row = {
          static_cast<double>(mode), s.amplitude, p.output_amplitude, s.omega,
          s.omega / (2.0 * std::numbers::pi), s.damping_ratio, s.dissipation,
          s.viscous_dissipation, s.damping_ratio_energy, s.slip_fraction,
          static_cast<double>(s.slipping_points), 0.0};
      for (const auto& field : contact_state_fields(s.states)) row.push_back(field);
      row.push_back(static_cast<double>(p.iterations));
      row.push_back(p.step);
      const continuation::BackboneError& e = p.error;
      for (const auto& field : backbone_error_fields(e)) {
        row.push_back(field);
      }
      row.push_back(static_cast<double>(p.harmonics));
      row.push_back(static_cast<double>(p.time_samples));
      csv.write_row(std::span<const std::optional<double>>(row));
      worst.add(e);
      points.push_back({{"amplitude", s.amplitude},
                        {"omega", s.omega},
                        {"frequency_hz", s.omega / (2.0 * std::numbers::pi)},
                        {"damping_ratio", s.damping_ratio},
                        {"W_D", s.dissipation},
                        {"damping_ratio_energy", s.damping_ratio_energy},
                        {"slip_fraction", s.slip_fraction},
                        {"contact_states", contact_states_json(s.states)},
                        {"harmonics", p.harmonics},
                        {"time_samples", p.time_samples}});
      ++outcome.rows;
    };
    const auto on_point = [&](const continuation::BackbonePoint& p) {
      const hb::NonlinearModeState& s = p.state;
      for (double v : {s.amplitude, s.omega, s.damping_ratio, s.dissipation}) {
        require_finite_result("backbone point", v);
      }
      if (progress) {
        std::cerr << fmt::format("\rjointhb run: mode {}  q = {:.4g}  f = {:.6g} Hz  ζ = {:.4g}  ",
                                 mode, s.amplitude, s.omega / (2.0 * std::numbers::pi),
                                 s.damping_ratio)
                  << std::flush;
      }
      progress_activity("damping curve of mode {}: q = {:.4g}  f = {:.6g} Hz  zeta = {:.4g}", mode, s.amplitude,
                        s.omega / (2.0 * std::numbers::pi), s.damping_ratio);
      return true;
    };
    continuation::BackboneCurve curve;
    try {
      curve = pipe.backbone(options, on_point);
      for (const continuation::BackbonePoint& p : curve.points) write_point(p);
    } catch (const std::exception& e) {
      // An error (a non-finite output, or writing the CSV) ends the curve and loses its in-memory
      // points; the rows already written stay, and the summary below counts and lists exactly
      // those, with no invented linear values (null where the curve never computed them).
      curve = continuation::BackboneCurve{};
      curve.reason = continuation::StopReason::error;
      curve.message = e.what();
    }
    if (progress) std::cerr << '\r' << std::string(72, ' ') << '\r';
    outcome.curves.push_back({fmt::format("nonlinear mode {}", mode), curve.status()});
    Json entry = {{"mode", mode}};
    put_status(entry, curve.status());
    entry["stop_reason"] = std::string(continuation::to_string(curve.reason));  // the detail
    const bool lost = curve.reason == continuation::StopReason::error;
    const auto known = [&](double v) { return lost ? Json(nullptr) : Json(v); };
    entry.update(Json{
         {"linear_omega", known(curve.linear_omega)},
         {"linear_frequency_hz", known(curve.linear_omega / (2.0 * std::numbers::pi))},
         {"linear_damping_ratio", known(curve.linear_damping_ratio)},
         {"points", points.size()},
         {"newton_iterations", curve.newton_iterations},
         {"rejected_steps", curve.rejected_steps},
         {"seconds", curve.seconds},
         {"error_estimate", worst.json("omega", "damping")},
         {"curve", points}});
    if (!lost) entry["error_estimate"]["seconds"] = curve.error_seconds;
    entry["accuracy"] = accuracy_json(options.accuracy, curve.points, curve.level_changes, curve.short_of_accuracy);
    entry["turn_points"] = turns_json(curve.turns);
    summary["backbones"].push_back(std::move(entry));
    if (!curve.turns.empty()) std::cerr << "jointhb run: nonlinear mode " << mode << ": " << turns_line(curve.turns) << "\n";
    if (!curve.completed()) {
      std::cerr << fmt::format("jointhb run: nonlinear mode {}: curve stopped at {} points: {}\n",
                               mode, points.size(), curve.message);
    }
  }
  summary["seconds"]["nonlinear_modes"] = seconds_since(start);
  outcome.what = fmt::format("{} damping curve(s) with {} points", c.modes.size(), outcome.rows);
  return outcome;
}

}  // namespace

void check_discrete_setup(const io::DiscreteCase& c) { check_setup(c); }

int run_discrete_case(const io::DiscreteCase& c, const fs::path& dir, Clock::time_point start) {
  if (!c.frf && !c.nonlinear_modes) {
    throw UsageError(c.source + ": the case asks for no analysis jointhb can run");
  }
  const double read_seconds = seconds_since(start);
  check_setup(c);
  Json analyses = Json::array();
  if (c.frf) analyses.push_back("frf");
  if (c.nonlinear_modes) analyses.push_back("nonlinear_modes");
  Json summary = {{"jointhb_version", JOINTHB_VERSION},
                  {"status", nullptr},  // "running" until put_run_status below: "ok" or "failed"
                  {"case", c.source},
                  {"analyses", analyses},
                  {"inputs", inputs_json(c)},
                  {"outputs", Json::object()},
                  {"columns", Json::object()},
                  {"seconds", {{"read", read_seconds}}}};
  write_summary(dir / "summary.json", summary);  // "status": "running" before any curve
  // The discrete pipeline (no preload, no reduction) traces the curves.
  pipeline::DiscretePipeline pipe(c);
  std::vector<AnalysisOutcome> outcomes;
  if (c.frf) outcomes.push_back(run_frf(c, pipe, dir, summary));
  if (c.nonlinear_modes) outcomes.push_back(run_backbone(c, pipe, dir, summary));
  std::vector<NamedStatus> curves;
  std::string what;
  for (const auto& o : outcomes) {
    curves.insert(curves.end(), o.curves.begin(), o.curves.end());
    what += (what.empty() ? "" : " and ") + o.what;
  }
  const Status run = worst(curves);
  put_run_status(summary, run);
  summary["seconds"]["total"] = seconds_since(start);
  write_summary(dir / "summary.json", summary);
  if (!run.ok()) {
    // The last line of a failed run is its error line, as for the other kinds of case: a script
    // reading stderr must not take it for a finished one (the exit code says the same).
    std::cerr << fmt::format("jointhb run: {}: failed: {} ({}, {:.3g} s; results so far in {})\n", c.source,
                             io::printable_one_line(run.message), what, seconds_since(start), dir.string());
    return exit_failure;
  }
  std::cerr << fmt::format("jointhb run: {}: {} in {:.3g} s; wrote {}\n", c.source, what,
                           seconds_since(start), dir.string());
  return exit_ok;
}

}  // namespace jointhb::cli
