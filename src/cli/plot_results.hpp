#pragma once
// `jointhb run --plot`: runs src/python/jointhb_plot.py on the output directory with
// /usr/bin/python3 when it and matplotlib are present; otherwise says so on stderr. Never changes
// the run's exit code.

#include <filesystem>

namespace jointhb::cli {

void plot_results(const std::filesystem::path& dir);

}  // namespace jointhb::cli
