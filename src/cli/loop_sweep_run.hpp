#pragma once
// `jointhb run` on a loop-sweep case (analysis.loop_sweep): the W_D amplitude sweep of one contact
// point against the closed forms. Writes DIR/wd_sweep.csv (a row per amplitude, flushed) and
// DIR/summary.json.

#include <filesystem>

#include "jointhb/io/loop_sweep_case.hpp"
#include "run_support.hpp"

namespace jointhb::cli {

/// Returns the exit code (0, or 1 when a point failed: rows so far kept).
int run_loop_sweep(const io::LoopSweepCase& c, const std::filesystem::path& dir,
                   Clock::time_point start);

}  // namespace jointhb::cli
