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

#include "jointhb/pipeline/fe_pipeline.hpp"

namespace jointhb::cli {

/// Returns 0, or 1 when a curve stopped before its end or a stage failed (everything computed is
/// written). The pipeline's analysis must have dynamics and its model interfaces.
int run_fe_dynamics(pipeline::FePipeline& pipe, const std::filesystem::path& dir, nlohmann::ordered_json& summary);

}  // namespace jointhb::cli
