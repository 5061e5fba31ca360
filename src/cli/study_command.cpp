#include "study_command.hpp"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <filesystem>
#include <iostream>
#include <thread>

#include "cli_support.hpp"
#include "jointhb/io/study_case.hpp"
#include "jointhb/study/distributed.hpp"
#include "plot_results.hpp"
#include "run_support.hpp"

namespace jointhb::cli {
namespace {

namespace fs = std::filesystem;

}  // namespace

StudyCommand::StudyCommand(CLI::App& parent, const study::Communicator& communicator) : communicator_(communicator) {
  app_ = parent.add_subcommand(
      "study",
      "Evaluate the case at the samples of its study section (docs/studies.md): a list, grid,\n"
      "Latin hypercube or Sobol design of any parameters a fit can set; per sample the damping\n"
      "curves' frequency and damping at the study's amplitudes and the FRFs' values and peaks.\n"
      "Runs on local worker processes (-j), or under mpirun -np N on N ranks. Writes\n"
      "  DIR/study.csv             one row per sample: parameters, outputs, termination\n"
      "  DIR/study_statistics.csv  per output: count, mean, std, min, max, quantiles\n"
      "  DIR/study_curves.csv      every sample's curves\n"
      "  DIR/study.json            design, counts, failed samples and why, statistics, times\n"
      "  DIR/samples/              one file per finished sample (what --resume reuses)\n"
      "  DIR/study.png             curves of all samples with mean and quantile band");
  app_->add_option("case", case_path_, "case file (YAML) with a study section")->type_name("CASE.yaml")->required();
  app_->add_option("-o,--output", output_dir_, "output directory, created if needed")->type_name("DIR")->capture_default_str();
  app_->add_option("-j,--jobs", jobs_,
                   "local workers, each evaluating one sample at a time with one OpenMP thread (default: "
                   "the cores; under MPI 1 per rank); the results do not depend on it")
      ->type_name("N");
  app_->add_flag("--resume", resume_, "reuse the samples DIR/samples/ holds from an earlier run of the same case");
  app_->add_option("--cache-dir", cache_dir_,
                   "finite-element cases: the stage cache shared by all samples (default DIR/.cache)")
      ->type_name("DIR");
  app_->add_flag("--quiet", quiet_, "no progress lines or warnings (errors only)");
  app_->footer(
      "Exit codes: 0 every sample converged, 1 some failed (the table says which and study.json\n"
      "why), 2 invalid case file or options, 130 interrupted (Ctrl-C: the running samples finish,\n"
      "the files are written; --resume continues).\n"
      "Example: jointhb study cases/16-study-lap/case.yaml -o out\n"
      "         mpirun -np 2 jointhb study cases/16-study-lap/case.yaml -o out");
}

bool StudyCommand::selected() const { return app_->parsed(); }

int StudyCommand::run() const {
  const bool root = communicator_.rank() == 0;
  io::StudyCase study_case;
  try {
    study_case = io::read_study_case(case_path_);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  const study::StudySpec& spec = study_case.spec;
  study::RunOptions options;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  options.jobs = jobs_.empty() ? (communicator_.size() > 1 ? 1 : static_cast<int>(cores))
                               : integer_option("--jobs", jobs_, 1, 1024);
  const fs::path dir(output_dir_);
  std::optional<OutputDirectory> output;
  if (root) output.emplace(dir);  // created and locked by rank 0 only (the others write nothing)
  options.resume = resume_;
  options.communicator = &communicator_;
  // Ctrl-C: no new samples; the running ones finish and everything is written (a second one quits).
  static std::atomic<bool> interrupted{false};
  install_stop_request("jointhb study", interrupted, "finishing the running samples, then writing the results");
  options.interrupt = &interrupted;
  const auto start = Clock::now();
  const std::size_t total = spec.sampling.count();
  const bool terminal = stderr_is_terminal() && !quiet_;
  std::optional<ProgressHeartbeat> heartbeat;
  if (!quiet_ && root) heartbeat.emplace("jointhb study", progress_interval());
  std::size_t failed = 0;
  options.on_sample = [&](const study::SampleResult& s, std::size_t done, std::size_t n) {
    if (!s.status.ok()) ++failed;
    if (quiet_) return true;
    const std::string line = fmt::format("sample {} {} ({}{:.2f} s); {} of {} done, {} failed, {:.1f} s", s.sample,
                                         s.status.ok() ? "ok" : "failed", s.reused ? "reused, " : "", s.seconds, done, n,
                                         failed, seconds_since(start));
    if (terminal) std::cerr << "\rjointhb study: " << line << "   " << std::flush;
    progress_activity("{}", line);
    return true;
  };
  study::StudyResult result;
  try {
    result = io::run_study_case(study_case, dir, options, cache_dir_);
  } catch (const std::invalid_argument& e) {
    if (communicator_.size() > 1) {
      std::cerr << "jointhb study: " << e.what() << '\n';
      communicator_.abort(exit_bad_input);
    }
    throw UsageError(e.what());
  } catch (const std::exception& e) {
    if (communicator_.size() > 1) {
      std::cerr << "jointhb study: " << e.what() << '\n';
      communicator_.abort(exit_failure);
    }
    throw;
  }
  if (terminal) std::cerr << '\n';
  if (!root) return exit_ok;
  plot_study_results(dir, quiet_);
  if (!quiet_) {
    for (const auto& w : result.warnings) std::cerr << "jointhb study: warning: " << w << '\n';
    std::cerr << fmt::format(
        "jointhb study: {} samples ({} computed, {} reused, {} failed) on {} rank{} ({} local worker{}) in {:.1f} s -> {}\n",
        total, result.computed, result.reused, result.failed, result.ranks, result.ranks == 1 ? "" : "s", result.jobs,
        result.jobs == 1 ? "" : "s", result.seconds, dir.string());
    for (std::size_t i = 0, shown = 0; i < result.samples.size() && shown < 5; ++i) {
      if (result.done[i] && !result.samples[i].status.ok()) {
        std::cerr << fmt::format("jointhb study: sample {} failed: {}\n", i, result.samples[i].status.message);
        ++shown;
      }
    }
  }
  if (interrupted && result.not_run > 0) {
    std::cerr << fmt::format("jointhb study: interrupted with {} of {} samples not run; the same command with --resume "
                             "computes only those\n",
                             result.not_run, total);
    return exit_interrupted;
  }
  return result.status().ok() ? exit_ok : exit_failure;
}

}  // namespace jointhb::cli
