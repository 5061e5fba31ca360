#include "fit_command.hpp"

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <iostream>
#include <limits>
#include <variant>

#include "cli_support.hpp"
#include "jointhb/pipeline/discrete_fit_model.hpp"
#include "jointhb/fit/history.hpp"
#include "jointhb/io/case_file.hpp"
#include "jointhb/io/csv_writer.hpp"
#include "jointhb/io/stage_cache.hpp"
#include "jointhb/pipeline/fe_fit_model.hpp"
#include "jointhb/study/distributed.hpp"
#include "plot_results.hpp"
#include "run_support.hpp"
#include "status_json.hpp"

namespace jointhb::cli {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

// A JSON number, or null for ∞ and NaN (an unidentifiable parameter has no standard error).
Json number_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

std::vector<std::string> names_of(const std::vector<fit::FitParameter>& parameters) {
  std::vector<std::string> names;
  for (const auto& p : parameters) names.push_back(p.name);
  return names;
}

double quantity_code(fit::Quantity q) {
  return q == fit::Quantity::frequency_hz ? 0.0 : q == fit::Quantity::damping_ratio ? 1.0 : 2.0;
}

double kind_code(fit::TargetKind k) {
  return k == fit::TargetKind::backbone ? 0.0 : k == fit::TargetKind::frf ? 1.0 : 2.0;
}

// The model's whole curves (for the plot) and its values at the target points.
void write_model_curves(io::CsvWriter& csv, double label, const std::vector<fit::Target>& targets,
                        const fit::ModelPrediction& prediction) {
  for (std::size_t t = 0; t < targets.size() && t < prediction.curves.size(); ++t) {
    const auto& c = prediction.curves[t];
    if (!c.ok) continue;
    const auto put = [&](fit::Quantity q, const std::vector<double>& y) {
      for (std::size_t i = 0; i < y.size() && i < c.abscissa.size(); ++i) {
        if (std::isfinite(y[i]) && std::isfinite(c.abscissa[i])) {
          csv.write_row({label, static_cast<double>(t), quantity_code(q), c.abscissa[i], y[i]});
        }
      }
    };
    put(fit::Quantity::frequency_hz, c.frequency_hz);
    put(fit::Quantity::damping_ratio, c.damping_ratio);
    put(fit::Quantity::amplitude, c.amplitude);
  }
}

// Says what -j N (or the ranks) cannot spread: a single start, or the global phase of direct/mlsl.
void note_serial_search(const fit::FitOptions& o, int jobs, int workers, std::size_t parameters) {
  if (workers <= 1) return;
  const bool global = o.algorithm == "direct" || o.algorithm == "mlsl";  // batches: parallel
  if (global || o.starts > 1) return;
  std::cerr << fmt::format(
      "jointhb fit: note: {} workers, but a single start (fit.options multistart.starts = 1): the "
      "search runs in one process; {}\n",
      workers,
      jobs > 1 ? fmt::format("only the Jacobian's {} evaluations at the optimum are spread over the {} "
                             "local workers", 2 * parameters, jobs)
               : std::string("the other ranks have nothing to do"));
}

}  // namespace

