#pragma once
// `jointhb run` on a discrete-model case: the nonlinear FRF (analysis.frf), one curve per
// excitation level. Writes DIR/frf.csv (a row per accepted continuation point, flushed) and
// DIR/summary.json (inputs echoed, per-curve peak, steps, Newton iterations, timings per phase).

#include <filesystem>

#include "jointhb/io/discrete_case.hpp"
#include "run_support.hpp"

namespace jointhb::cli {

/// Returns the exit code: 0, or 1 when a curve stopped early (its points and the other curves are
/// kept). Throws UsageError when the case cannot be set up (before anything is written).
int run_discrete_case(const io::DiscreteCase& c, const std::filesystem::path& dir,
                      Clock::time_point start);

/// The set-up checks that need the model built (e.g. a forcing harmonic outside the basis):
/// throws UsageError naming the problem. run_discrete_case makes them first; `run --check` too.
void check_discrete_setup(const io::DiscreteCase& c);

}  // namespace jointhb::cli
