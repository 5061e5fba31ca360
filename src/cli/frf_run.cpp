#include "frf_run.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "cli_support.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/io/csv_writer.hpp"

namespace jointhb::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

const std::vector<std::string> kFrfColumns = {
    "level",       "force_amplitude",   "omega", "frequency_hz", "amplitude_h1", "amplitude_max",
    "dissipation", "newton_iterations", "step",  "fold"};

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

std::string reason_name(continuation::StopReason r) {
  switch (r) {
    case continuation::StopReason::reached_end:
      return "reached_end";
    case continuation::StopReason::max_points:
      return "max_points";
    case continuation::StopReason::min_step:
      return "min_step";
    case continuation::StopReason::start_failed:
      return "start_failed";
    case continuation::StopReason::stopped_by_user:
      return "stopped_by_user";
    case continuation::StopReason::left_range:
      return "left_range";
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
                     {"continuation",
                      {{"initial_step", f.continuation.initial_step},
                       {"min_step", f.continuation.min_step},
                       {"max_step", f.continuation.max_step},
                       {"max_points", f.continuation.max_points},
                       {"residual_tolerance", f.continuation.residual_tolerance}}}};
  }
  return inputs;
}

Json curve_json(std::size_t level, double force, const continuation::FrfCurve& curve,
                bool check_jacobian) {
  Json j = {{"level", level},
            {"force_amplitude", force},
            {"status", curve.completed() ? "ok" : "failed"},
            {"stop_reason", reason_name(curve.reason)},
            {"message", curve.message},
            {"points", curve.points.size()},
            {"newton_iterations", curve.newton_iterations},
            {"rejected_steps", curve.rejected_steps},
            {"kept_harmonics", curve.kept_harmonics}};
  const continuation::FrfPoint* peak = nullptr;
  int folds = 0;
  for (const auto& p : curve.points) {
    if (!peak || p.amplitude_h1 > peak->amplitude_h1) peak = &p;
    folds += p.fold ? 1 : 0;
  }
  if (peak) {
    j["peak"] = {{"omega", peak->omega},
                 {"frequency_hz", peak->omega / (2.0 * std::numbers::pi)},
                 {"amplitude_h1", peak->amplitude_h1},
                 {"amplitude_max", peak->amplitude_max}};
  }
  j["folds"] = folds;
  if (check_jacobian) {
    j["jacobian_check_error"] = curve.jacobian_check_error;
    j["jacobian_check_omega"] = curve.jacobian_check_omega;
  }
  j["seconds"] = {{"aft", curve.timings.aft},
                  {"assembly", curve.timings.assembly},
                  {"linear_solve", curve.timings.linear_solve},
                  {"total", curve.timings.total}};
  return j;
}

}  // namespace

int run_discrete_case(const io::DiscreteCase& c, const fs::path& dir, Clock::time_point start) {
  if (!c.frf) throw UsageError(c.source + ": the case asks for no analysis jointhb can run");
  const continuation::FrfOptions& options = *c.frf;
  const double read_seconds = seconds_since(start);
  // Set-up errors (e.g. a forcing harmonic outside the basis) are input errors: report them before
  // any output exists.
  for (const auto& level : c.levels) {
    try {
      const hb::HarmonicBalance check(c.system, level,
                                      {options.harmonics, options.time_samples, options.selection,
                                       options.periodic_tolerance, true});
    } catch (const std::invalid_argument& e) {
      throw UsageError(c.source + ": " + e.what());
    }
  }

  Json summary = {{"jointhb_version", JOINTHB_VERSION},
                  {"status", "ok"},
                  {"message", ""},
                  {"case", c.source},
                  {"analysis", "frf"},
                  {"inputs", inputs_json(c)},
                  {"outputs", {{"frf", "frf.csv"}}},
                  {"columns", kFrfColumns},
                  {"curves", Json::array()}};
  io::CsvWriter csv(dir / "frf.csv", kFrfColumns);
  const bool progress = stderr_is_terminal();
  int failed = 0;
  std::size_t rows = 0;
  const auto frf_start = Clock::now();
  for (std::size_t l = 0; l < c.levels.size(); ++l) {
    const double force = c.level_amplitudes[l];
    continuation::FrfCurve curve;
    const auto on_point = [&](const continuation::FrfPoint& p) {
      for (double v : {p.omega, p.amplitude_h1, p.amplitude_max, p.dissipation}) {
        require_finite_result("frf point", v);
      }
      csv.write_row({static_cast<double>(l), force, p.omega, p.omega / (2.0 * std::numbers::pi),
                     p.amplitude_h1, p.amplitude_max, p.dissipation,
                     static_cast<double>(p.iterations), p.step, p.fold ? 1.0 : 0.0});
      ++rows;
      if (progress) {
        std::cerr << fmt::format("\rjointhb run: level {}/{}  Ω = {:.6g} rad/s  |x| = {:.4g}  ",
                                 l + 1, c.levels.size(), p.omega, p.amplitude_h1)
                  << std::flush;
      }
      return true;
    };
    try {
      curve = continuation::trace_frf(c.system, c.levels[l], options, on_point);
    } catch (const std::exception& e) {
      curve.reason = continuation::StopReason::start_failed;
      curve.message = e.what();
    }
    if (!curve.completed()) ++failed;
    summary["curves"].push_back(curve_json(l, force, curve, options.check_jacobian));
    if (progress) std::cerr << '\r' << std::string(72, ' ') << '\r';
    if (!curve.completed()) {
      std::cerr << fmt::format(
          "jointhb run: level {} (force {} N): curve stopped at {} points: {}\n", l, force,
          curve.points.size(), curve.message);
    }
  }
  const double frf_seconds = seconds_since(frf_start);
  if (failed > 0) {
    summary["status"] = "failed";
    summary["message"] =
        fmt::format("{} of {} curves stopped before the end of the range", failed, c.levels.size());
  }
  summary["seconds"] = {
      {"read", read_seconds}, {"frf", frf_seconds}, {"total", seconds_since(start)}};
  write_summary(dir / "summary.json", summary);
  std::cerr << fmt::format(
      "jointhb run: {}: {} FRF curve(s), {} points in {:.3g} s; wrote {} and {}\n", c.source,
      c.levels.size(), rows, seconds_since(start), (dir / "frf.csv").string(),
      (dir / "summary.json").string());
  return failed > 0 ? exit_failure : exit_ok;
}

}  // namespace jointhb::cli
