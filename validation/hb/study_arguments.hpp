#pragma once
// The command line every harmonic-balance validation study takes: PROGRAM [--ci] OUTPUT_PREFIX
// (validation/hb/CMakeLists.txt runs each with --ci under ctest).

#include <cstdio>
#include <string>

namespace study {

struct Arguments {
  bool ci = false;     // reduced, still scored sweep (ctest)
  std::string prefix;  // tables are written to prefix + "_<table>.csv"
  bool ok = false;     // false: usage printed, exit with 2
};

inline Arguments parse_arguments(int argc, char** argv) {
  Arguments a;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--ci") {
      a.ci = true;
    } else if (a.prefix.empty() && !arg.empty() && arg[0] != '-') {
      a.prefix = arg;
    } else {
      a.prefix.clear();
      break;
    }
  }
  a.ok = !a.prefix.empty();
  if (!a.ok) std::fprintf(stderr, "usage: %s [--ci] OUTPUT_PREFIX\n", argv[0]);
  return a;
}

}  // namespace study