FitCommand::FitCommand(CLI::App& parent, const study::Communicator& communicator)
    : communicator_(communicator) {
  app_ = parent.add_subcommand(
      "fit",
      "Identify model parameters from measured data (docs/identification.md): the case's fit\n"
      "section names the parameters (bounds, start, log scale), the target CSV files\n"
      "(backbone: amplitude -> frequency_hz, damping_ratio; frf: frequency_hz -> amplitude;\n"
      "modal: mode -> frequency_hz, damping_ratio) and the NLopt search. Writes\n"
      "  DIR/fit_history.csv   one row per evaluation, flushed (an interrupted run keeps it)\n"
      "  DIR/fit.json          fitted values, standard errors, correlation, singular values,\n"
      "                        identifiability warnings, residual per target, evaluations, time\n"
      "  DIR/fit_curves.csv    measured vs fitted at every target point\n"
      "  DIR/fit_model_curves.csv  the model's curves at the start and at the optimum\n"
      "  DIR/fit.png           fitted vs measured (needs python3-matplotlib)\n"
      "Parallel: the starts of a multi-start search (multistart.starts > 1), each a whole local\n"
      "search, run on -j local worker processes and, under mpirun -np N, on the other ranks\n"
      "(rank 0 coordinates and alone writes files); then the Jacobian's 2p evaluations at the\n"
      "optimum on the local workers. Not parallel: a single start, and the global phase of\n"
      "direct/mlsl (NLopt calls the model in sequence). The results do not depend on -j or ranks.");
  app_->add_option("case", case_path_, "case file (YAML) with a fit section")
      ->type_name("CASE.yaml")
      ->required();
  app_->add_option("-o,--output", output_dir_, "output directory, created if needed")
      ->type_name("DIR")
      ->capture_default_str();
  app_->add_option("-j,--jobs", jobs_,
                   "local worker processes for the starts and the Jacobian (default 1); the results do "
                   "not depend on it")
      ->type_name("N");
  app_->add_flag("--resume", resume_,
                 "continue from DIR/fit_history.csv: evaluations found in it are not recomputed");
  app_->add_option("--cache-dir", cache_dir_,
                   "finite-element cases: the stage cache (default DIR/.cache; the same as jointhb "
                   "run's, so a fit can start from a run's stages)")
      ->type_name("DIR");
  app_->add_flag("--quiet", quiet_, "no progress line, warnings or table (errors only)");
  app_->footer(
      "Exit codes: 0 ok, 1 every evaluation failed, 2 invalid case file or options.\n"
      "Example: jointhb fit cases/10-fit-one-dof/case.yaml -o out\n"
      "         mpirun -np 2 jointhb fit CASE.yaml -o out");
}

bool FitCommand::selected() const { return app_->parsed(); }

