#pragma once
// `jointhb run` on a finite-element case: the preloaded static state (analysis.preload) and the
// modes about it (analysis.modes). Writes, as far as they are asked for and computed:
//   DIR/preload_steps.csv      load step, load factor, iterations, residual
//   DIR/contact_<iface>.csv    per interface point: position, pressure, gap, tractions, open
//   DIR/contact_<iface>.vtu    the interface facets with node-averaged pressure and gap (ParaView)
//   DIR/preload.vtu            the mesh with the preload displacement
//   DIR/modes.csv              mode, frequency_hz, residual
//   DIR/modes.vtu              the mesh with every mode shape as a point array
//   DIR/summary.json           inputs, per-stage results and timings
//
// Stage cache (io/stage_cache.hpp): the preload and the modes are stored in CACHE_DIR (default
// DIR/.cache; `--cache-dir`, off with `--no-cache`) as preload-<key>.bin and modes-<key>.bin, the
// keys being pipeline::fe_stage_keys (the typed model, plus analysis.preload, plus
// analysis.modes). A second run whose model and those settings are unchanged reads the stages
// instead of solving them ("preload: from cache (FILE)") and writes every output as the first
// did; summary.json says "cache": "hit" or "miss" per stage, with the original solve time in
// "seconds" and the read or write time in "cache_seconds". Only converged stages are stored. A
// damaged cache file is a warning and a miss; a cache that cannot be written is a warning.
#include <filesystem>

#include "jointhb/io/fe_case.hpp"
#include "jointhb/pipeline/fe_analysis.hpp"
#include "run_support.hpp"

namespace jointhb::cli {

struct FeRunOptions {
  std::filesystem::path cache_dir;  ///< empty: DIR/.cache
  bool use_cache = true;            ///< false: neither read nor write the stage cache
  pipeline::FeSolvers solvers;      ///< --linear-algebra (docs/distributed.md)
  int ranks = 1;                    ///< MPI ranks the solvers run on (for the summary)
};

/// Returns 0, or 1 when a stage failed (what it computed is kept and written).
int run_fe_case(const io::FeCase& c, const std::filesystem::path& dir, Clock::time_point start,
                const FeRunOptions& options = {});

}  // namespace jointhb::cli
