#include "run_command.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <variant>

#include "cli_support.hpp"
#include "fe_run.hpp"
#include "frf_run.hpp"
#include "jointhb/io/case_file.hpp"
#include "loop_sweep_run.hpp"
#include "plot_results.hpp"
#include "run_support.hpp"

namespace jointhb::cli {

namespace fs = std::filesystem;

RunCommand::RunCommand(CLI::App& parent) {
  app_ = parent.add_subcommand(
      "run",
      "Run the analyses a case file asks for, or the built-in default case when no file is\n"
      "given (docs/case-files.md):\n"
      "  analysis.loop_sweep  W_D amplitude sweep of one contact point -> DIR/wd_sweep.csv\n"
      "  analysis.frf         nonlinear FRF of a discrete model, one curve per excitation\n"
      "                       level -> DIR/frf.csv\n"
      "  analysis.nonlinear_modes  damping curves (EPMC) -> DIR/backbone.csv\n"
      "  analysis.preload     preloaded state of a finite-element case (model.type fe)\n"
      "                       -> DIR/preload_steps.csv, contact_<interface>.csv/.vtu\n"
      "  analysis.modes       modes about the preloaded state -> DIR/modes.csv, modes.vtu\n"
      "  analysis.nonlinear_modes / frf of an FE case: condensation to the interface, damping\n"
      "                       curves and FRFs by harmonic balance -> DIR/backbone.csv, frf.csv\n"
      "Without a case: the built-in default case, the bolted lap's preload, modes and first\n"
      "damping curve, with plots (docs/case-files.md).\n"
      "Rows are flushed as they are computed; DIR/summary.json echoes the inputs and gives\n"
      "per-curve results, iteration counts and timings.");
  app_->add_option("case", case_path_, "case file (YAML); omitted: the built-in default case")
      ->type_name("CASE.yaml");
  app_->add_option("-o,--output", output_dir_, "output directory, created if needed")
      ->type_name("DIR")
      ->capture_default_str();
  app_->add_flag(
      "--plot", plot_,
      "after the run, draw DIR/frf.png and DIR/backbone.png (always for the built-in default "
      "case; needs /usr/bin/python3 with matplotlib; a missing one is reported, not an error)");
  app_->add_option("--cache-dir", cache_dir_,
                   "stage cache of finite-element cases (preload, modes), reused when the model "
                   "and the stage's settings are unchanged; default DIR/.cache")
      ->type_name("CACHE_DIR");
  app_->add_flag("--no-cache", no_cache_,
                 "neither read nor write the stage cache: every stage is computed");
  app_->add_option("--linear-algebra", linear_algebra_,
                   "finite-element cases: 'serial' (CHOLMOD, ARPACK; default), 'petsc' (MUMPS "
                   "factorisations and SLEPc modes across MPI ranks: mpirun -np N jointhb run "
                   "--linear-algebra petsc ...), or 'petsc-gamg' / 'petsc-hypre' (no factor: "
                   "conjugate gradients with PETSc's GAMG or hypre's BoomerAMG, SLEPc modes with "
                   "the same inner solves; memory O(n); docs/distributed.md)")
      ->check(CLI::IsMember({"serial", "petsc", "petsc-gamg", "petsc-hypre"}));
  app_->add_option("--cg-tolerance", cg_tolerance_,
                   "petsc-gamg, petsc-hypre: relative residual ||b - Ax|| / ||b|| of every CG solve "
                   "(the modes' inner solves go two orders below their own tolerance)")
      ->check(CLI::Range(1e-15, 1e-2))
      ->capture_default_str();
  app_->add_flag("--check", check_only_,
                 "read and check the case file (and the meshes and target files it names), run "
                 "nothing and write nothing: exit 0 when it is valid, 2 with the error otherwise");
  app_->footer(
      "Exit codes: 0 ok, 1 a point or curve failed (rows so far kept, summary.json status\n"
      "\"failed\"), 2 invalid case file or options, or DIR in use by another run, 130/143\n"
      "interrupted by SIGINT/SIGTERM (summary.json status \"interrupted\"; \"running\" while the\n"
      "run goes on).\n"
      "Example: jointhb run cases/01-contact-loop/case.yaml -o out");
}

bool RunCommand::selected() const { return app_->parsed(); }

int RunCommand::run() const {
  const auto start = Clock::now();
  // The docs say `--cache-dir CACHE_DIR | --no-cache`: a cache directory that is then neither read
  // nor written is a mistake, not a choice to make for the user.
  if (no_cache_ && !cache_dir_.empty())
    require_option("--cache-dir", "cannot be combined with --no-cache (which neither reads nor writes a cache)");
  const double progress_seconds = progress_interval();
  // Before any thread exists: SIGINT/SIGTERM then mark summary.json "interrupted" (exit 130/143).
  install_interrupt_handler("jointhb run");
  // The case is read before anything is created, so bad input leaves no output behind.
  const bool built_in = case_path_.empty();
  const io::CaseFile c = built_in ? io::parse_case_file(io::default_case_text(), "built-in default case")
                                  : io::read_case_file(case_path_);
  if (app_->count("--cg-tolerance") > 0 && linear_algebra_ != "petsc-gamg" && linear_algebra_ != "petsc-hypre")
    require_option("--cg-tolerance", "applies to --linear-algebra petsc-gamg or petsc-hypre only (the other "
                                     "paths factor, with no tolerance to set)");
  if (wants_petsc() && !std::holds_alternative<io::FeCase>(c))
    require_option("--linear-algebra", "petsc applies to finite-element cases only, not to this case");
  if (check_only_) {
    if (const auto* discrete = std::get_if<io::DiscreteCase>(&c)) check_discrete_setup(*discrete);
    std::fprintf(stderr, "jointhb run: %s: valid\n", built_in ? "built-in default case" : case_path_.c_str());
    return exit_ok;
  }
  const OutputDirectory output(output_dir_);  // created and locked until the run returns
  const fs::path& dir = output.path();
  // A line every 10 s while the analysis runs when stderr is not a terminal; ended before the
  // plots, after the analysis' last line.
  std::optional<ProgressHeartbeat> heartbeat(std::in_place, "jointhb run", progress_seconds);
  try {
    if (const auto* sweep = std::get_if<io::LoopSweepCase>(&c)) {
      return run_loop_sweep(*sweep, dir, start);
    }
    if (const auto* fe_case = std::get_if<io::FeCase>(&c)) {
      FeRunOptions options;
      options.cache_dir = cache_dir_.empty() ? dir / ".cache" : fs::path(cache_dir_);
      options.use_cache = !no_cache_;
      if (wants_petsc()) {
        options.solvers.linear = linear_algebra_ == "petsc" ? fe::LinearSolver::mumps : fe::LinearSolver::cg;
        options.solvers.eigen = modal::ModalOptions::EigenSolver::slepc;
        options.solvers.iterative.preconditioner = linear_algebra_ == "petsc-hypre"
                                                       ? fe::IterativeSettings::Preconditioner::hypre
                                                       : fe::IterativeSettings::Preconditioner::gamg;
        options.solvers.iterative.relative_tolerance = cg_tolerance_;
        options.ranks = ranks_;
      }
      const int code = run_fe_case(*fe_case, dir, start, options);
      heartbeat.reset();
      if (plot_ || built_in) plot_results(dir);
      return code;
    }
    const int code = run_discrete_case(std::get<io::DiscreteCase>(c), dir, start);
    heartbeat.reset();
    if (plot_) plot_results(dir);
    return code;
  } catch (const std::exception& e) {
    mark_summary_failed(e.what());  // a summary.json left "running" says how the run ended
    throw;
  }
}

}  // namespace jointhb::cli
