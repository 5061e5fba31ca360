#include "loop_command.hpp"

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "cli_support.hpp"
#include "jointhb/contact/harmonic_loop.hpp"
#include "jointhb/io/csv_writer.hpp"
#include "jointhb/io/value_checks.hpp"
#include "status_json.hpp"

namespace jointhb::cli {
namespace {

constexpr double degrees_to_radians = std::numbers::pi / 180.0;

// Values within this relative distance of the slip limit count as sliding: the limit is reached
// exactly in exact arithmetic, but the sampled loop may stop one rounding error short of it.
constexpr double gross_slip_tolerance = 1.0e-12;

struct HarmonicInput {
  contact::LoopHarmonic harmonic;
  double phase_deg = 0.0;
};

HarmonicInput parse_harmonic(const std::string& text, int time_samples) {
  const std::string option = "--harmonic";
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    fields.push_back(text.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (fields.size() < 2 || fields.size() > 3) {
    require_option(option, "must be K,AMPLITUDE[,PHASE_DEG], got '" + text + "'");
  }
  HarmonicInput input;
  const auto order = io::parse_integer(fields[0]);
  if (!order) require_option(option, "order K must be an integer, got '" + fields[0] + "'");
  // A harmonic at or above half the sampling rate would be aliased onto a lower one.
  const long long nyquist_order = time_samples / 2;
  if (*order < 1 || *order >= nyquist_order) {
    require_option(option, fmt::format("order K must be in [1, {}] (below time_samples/2), got {}",
                                       nyquist_order - 1, *order));
  }
  input.harmonic.order = static_cast<int>(*order);
  const auto amplitude = io::parse_number(fields[1]);
  if (!amplitude) require_option(option, "amplitude must be a number, got '" + fields[1] + "'");
  if (auto error = io::check_non_negative(*amplitude); !error.empty()) {
    require_option(option, "amplitude " + error);
  }
  input.harmonic.amplitude = *amplitude;
  if (fields.size() == 3) {
    const auto phase = io::parse_number(fields[2]);
    if (!phase) require_option(option, "phase must be a number, got '" + fields[2] + "'");
    if (auto error = io::check_finite(*phase); !error.empty()) {
      require_option(option, "phase " + error);
    }
    input.phase_deg = *phase;
  }
  input.harmonic.phase = input.phase_deg * degrees_to_radians;
  return input;
}

// Largest |F_T|/(μ F_N(t)) over the samples: 1 when the contact slides at some instant. With a
// constant normal force this is F̂/(μ F_N); open samples (F_N = 0) carry no friction and are
// skipped.
double peak_limit_ratio(const contact::LoopResult& r, double friction_coefficient) {
  double ratio = 0.0;
  for (std::size_t i = 0; i < r.force.size(); ++i) {
    const double limit = friction_coefficient * r.normal_force[i];
    if (limit > 0.0) ratio = std::max(ratio, std::abs(r.force[i]) / limit);
  }
  return ratio;
}

void require_finite_samples(const std::string& name, const std::vector<double>& values) {
  for (double v : values) require_finite_result(name, v);
}

}  // namespace

LoopCommand::LoopCommand(CLI::App& parent) {
  const contact::LoopOptions defaults;
  law_ = defaults.law;
  exponent_ = io::format_number(defaults.exponent);
  friction_coefficient_ = io::format_number(defaults.friction_coefficient);
  normal_force_ = io::format_number(defaults.normal_force);
  stiffness_ = io::format_number(defaults.stiffness);
  amplitude_ = io::format_number(defaults.amplitude);
  time_samples_ = std::to_string(defaults.time_samples);

  app_ = parent.add_subcommand(
      "loop",
      "Drive one contact point through its periodic steady state under the prescribed slip\n"
      "g_T(t) = a cos(wt) + sum_k a_k cos(k wt + phi_k), optionally with a normal motion\n"
      "F_N(t) = F_N exp(-lambda a_N cos(wt + phi_N)); report the dissipated energy per cycle W_D\n"
      "and the closed forms of eq. (11)/(12) and the general-n formula.");
  app_->add_option("--law", law_, "tangential law: gaul-mayer (eq. 10) or jenkins")
      ->type_name("NAME")
      ->capture_default_str();
  app_->add_option("--n", exponent_, "Gaul-Mayer exponent n, in (0, 1) (1/3 = Mindlin)")
      ->type_name("FLOAT")
      ->capture_default_str();
  app_->add_option("--mu", friction_coefficient_, "friction coefficient mu [-], > 0")
      ->type_name("FLOAT")
      ->capture_default_str();
  app_->add_option("--normal-force", normal_force_, "mean normal force F_N [N], > 0")
      ->type_name("FLOAT")
      ->capture_default_str();
  app_->add_option("--kt0", stiffness_, "initial tangential stiffness k_T0 [N/m], > 0")
      ->type_name("FLOAT")
      ->capture_default_str();
  app_->add_option("--amplitude", amplitude_, "slip amplitude a of the fundamental [m], >= 0")
      ->type_name("FLOAT")
      ->capture_default_str();
  app_->add_option("--time-samples", time_samples_,
                   fmt::format("samples per period N, in [4, {}]", io::max_time_samples))
      ->type_name("INT")
      ->capture_default_str();
  app_->add_option("--harmonic", harmonics_,
                   "add a_k cos(k wt + phi_k) to the slip: order K in [1, N/2), amplitude a_k [m] "
                   ">= 0, phase phi_k [deg] (default 0); repeatable")
      ->type_name("K,AMPLITUDE[,PHASE_DEG]")
      ->allow_extra_args(false);
  app_->add_option("--normal-amplitude", normal_amplitude_,
                   "normal gap amplitude a_N [m] (0: constant normal force)")
      ->type_name("FLOAT")
      ->capture_default_str();
  app_->add_option("--normal-phase", normal_phase_deg_, "normal phase phi_N [deg]")
      ->type_name("FLOAT")
      ->capture_default_str();
  app_->add_option("--lambda", normal_decay_,
                   "decay lambda = 1/sigma of the exponential normal law (eq. 6) [1/m], >= 0; "
                   "> 0 when --normal-amplitude is not 0")
      ->type_name("FLOAT")
      ->capture_default_str();
  app_->add_flag("--kt-follows-normal", stiffness_follows_normal_,
                 "k_T(t) = k_T0 F_N(t)/F_N (stiffness proportional to the normal load) instead of "
                 "a constant k_T0");
  app_->add_flag("--json", json_, "print one JSON object on stdout instead of a table");
  app_->add_option("--csv", csv_path_,
                   "write the loop samples to FILE: phase_rad,slip_m,force_N,normal_force_N")
      ->type_name("FILE");
  app_->footer(
      "Exit codes: 0 converged, 1 not converged or failed, 2 invalid options.\n"
      "Example: jointhb loop --amplitude 2e-5 --json");
}

bool LoopCommand::selected() const { return app_->parsed(); }

int LoopCommand::run() const {
  contact::LoopOptions options;
  require_option("--law", io::check_one_of(law_, {"gaul-mayer", "jenkins"}));
  options.law = law_;
  options.exponent = number_option("--n", exponent_);
  require_option("--n", io::check_open_unit(options.exponent));
  options.friction_coefficient = number_option("--mu", friction_coefficient_);
  require_option("--mu", io::check_positive(options.friction_coefficient));
  options.normal_force = number_option("--normal-force", normal_force_);
  require_option("--normal-force", io::check_positive(options.normal_force));
  options.stiffness = number_option("--kt0", stiffness_);
  require_option("--kt0", io::check_positive(options.stiffness));
  options.amplitude = number_option("--amplitude", amplitude_);
  require_option("--amplitude", io::check_non_negative(options.amplitude));
  options.time_samples = integer_option("--time-samples", time_samples_, 4, io::max_time_samples);
  std::vector<HarmonicInput> harmonics;
  for (const auto& text : harmonics_) {
    harmonics.push_back(parse_harmonic(text, options.time_samples));
    options.harmonics.push_back(harmonics.back().harmonic);
  }
  options.normal_amplitude = number_option("--normal-amplitude", normal_amplitude_);
  require_option("--normal-amplitude", io::check_finite(options.normal_amplitude));
  const double normal_phase_deg = number_option("--normal-phase", normal_phase_deg_);
  require_option("--normal-phase", io::check_finite(normal_phase_deg));
  options.normal_phase = normal_phase_deg * degrees_to_radians;
  options.normal_decay = number_option("--lambda", normal_decay_);
  require_option("--lambda", io::check_non_negative(options.normal_decay));
  if (options.normal_amplitude != 0.0 && options.normal_decay == 0.0) {
    require_option("--lambda", "must be > 0 when --normal-amplitude is not 0, got 0");
  }
  options.stiffness_follows_normal = stiffness_follows_normal_;
  // The library's constraints that involve several options (e.g. the slip range) are reported
  // at the option their message names.
  if (const std::string msg = options.validate(); !msg.empty()) {
    const std::size_t colon = msg.find(": ");
    const std::string field = msg.substr(0, colon);
    for (const auto& [name, option] : {std::pair{"amplitude", "--amplitude"}, std::pair{"mu", "--mu"},
                                       std::pair{"normal_force", "--normal-force"}, std::pair{"kt0", "--kt0"},
                                       std::pair{"lambda", "--lambda"}}) {
      if (field == name && colon != std::string::npos) require_option(option, msg.substr(colon + 2));
    }
  }

  contact::LoopResult r;
  try {
    r = contact::run_loop(options);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());  // the library's own validation: still bad input
  }

