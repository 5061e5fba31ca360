#pragma once
// The command line every harmonic-balance validation study takes:
//   PROGRAM [--ci] [--only TEXT] OUTPUT_PREFIX
// (validation/hb/CMakeLists.txt runs each with --ci under ctest). --only keeps the scenarios whose
// name contains TEXT, in the studies that name their scenarios (light_damping): one curve
// reproduced by itself.

#include <cstdio>
#include <string>

namespace validation_study {

struct Arguments {
  bool ci = false;     // reduced, still scored sweep (ctest)
  std::string prefix;  // tables are written to prefix + "_<table>.csv"
  std::string only;    // non-empty: run only the scenarios whose name contains it
  bool ok = false;     // false: usage printed, exit with 2

  /// True when --only leaves out the scenario called `name`.
  [[nodiscard]] bool skips(const std::string& name) const {
    return !only.empty() && name.find(only) == std::string::npos;
  }
};

inline Arguments parse_arguments(int argc, char** argv) {
  Arguments a;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--ci") {
      a.ci = true;
    } else if (arg == "--only" && i + 1 < argc) {
      a.only = argv[++i];
    } else if (a.prefix.empty() && !arg.empty() && arg[0] != '-') {
      a.prefix = arg;
    } else {
      a.prefix.clear();
      break;
    }
  }
  a.ok = !a.prefix.empty();
  if (!a.ok) std::fprintf(stderr, "usage: %s [--ci] [--only TEXT] OUTPUT_PREFIX\n", argv[0]);
  return a;
}

}  // namespace validation_study
