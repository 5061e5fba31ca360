#pragma once
// The dynamic stage of `jointhb run` on a finite-element case (analysis.nonlinear_modes and/or
// analysis.frf, io/fe_dynamics_case.hpp): condensation of the preloaded model to its interface
// in modal form (reduction/modal_interface.hpp), then damping curves by EPMC and nonlinear FRFs
// by harmonic balance (continuation/interface_response.hpp). Writes
//   DIR/interface_model.csv   kept mode, frequency_hz, rigid (the condensed model's modes)
//   DIR/backbone.csv          mode, amplitude (q), output amplitude, frequency, damping ratio,
//                             W_D, ζ from W_D, slipping and open points, Newton iterations
//   DIR/frf.csv               level, force, Ω, frequency, |fundamental| and max of the output,
//                             W_D, slipping and open points, Newton iterations
// Rows are flushed as points are accepted; summary.json gets "interface_model", "backbones" and
// "frfs" with iterations, stop reasons and timings. The condensed model is kept in the stage
// cache (key: the modes key + cutoff, damping, load and outputs), so a second run that changes
// only the continuation, harmonics or force levels skips preload, modes and condensation.

#include <filesystem>
#include <nlohmann/json.hpp>

#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/stage_cache.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/preload/preload_solver.hpp"

namespace jointhb::cli {

/// Returns 0, or 1 when a curve stopped before its end or a stage failed (everything computed is
/// written). `modes`: the modes of K_t (the modes stage), used for the default cutoff and damping.
int run_fe_dynamics(const io::FeCase& c, const preload::PreloadModel& model,
                    const preload::PreloadResult& preload, const modal::ModalResult& modes,
                    const std::filesystem::path& dir, io::StageCache& cache,
                    nlohmann::ordered_json& summary);

}  // namespace jointhb::cli