  const bool jenkins = options.law == "jenkins";
  const bool formulas = r.formulas_apply && !jenkins;
  // run_loop fills the Jenkins closed form only for the plain harmonic path (it leaves 0
  // otherwise), while formulas_apply is false for every Jenkins run: decide here which one is
  // meaningful.
  const bool jenkins_formula =
      jenkins && options.harmonics.empty() && options.normal_amplitude == 0.0;
  require_finite_result("W_D", r.dissipation);
  require_finite_result("F_hat", r.force_amplitude);
  require_finite_result("loading_span", r.loading_span);
  require_finite_result("g_max", r.full_slip_span);
  require_finite_result("residual", r.state.residual);
  // The closed forms are only compared with W_D: one that does not fit in double precision (an
  // overflow at extreme scales) is reported as unavailable (null, a note), W_D stays the answer.
  const auto available = [](bool applies, double value) -> std::optional<double> {
    return applies && std::isfinite(value) ? std::optional<double>(value) : std::nullopt;
  };
  const std::optional<double> wd_paper = available(formulas, r.dissipation_paper);
  const std::optional<double> wd_general = available(formulas, r.dissipation_general);
  const std::optional<double> wd_paper_a = available(formulas, r.dissipation_paper_amplitude_reading);
  const std::optional<double> wd_jenkins = available(jenkins_formula, r.dissipation_jenkins);
  require_finite_samples("slip", r.slip);
  require_finite_samples("force", r.force);
  require_finite_samples("normal_force", r.normal_force);
  if (r.phase.size() != r.slip.size() || r.force.size() != r.slip.size() ||
      r.normal_force.size() != r.slip.size()) {
    throw std::runtime_error("run_loop returned sample vectors of different lengths");
  }