int FitCommand::run() const {
  const auto start = Clock::now();
  const bool root = communicator_.rank() == 0;
  fit::ParallelOptions parallel;
  parallel.jobs = jobs_.empty() ? 1 : integer_option("--jobs", jobs_, 1, 1024);
  parallel.communicator = &communicator_;
  const double progress_seconds = progress_interval();
  const io::CaseFile file = io::read_case_file(case_path_);
  const auto* c = std::get_if<io::DiscreteCase>(&file);
  const auto* fe = std::get_if<io::FeCase>(&file);
  if (!c && !fe) {
    throw UsageError(case_path_ +
                     ": jointhb fit needs a discrete (model.type discrete) or finite-element "
                     "(model.type fe) case with a fit section");
  }
  const std::optional<io::FitSection>& fit_section = c ? c->fit : fe->fit;
  if (!fit_section) throw UsageError(case_path_ + ": the case has no fit section (docs/case-files.md)");
  const std::string source = c ? c->source : fe->source;
  const io::FitSection& section = *fit_section;
  const std::vector<std::string> names = names_of(section.parameters);
  const fs::path dir(output_dir_);
  const fs::path history_file = dir / "fit_history.csv";
  std::vector<fit::HistoryRow> replay;
  if (resume_) {
    std::error_code ec;
    if (!fs::exists(history_file, ec)) {
      require_option("--resume", fmt::format("no history to resume from: '{}' does not exist",
                                             history_file.string()));
    }
    try {
      replay = fit::read_history(history_file, names);
    } catch (const std::runtime_error& e) {
      throw UsageError(std::string("--resume: ") + e.what());
    }
    const std::size_t points = fit::point_count(section.targets);
    for (const auto& row : replay) {
      if (!row.failed && row.residuals.size() != points) {
        throw UsageError(fmt::format(
            "--resume: {}: the history has {} residuals per evaluation, the case's targets {}: "
            "it belongs to another fit (remove it or use another -o)",
            history_file.string(), row.residuals.size(), points));
      }
    }
  }
  // The model is checked once before any output exists (a setup error is bad input).
  std::vector<double> start_values;
  for (const auto& p : section.parameters) start_values.push_back(p.start);
  std::optional<pipeline::FePipeline> fe_pipeline;
  std::optional<pipeline::FeFitModel> fe_model;
  if (c) {
    io::DiscreteCase check = *c;
    try {
      pipeline::set_model_parameters(check, names, start_values);
    } catch (const std::invalid_argument& e) {
      throw UsageError(case_path_ +
                       ": fit.parameters: the start values give an invalid model: " + e.what());
    }
  } else {
    // The stages are kept on disk (the run's stage cache), so a fit resumed or repeated reads
    // what an earlier one computed.
    auto store = std::make_shared<io::StageCache>(
        cache_dir_.empty() ? fs::path(output_dir_) / ".cache" : fs::path(cache_dir_), true);
    fe_pipeline.emplace(*fe, *fe, store);
    fe_model.emplace(*fe_pipeline, names, section.targets, section.friction_in_dynamics_only);
    try {
      fe_model->set(start_values);
    } catch (const std::exception& e) {
      throw UsageError(case_path_ + ": fit.parameters: the start values give an invalid case: " + e.what());
    }
  }
  std::optional<OutputDirectory> output;
  if (root) output.emplace(dir);  // created and locked for the whole fit by rank 0 alone

  const std::size_t m = fit::point_count(section.targets);
  const bool progress = stderr_is_terminal() && !quiet_;
  std::optional<ProgressHeartbeat> heartbeat;  // a line every 10 s when stderr is no terminal
  if (!quiet_ && root) heartbeat.emplace("jointhb fit", progress_seconds);
  std::optional<fit::HistoryWriter> history;
  if (root) history.emplace(history_file, names, m, resume_);
  const int workers = parallel.jobs + communicator_.size() - 1;
  if (root && !quiet_) note_serial_search(section.options, parallel.jobs, workers, names.size());
  double best = std::numeric_limits<double>::infinity();
  int shown = 0;
  const bool global = section.options.algorithm == "direct" || section.options.algorithm == "mlsl";
  const auto search_of = [global](int index) {
    if (index < 0) return std::string("jacobian");
    if (global) return index == 0 ? std::string("global phase") : fmt::format("local search {}", index);
    return fmt::format("start {}", index);
  };
  const auto sink = [&](const fit::HistoryRow& row) {
    history->write(row);
    if (!row.failed) best = std::min(best, row.objective);
    if (progress) {
      std::cerr << fmt::format(
                       "\rjointhb fit: evaluation {} ({})  S = {:.6g}  best {:.6g}  {:.1f} s   ",
                       row.eval, search_of(row.start),
                       row.objective, best, seconds_since(start))
                << std::flush;
      ++shown;
    }
    if (!row.failed && std::isfinite(row.objective))
      progress_activity("evaluation {}  S = {:.6g}  best {:.6g}", row.eval, row.objective, best);
  };
  for (const auto& row : replay) {
    if (!row.failed) best = std::min(best, row.objective);
  }
  const fit::Model model = c ? pipeline::discrete_model(*c, names, section.targets) : fe_model->model();
  fit::FitResult r;
  try {
    r = fit::fit(model, section.parameters, section.options, sink, replay, parallel);
  } catch (const std::exception& e) {
    if (communicator_.size() > 1) {  // the other ranks would wait for rank 0 forever
      std::cerr << "jointhb fit: " << e.what() << '\n';
      communicator_.abort(exit_failure);
    }
    throw;
  }
  if (!root) return exit_ok;  // rank 0 writes everything
  if (progress && shown) std::cerr << '\r' << std::string(78, ' ') << '\r';

  // Outputs: the predictions at the start and at the optimum.
  const auto prediction_at = [&](const std::vector<double>& values) {
    if (fe_model) return fe_model->predict(values);
    io::DiscreteCase k = *c;
    fit::ModelPrediction pred;
    try {
      pipeline::set_model_parameters(k, names, values);
      pred = pipeline::predict(k, section.targets);
    } catch (const std::exception& e) {
      pred.ok = false;
      pred.message = e.what();
    }
    return pred;
  };
  const fit::ModelPrediction at_start = prediction_at(start_values);
  const fit::ResidualEvaluation start_res = fit::residuals(section.targets, at_start);
  fit::ModelPrediction at_best;
  fit::ResidualEvaluation best_res;
  best_res.ok = false;  // no optimum: no fitted values
  if (r.ok) {
    at_best = prediction_at(r.best);
    best_res = fit::residuals(section.targets, at_best);
  }

  {
    io::CsvWriter curves(dir / "fit_curves.csv",
                         {"target", "kind", "mode_or_level", "abscissa", "quantity", "measured",
                          "fitted", "start", "residual", "weight", "scale"});
    std::size_t i = 0;
    for (std::size_t t = 0; t < section.targets.size(); ++t) {
      const auto& target = section.targets[t];
      for (const auto& p : target.points) {
        const double fitted =
            best_res.ok && i < best_res.predicted.size() ? best_res.predicted[i] : 0.0;
        const double residual =
            best_res.ok && i < best_res.residuals.size() ? best_res.residuals[i] : 0.0;
        const double at0 =
            start_res.ok && i < start_res.predicted.size() ? start_res.predicted[i] : 0.0;
        curves.write_row(
            {static_cast<double>(t), kind_code(target.kind),
             static_cast<double>(target.kind == fit::TargetKind::frf ? target.level : target.mode),
             p.abscissa, quantity_code(p.quantity), p.measured, fitted, at0, residual, p.weight,
             p.scale()});
        ++i;
      }
    }
    io::CsvWriter model_curves(dir / "fit_model_curves.csv",
                               {"at", "target", "quantity", "abscissa", "value"});
    write_model_curves(model_curves, 0.0, section.targets, at_start);
    if (r.ok) write_model_curves(model_curves, 1.0, section.targets, at_best);
  }

  Json parameters = Json::array();
  for (std::size_t i = 0; i < section.parameters.size(); ++i) {
    const auto& p = section.parameters[i];
    Json j = {{"name", p.name},
              {"value", r.ok ? Json(r.best[i]) : Json(nullptr)},
              {"standard_error", nullptr},
              {"relative_standard_error", nullptr},
              {"lower", p.lower},
              {"upper", p.upper},
              {"start", p.start},
              {"log_scale", p.log_scale}};
    if (r.has_jacobian) {
      j["standard_error"] = number_or_null(r.standard_errors[static_cast<Eigen::Index>(i)]);
      j["relative_standard_error"] =
          number_or_null(r.standard_errors[static_cast<Eigen::Index>(i)] / std::abs(r.best[i]));
    }
    parameters.push_back(j);
  }
  Json per_target = Json::array();
  {
    std::size_t i = 0;
    for (std::size_t t = 0; t < section.targets.size(); ++t) {
      const auto& target = section.targets[t];
      double ssr = 0.0;
      for (std::size_t k = 0; k < target.points.size(); ++k, ++i) {
        if (best_res.ok && i < best_res.residuals.size())
          ssr += best_res.residuals[i] * best_res.residuals[i];
      }
      per_target.push_back(
          {{"target", target.name},
           {"type", fit::to_string(target.kind)},
           {"file", target.file},
           {"points", target.points.size()},
           {"objective", best_res.ok ? Json(ssr) : Json(nullptr)},
           {"rms_residual", best_res.ok
                                ? Json(std::sqrt(ssr / static_cast<double>(target.points.size())))
                                : Json(nullptr)}});
    }
  }
  const auto matrix = [](const Eigen::MatrixXd& a) {
    Json rows = Json::array();
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      Json row = Json::array();
      for (Eigen::Index k = 0; k < a.cols(); ++k) row.push_back(number_or_null(a(i, k)));
      rows.push_back(row);
    }
    return rows;
  };
  Json unresolved = Json::array();
  for (const auto& d : r.unresolved) {
    unresolved.push_back({{"combination", d.description},
                          {"components", d.components},
                          {"singular_value", d.singular_value},
                          {"standard_error_unit_box", number_or_null(d.standard_error)}});
  }
  Json starts = Json::array();
  for (const auto& s : r.starts) {
    starts.push_back({{"start", s.start},
                      {"from", s.from},
                      {"objective", number_or_null(s.objective)},
                      {"evaluations", s.evaluations},
                      {"stop_reason", s.stop_reason}});
  }
  const auto& o = section.options;
  Json summary = {
      {"jointhb_version", JOINTHB_VERSION},
      {"status", r.ok ? "ok" : "failed"},  // a fit was found (exit code 0); how the search ended:
      {"termination", nullptr},              // put_status below (FitResult::status())
      {"ok", nullptr},
      {"message", nullptr},
      {"case", source},
      {"parameters", parameters},
      {"objective", r.ok ? Json(r.objective) : Json(nullptr)},
      {"residual_points", m},
      {"degrees_of_freedom", r.degrees_of_freedom},
      {"s2", r.has_jacobian ? Json(r.s2) : Json(nullptr)},
      {"targets", per_target},
      {"correlation", r.has_jacobian ? matrix(r.correlation) : Json(nullptr)},
      {"singular_values", r.has_jacobian ? Json(std::vector<double>(
                                               r.singular_values.data(),
                                               r.singular_values.data() + r.singular_values.size()))
                                         : Json(nullptr)},
      {"right_singular_vectors", r.has_jacobian ? matrix(r.right_singular_vectors) : Json(nullptr)},
      {"unidentifiable", unresolved},
      {"warnings", r.warnings},
      {"evaluations", r.evaluations},
      {"model_evaluations", r.model_evaluations},
      {"replayed_evaluations", r.replayed},
      {"failed_evaluations", r.failed_evaluations},
      {"stop_reason", r.stop_reason},
      {"starts", starts},
      {"options",
       {{"algorithm", o.algorithm},
        {"local_algorithm", o.local_algorithm},
        {"xtol", o.xtol},
        {"ftol_rel", o.ftol_rel},
        {"max_evaluations", o.max_evaluations},
        {"starts", o.starts},
        {"seed", o.seed},
        {"penalty", o.penalty},
        {"initial_step", o.initial_step},
        {"jacobian_step", o.jacobian_step}}},
      {"parallel", {{"jobs", parallel.jobs}, {"ranks", communicator_.size()}}},
      {"seconds", {{"fit", r.seconds}, {"total", seconds_since(start)}}}};
  put_status(summary, r.status());
  if (fe_model) {
    summary["options"]["friction_in_dynamics_only"] = section.friction_in_dynamics_only;
    const pipeline::StageCounters& k = fe_pipeline->counters();
    // solved: computed; from_cache: read from the stage cache; reused: kept from an earlier
    // evaluation (its inputs unchanged).
    summary["stages"] = {
        {"preload", {{"solved", k.preload_solved}, {"from_cache", k.preload_read}, {"reused", k.preload_reused}}},
        {"modes", {{"solved", k.modes_solved}, {"from_cache", k.modes_read}, {"reused", k.modes_reused}}},
        {"condensation",
         {{"solved", k.condensed}, {"from_cache", k.condensation_read}, {"reused", k.condensation_reused}}},
        {"damping_curves", k.curves},
        {"values_put_on_the_curve", fe_model->corrected()}};
  }
  write_summary(dir / "fit.json", summary);
  if (!quiet_) {
    for (const auto& w : r.warnings) std::cerr << "jointhb fit: warning: " << w << '\n';
    for (std::size_t i = 0; i < names.size() && r.ok; ++i) {
      const double se = r.has_jacobian ? r.standard_errors[static_cast<Eigen::Index>(i)]
                                       : std::numeric_limits<double>::quiet_NaN();
      std::cout << fmt::format("{:<28} {:>14.7g} +- {}\n", names[i], r.best[i],
                               std::isfinite(se) ? fmt::format("{:.3g}", se) : "unidentifiable");
    }
  }
  plot_fit_results(dir, quiet_);
  std::cerr << fmt::format(
      "jointhb fit: {}: {} after {} evaluations ({} new, {} failed) in {:.3g} s; wrote {}\n",
      source, r.ok ? fmt::format("S = {:.6g}", r.objective) : "no successful evaluation",
      r.evaluations, r.model_evaluations, r.failed_evaluations, seconds_since(start), dir.string());
  return r.ok ? exit_ok : exit_failure;
}

}  // namespace jointhb::cli
