#pragma once
// `jointhb run --plot`: runs src/python/jointhb_plot.py on the output directory with
// /usr/bin/python3 when it and matplotlib are present; otherwise says so on stderr. Never changes
// the run's exit code.

#include <filesystem>

namespace jointhb::cli {

void plot_results(const std::filesystem::path& dir);

/// `jointhb fit`: draws DIR/fit.png from fit_curves.csv and fit_model_curves.csv with
/// src/python/jointhb_fit_plot.py; a missing python3 or matplotlib is said on stderr (unless
/// `quiet`), never an error.
void plot_fit_results(const std::filesystem::path& dir, bool quiet);
/// `jointhb study`: draws DIR/study.png from study_curves.csv and study_statistics.csv with
/// src/python/jointhb_study_plot.py; as plot_fit_results, never an error.
void plot_study_results(const std::filesystem::path& dir, bool quiet);

}  // namespace jointhb::cli
