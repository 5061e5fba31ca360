#pragma once
// The finite-element model of the identification (fit/fitter.hpp; docs/identification.md,
// "Finite-element cases"): a parameter vector → the pipeline's typed parameters
// (FePipeline::set_parameter) → its stages, of which only those whose key changed are recomputed
// (or read from the pipeline's store) → the model's curves for the targets:
//   modal     the elastic modes of K_t about the preloaded state: f_k, and ζ_k = (a/ω_k + b ω_k)/2
//             of the Rayleigh damping (analysis.damping; 0 without it);
//   backbone  the damping curve (EPMC, analysis.nonlinear_modes settings) of the target's mode
//             from the start amplitude to a tenth of a decade beyond the largest measured one (no
//             frequency_drop stop), its values at the measured amplitudes put on the curve by Newton;
//   frf       the analysis' FRF at the target's force level, the |fundamental| of its output.
// With friction_in_dynamics_only, μ and n are set with ParameterScope::dynamics: the preloaded
// state stays that of the nominal friction (an approximation, measured in docs/identification.md §9).

#include <string>
#include <vector>

#include "jointhb/fit/fitter.hpp"
#include "jointhb/fit/targets.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"

namespace jointhb::pipeline {

class FeFitModel {
 public:
  /// `pipeline` is driven by this object (it must outlive it); `names` are its parameter names.
  FeFitModel(FePipeline& pipeline, std::vector<std::string> names, std::vector<fit::Target> targets,
             bool friction_in_dynamics_only = false);

  /// Sets `values` on the pipeline. Throws std::invalid_argument naming a value the model rejects.
  void set(const std::vector<double>& values);
  /// The curves for the targets at `values`; a stage or curve that fails gives !ok (no throw).
  [[nodiscard]] fit::ModelPrediction predict(const std::vector<double>& values);
  /// fit()'s model (this object must outlive it).
  [[nodiscard]] fit::Model model();
  /// Backbone values put on the curve at the measured amplitudes by Newton (the others were
  /// interpolated between continuation points).
  [[nodiscard]] int corrected() const { return corrected_; }

 private:
  fit::PredictedCurve modal_curve();
  fit::PredictedCurve backbone_curve(const fit::Target& t);
  fit::PredictedCurve frf_curve(const fit::Target& t);

  FePipeline& pipeline_;
  std::vector<std::string> names_;
  std::vector<fit::Target> targets_;
  bool friction_in_dynamics_only_ = false;
  int corrected_ = 0;
};

}  // namespace jointhb::pipeline
