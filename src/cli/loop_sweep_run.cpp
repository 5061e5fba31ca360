#include "loop_sweep_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "cli_support.hpp"
#include "jointhb/contact/harmonic_loop.hpp"
#include "jointhb/io/csv_writer.hpp"
#include "jointhb/io/value_checks.hpp"
#include "status_json.hpp"

namespace jointhb::cli {
namespace {

namespace fs = std::filesystem;

// |formula - W_D|/W_D; 0 when both vanish (a sticking Jenkins contact), and relative to the
// formula when only W_D vanishes so that the error stays finite and still shows.
double relative_error(double formula, double reference) {
  const double scale = std::max(std::abs(reference), std::abs(formula));
  if (scale == 0.0) return 0.0;
  return std::abs(formula - reference) / (reference != 0.0 ? std::abs(reference) : scale);
}

struct SweepOutcome {
  /// The run's status: reached_end when every amplitude was computed, failed (with the point and
  /// why) when one threw.
  Status run{Termination::reached_end, {}};
  int points_done = 0;
  double max_rel_err_general = 0.0;
  double max_rel_err_paper = 0.0;
  double max_rel_err_jenkins = 0.0;
  int iterations = 0;
};

std::vector<std::string> sweep_columns(bool jenkins) {
  if (jenkins) {
    return {"amplitude_m", "amplitude_over_gmax", "F_hat_N",        "loading_span_m",
            "W_D_J",       "W_D_jenkins_J",       "rel_err_jenkins"};
  }
  return {"amplitude_m",   "amplitude_over_gmax", "F_hat_N",         "loading_span_m", "W_D_J",
          "W_D_general_J", "W_D_paper_J",         "rel_err_general", "rel_err_paper"};
}

// One point of the sweep: run the loop, check it, append its row. Throws on any failure.
void run_point(const io::LoopSweepCase& c, double ratio, io::CsvWriter& csv,
               SweepOutcome& outcome) {
  const bool jenkins = c.law == "jenkins";
  contact::LoopOptions options;
  options.law = c.law;
  options.exponent = c.exponent;
  options.friction_coefficient = c.friction_coefficient;
  options.normal_force = c.normal_force;
  options.stiffness = c.stiffness;
  options.amplitude = ratio * c.full_slip_span();
  options.time_samples = c.time_samples;

  const contact::LoopResult r = contact::run_loop(options);
  if (r.state.termination != jointhb::Termination::converged) {
    throw std::runtime_error(
        fmt::format("periodic state not converged after {} iterations (residual {}){}",
                    r.state.iterations, describe_result(r.state.residual),
                    r.state.message.empty() ? "" : ": " + r.state.message));
  }
  require_finite_result("W_D", r.dissipation);
  require_finite_result("F_hat", r.force_amplitude);
  require_finite_result("loading_span", r.loading_span);
  outcome.iterations += r.state.iterations;

  if (jenkins) {
    require_finite_result("W_D_jenkins", r.dissipation_jenkins);
    const double error = relative_error(r.dissipation_jenkins, r.dissipation);
    csv.write_row({options.amplitude, ratio, r.force_amplitude, r.loading_span, r.dissipation,
                   r.dissipation_jenkins, error});
    outcome.max_rel_err_jenkins = std::max(outcome.max_rel_err_jenkins, error);
  } else {
    if (!r.formulas_apply) throw std::logic_error("run_loop: closed forms do not apply");
    require_finite_result("W_D_general", r.dissipation_general);
    require_finite_result("W_D_paper", r.dissipation_paper);
    const double error_general = relative_error(r.dissipation_general, r.dissipation);
    const double error_paper = relative_error(r.dissipation_paper, r.dissipation);
    csv.write_row({options.amplitude, ratio, r.force_amplitude, r.loading_span, r.dissipation,
                   r.dissipation_general, r.dissipation_paper, error_general, error_paper});
    outcome.max_rel_err_general = std::max(outcome.max_rel_err_general, error_general);
    outcome.max_rel_err_paper = std::max(outcome.max_rel_err_paper, error_paper);
  }
  ++outcome.points_done;
}

// `ended`: false for the summary written at the start ("status": "running", run_support.hpp).
nlohmann::ordered_json summary_json(const io::LoopSweepCase& c, const SweepOutcome& outcome,
                                    double seconds, bool ended = true) {
  const bool jenkins = c.law == "jenkins";
  const bool built_in = c.source == "built-in";
  nlohmann::ordered_json summary = {
      {"jointhb_version", JOINTHB_VERSION},
      {"status", nullptr},  // the run's status, by put_run_status below
      {"case", c.source},
      {"description", built_in ? "built-in default case" : "case file"},
      {"analysis", "loop_sweep"},
      {"inputs",
       {{"law", c.law},
        {"n", c.exponent},
        {"mu", c.friction_coefficient},
        {"normal_force", c.normal_force},
        {"kt0", c.stiffness},
        {"amplitude_over_gmax", {c.ratio_min, c.ratio_max}},
        {"points", c.points},
        {"time_samples", c.time_samples}}},
      {"g_max", c.full_slip_span()},
      {"points", c.points},
      {"points_completed", outcome.points_done},
      {"periodic_iterations", outcome.iterations},
      {"outputs", {{"wd_sweep", "wd_sweep.csv"}}},
      {"columns", sweep_columns(jenkins)},
      {"seconds", seconds},
  };
  if (jenkins) {
    summary["max_rel_err_jenkins"] = outcome.max_rel_err_jenkins;
  } else {
    summary["max_rel_err_general"] = outcome.max_rel_err_general;
    summary["max_rel_err_paper"] = outcome.max_rel_err_paper;
  }
  if (ended) put_run_status(summary, outcome.run);
  return summary;
}

}  // namespace

int run_loop_sweep(const io::LoopSweepCase& c, const fs::path& dir, Clock::time_point start) {
  const bool built_in = c.source == "built-in";
  SweepOutcome outcome;
  std::optional<io::CsvWriter> csv;
  const bool progress = stderr_is_terminal();
  const std::vector<double> ratios = c.amplitude_ratios();
  write_summary(dir / "summary.json", summary_json(c, outcome, seconds_since(start), false));
  try {
    csv.emplace(dir / "wd_sweep.csv", sweep_columns(c.law == "jenkins"));
    for (std::size_t i = 0; i < ratios.size(); ++i) {
      if (progress) {
        std::cerr << fmt::format(
                         "\rjointhb run: point {}/{}  a/g_max = {:.3e}  ({} periods so far)", i + 1,
                         ratios.size(), ratios[i], outcome.iterations)
                  << std::flush;
      }
      progress_activity("point {}/{}  a/g_max = {:.3e}", i + 1, ratios.size(), ratios[i]);
      try {
        run_point(c, ratios[i], *csv, outcome);
      } catch (const std::exception& e) {
        throw std::runtime_error(fmt::format("point {}/{} (a/g_max = {}): {}", i + 1, ratios.size(),
                                             io::format_number(ratios[i]), e.what()));
      }
    }
  } catch (const std::exception& e) {
    outcome.run = {Termination::failed, e.what()};
  }
  if (progress) std::cerr << '\r' << std::string(72, ' ') << '\r';  // the summary replaces it

  const double seconds = seconds_since(start);
  write_summary(dir / "summary.json", summary_json(c, outcome, seconds));
  const std::string what = built_in ? "built-in default case" : c.source;
  if (!outcome.run.ok()) {
    std::cerr << "jointhb run: " << what << ": failed: " << outcome.run.message << " ("
              << outcome.points_done << " rows kept in " << (dir / "wd_sweep.csv").string()
              << ")\n";
    return exit_failure;
  }
  const std::string errors =
      c.law == "jenkins" ? fmt::format("max rel. err. Jenkins {:.2e}", outcome.max_rel_err_jenkins)
                         : fmt::format("max rel. err. general {:.2e}, paper {:.2e}",
                                       outcome.max_rel_err_general, outcome.max_rel_err_paper);
  std::cerr << fmt::format(
      "jointhb run: {}: loop sweep of {} amplitudes in {:.3g} s ({}); wrote "
      "{} and {}\n",
      what, outcome.points_done, seconds, errors, (dir / "wd_sweep.csv").string(),
      (dir / "summary.json").string());
  return exit_ok;
}

}  // namespace jointhb::cli
