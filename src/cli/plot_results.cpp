#include "plot_results.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <iostream>
#include <string>

namespace jointhb::cli {
namespace {

namespace fs = std::filesystem;

// The script next to the sources (build tree) or installed under share/jointhb.
fs::path plot_script(const std::string& name = "jointhb_plot.py") {
  for (const fs::path& candidate : {fs::path(JOINTHB_SOURCE_DIR) / "src/python" / name,
                                    fs::path(JOINTHB_DATA_DIR) / name}) {
    std::error_code ec;
    if (fs::exists(candidate, ec)) return candidate;
  }
  return {};
}

// Single quotes for /bin/sh, with embedded quotes escaped.
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

}  // namespace

void plot_results(const fs::path& dir) {
  const fs::path python = "/usr/bin/python3";
  const fs::path script = plot_script();
  std::error_code ec;
  if (!fs::exists(python, ec)) {
    std::cerr << "jointhb run: --plot: /usr/bin/python3 not found (install python3 and "
                 "python3-matplotlib); no plots drawn\n";
    return;
  }
  if (script.empty()) {
    std::cerr << "jointhb run: --plot: jointhb_plot.py not found; no plots drawn\n";
    return;
  }
  const std::string check = quoted(python.string()) + " -c 'import matplotlib' 2>/dev/null";
  if (std::system(check.c_str()) != 0) {
    std::cerr << "jointhb run: --plot: python3-matplotlib is not installed; no plots drawn\n";
    return;
  }
  const std::string command = fmt::format("{} {} {} >/dev/null", quoted(python.string()),
                                          quoted(script.string()), quoted(dir.string()));
  if (std::system(command.c_str()) != 0) {
    std::cerr << "jointhb run: --plot: the plot script failed; the results are unaffected\n";
    return;
  }
  std::cerr << fmt::format("jointhb run: plots in {}\n", dir.string());
}

// Runs `script` on `dir` with /usr/bin/python3 and matplotlib; a missing piece or a failed script
// is one line on stderr (unless quiet) naming what was not drawn.
void run_plot_script(const std::string& command_name, const std::string& script_name, const std::string& png,
                     const fs::path& dir, bool quiet) {
  const fs::path python = "/usr/bin/python3";
  const fs::path script = plot_script(script_name);
  std::error_code ec;
  const auto note = [&](const std::string& what) {
    if (!quiet) std::cerr << command_name << ": " << what << "; " << png << " not drawn\n";
  };
  if (!fs::exists(python, ec)) return note("/usr/bin/python3 not found");
  if (script.empty()) return note(script_name + " not found");
  const std::string check = quoted(python.string()) + " -c 'import matplotlib' 2>/dev/null";
  if (std::system(check.c_str()) != 0) return note("python3-matplotlib is not installed");
  const std::string command = fmt::format("{} {} {} >/dev/null 2>&1", quoted(python.string()),
                                          quoted(script.string()), quoted(dir.string()));
  if (std::system(command.c_str()) != 0) return note("the plot script failed");
}

void plot_fit_results(const fs::path& dir, bool quiet) {
  run_plot_script("jointhb fit", "jointhb_fit_plot.py", "fit.png", dir, quiet);
}

void plot_study_results(const fs::path& dir, bool quiet) {
  run_plot_script("jointhb study", "jointhb_study_plot.py", "study.png", dir, quiet);
}

}  // namespace jointhb::cli
