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
// cache (key: the modes key + cutoff, load and outputs), so a second run that changes
// only the continuation, harmonics or force levels skips preload, modes and condensation.

#include <filesystem>
#include <nlohmann/json.hpp>

#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/stage_cache.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/modal_interface.hpp"

namespace jointhb::cli {

/// The condensation settings of a case: cutoff (analysis.reduction, or cutoff_factor × the
/// highest frequency of interest) and Rayleigh damping (analysis.damping; a ratio becomes
/// stiffness-proportional at the followed mode), with where each came from (summary.json).
struct InterfaceSettings {
  reduction::ModalInterfaceOptions options;
  double followed_hz = 0.0;  ///< highest frequency of interest
  std::string cutoff_source, damping_source;
};

/// Frequencies [Hz] of the elastic modes among `modes` (|f| ≥ 1 Hz; rigid-body modes skipped).
std::vector<double> elastic_frequencies(const modal::ModalResult& modes);

/// Throws std::runtime_error when the modes stage found no elastic mode or fewer than followed.
InterfaceSettings resolve_interface_settings(const io::FeCase& c, const modal::ModalResult& modes);

/// Stage-cache key of the condensed model: the modes key + every option but the damping (the
/// condensation only copies it), and the load and output vectors.
std::string interface_model_key(const io::FeCase& c, const reduction::ModalInterfaceOptions& o,
                                const reduction::ModalLoad& load,
                                const std::vector<reduction::ModalOutputSpec>& outputs);

/// Returns 0, or 1 when a curve stopped before its end or a stage failed (everything computed is
/// written). `modes`: the modes of K_t (the modes stage), used for the default cutoff and damping.
int run_fe_dynamics(const io::FeCase& c, const preload::PreloadModel& model,
                    const preload::PreloadResult& preload, const modal::ModalResult& modes,
                    const std::filesystem::path& dir, io::StageCache& cache,
                    nlohmann::ordered_json& summary);

}  // namespace jointhb::cli