  const bool converged = r.state.termination == jointhb::Termination::converged;
  const bool sliding =
      peak_limit_ratio(r, options.friction_coefficient) >= 1.0 - gross_slip_tolerance;
  const std::string regime = sliding ? "gross slip" : (jenkins ? "stick" : "microslip");
  const auto optional = [](const std::optional<double>& value) -> nlohmann::ordered_json {
    return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
  };

  if (!csv_path_.empty()) {
    std::optional<io::CsvWriter> csv;
    try {
      csv.emplace(csv_path_,
                  std::vector<std::string>{"phase_rad", "slip_m", "force_N", "normal_force_N"});
    } catch (const std::runtime_error& e) {
      require_option("--csv", e.what());
    }
    for (std::size_t i = 0; i < r.slip.size(); ++i) {
      csv->write_row({r.phase[i], r.slip[i], r.force[i], r.normal_force[i]});
    }
  }

  if (json_) {
    nlohmann::ordered_json harmonics_json = nlohmann::ordered_json::array();
    for (const auto& h : harmonics) {
      harmonics_json.push_back({{"order", h.harmonic.order},
                                {"amplitude", h.harmonic.amplitude},
                                {"phase_deg", h.phase_deg}});
    }
    nlohmann::ordered_json out = {
        {"W_D", r.dissipation},
        {"F_hat", r.force_amplitude},
        {"loading_span", r.loading_span},
        {"W_D_paper", optional(wd_paper)},
        {"W_D_general", optional(wd_general)},
        {"W_D_paper_amplitude_reading", optional(wd_paper_a)},
        {"W_D_jenkins", optional(wd_jenkins)},
        {"formulas_apply", r.formulas_apply},
        {"g_max", r.full_slip_span},
        {"regime", regime},
        {"inputs",
         {{"law", options.law},
          {"n", options.exponent},
          {"mu", options.friction_coefficient},
          {"normal_force", options.normal_force},
          {"kt0", options.stiffness},
          {"amplitude", options.amplitude},
          {"time_samples", options.time_samples},
          {"harmonics", harmonics_json},
          {"normal_amplitude", options.normal_amplitude},
          {"normal_phase_deg", normal_phase_deg},
          {"lambda", options.normal_decay},
          {"kt_follows_normal", options.stiffness_follows_normal}}},
        {"iterations", r.state.iterations},
        {"residual", r.state.residual},
        {"termination", nullptr},  // put_status below: the periodic state's status()
        {"ok", nullptr},
        {"message", nullptr},
        {"seconds", r.seconds},
    };
    put_status(out, r.state.status());
    if (!csv_path_.empty()) out["csv"] = csv_path_;
    std::cout << out.dump(2) << '\n';
  } else {
    const auto relative = [&](double formula) {
      return r.dissipation > 0.0 ? fmt::format("  (rel. diff. {:.3g})",
                                               std::abs(formula - r.dissipation) / r.dissipation)
                                 : std::string();
    };
    const auto print_formula = [&](const char* label, const std::optional<double>& value, double raw) {
      if (value)
        fmt::print("  {:<28}{:.10g} J{}\n", label, *value, relative(*value));
      else
        fmt::print("  {:<28}unavailable: {}\n", label, describe_result(raw));
    };
    fmt::print("jointhb loop: {}, n = {}, mu = {}, F_N = {} N, k_T0 = {} N/m, a = {} m, N = {}\n",
               options.law, io::format_number(options.exponent),
               io::format_number(options.friction_coefficient),
               io::format_number(options.normal_force), io::format_number(options.stiffness),
               io::format_number(options.amplitude), options.time_samples);
    fmt::print("  {:<28}{:.10g} J\n", "W_D (periodic state)", r.dissipation);
    if (formulas) {
      print_formula("W_D general-n formula", wd_general, r.dissipation_general);
      print_formula("W_D eq. (11)/(12) at span", wd_paper, r.dissipation_paper);
      print_formula("W_D eq. (11)/(12) at a", wd_paper_a, r.dissipation_paper_amplitude_reading);
    } else if (!jenkins_formula) {
      fmt::print("  {:<28}{}\n", "closed forms", "do not apply (harmonics or normal motion)");
    }
    if (jenkins_formula) print_formula("W_D Jenkins closed form", wd_jenkins, r.dissipation_jenkins);
    fmt::print("  {:<28}{:.10g} N\n", "F_hat", r.force_amplitude);
    fmt::print("  {:<28}{:.10g} m\n", "loading span", r.loading_span);
    fmt::print("  {:<28}{:.10g} m\n", "g_max", r.full_slip_span);
    fmt::print("  {:<28}{}\n", "regime", regime);
    fmt::print("  {:<28}{} ({} iterations, residual {:.3g})\n", "converged",
               converged ? "yes" : "NO", r.state.iterations, r.state.residual);
    fmt::print("  {:<28}{:.3g} s\n", "time", r.seconds);
    if (!csv_path_.empty()) fmt::print("  {:<28}{}\n", "samples written to", csv_path_);
  }

  if (!converged) {
    std::cerr << "jointhb loop: periodic state not converged after " << r.state.iterations
              << " iterations (residual " << io::format_number(r.state.residual) << ")"
              << (r.state.message.empty() ? "" : ": " + r.state.message) << '\n';
    return exit_failure;
  }
  return exit_ok;
}

}  // namespace jointhb::cli
