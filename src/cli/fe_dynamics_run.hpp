#pragma once
// The dynamic stage of `jointhb run` on a finite-element case (analysis.nonlinear_modes and/or
// analysis.frf): the pipeline's condensed interface model (pipeline/fe_pipeline.hpp), then its
// damping curves by EPMC and nonlinear FRFs by harmonic balance. Writes
//   DIR/interface_model.csv   kept mode, frequency_hz, rigid (the condensed model's modes)
//   DIR/backbone.csv          mode, amplitude (q), output amplitude, frequency, damping ratio,
//                             W_D, ζ from W_D, slipping and open points, Newton iterations
//   DIR/frf.csv               level, force, Ω, frequency, |fundamental| and max of the output,
//                             W_D, slipping and open points, Newton iterations
// Rows are flushed as points are accepted; summary.json gets "interface_model", "backbones" and
// "frfs" with iterations, stop reasons and timings. The condensed model is kept in the stage
// cache (key: the modes key + cutoff, load and outputs), so a second run that changes
// only the continuation, harmonics or force levels skips preload, modes and condensation.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

#include "jointhb/pipeline/fe_pipeline.hpp"

namespace jointhb::cli {

/// Returns how each curve ended ("nonlinear mode 1", "frf level 0", ...; everything computed is
/// written), for the run's status (jointhb::worst). The pipeline's analysis must have dynamics and
/// its model interfaces.
std::vector<NamedStatus> run_fe_dynamics(pipeline::FePipeline& pipe, const std::filesystem::path& dir,
                                         nlohmann::ordered_json& summary);

}  // namespace jointhb::cli
