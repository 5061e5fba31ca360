#pragma once
// The finite-element adapter of the identification (fit/fitter.hpp; docs/identification.md,
// "Finite-element cases"): a parameter vector → the case file with those values
// (io/fe_fit_parameters.hpp) → the stages of `jointhb run` through the stage cache, so a stage
// whose inputs did not change is read, not recomputed → the model's curves for the targets:
//   modal     the elastic modes of K_t about the preloaded state: f_k, and ζ_k = (a/ω_k + b ω_k)/2
//             of the case's Rayleigh damping (analysis.damping; 0 without it);
//   backbone  the damping curve (EPMC, analysis.nonlinear_modes settings) of the target's mode
//             from the case's start amplitude to a tenth of a decade beyond the largest measured
//             one (no frequency_drop stop), interpolated in log10 q at the measured amplitudes.
// With friction_in_dynamics_only, the interfaces' mu and n are left at the case's values for the
// stages (so their keys, and the cached stages, do not change) and set only in the contact laws
// of the condensed model: the preloaded state is that of the nominal friction (an approximation,
// measured in docs/identification.md §9).

#include <filesystem>
#include <string>
#include <vector>

#include "jointhb/fit/fitter.hpp"
#include "jointhb/fit/targets.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/stage_cache.hpp"

namespace jointhb::cli {

class FeFitModel {
 public:
  /// How often each stage was computed and how often read from the cache.
  struct Counters {
    int preload_solved = 0, preload_cached = 0, modes_solved = 0, modes_cached = 0;
    int condensed = 0, condensation_cached = 0, curves = 0;
    int corrected = 0;  ///< backbone values put on the curve at the measured amplitude by Newton
  };

  /// `case_text`/`file_name`: the case as read (its fit section is dropped from every variant).
  FeFitModel(std::string case_text, std::string file_name, std::vector<std::string> names,
             std::vector<fit::Target> targets, const std::filesystem::path& cache_dir,
             bool friction_in_dynamics_only = false);

  /// The case with `values` set. Throws io::InputError or std::invalid_argument when the case
  /// rejects a value.
  [[nodiscard]] io::FeCase case_at(const std::vector<double>& values) const;
  /// The curves for the targets at `values`; a stage or curve that fails gives !ok (no throw).
  [[nodiscard]] fit::ModelPrediction predict(const std::vector<double>& values) const;
  /// fit()'s model (this object must outlive it).
  [[nodiscard]] fit::Model model() const;
  [[nodiscard]] const Counters& counters() const { return counters_; }

 private:
  std::string text_, file_;
  std::vector<std::string> names_;
  std::vector<fit::Target> targets_;
  bool friction_in_dynamics_only_ = false;
  mutable io::StageCache cache_;
  mutable Counters counters_;
};

}  // namespace jointhb::cli
