#pragma once
// The discrete-model adapter of the identification (fit/fitter.hpp): parameter names that address
// a DiscreteProblem (a discrete case), setting them consistently, and the model's prediction of the targets
// (fit/targets.hpp) by the existing analyses:
//   backbone  trace_backbone (EPMC, case analysis.nonlinear_modes settings) of the target's mode,
//             up to a tenth of a decade beyond the largest measured amplitude (not further than
//             the case's log10_amplitude end); then at each measured amplitude q the point on the
//             curve by Newton's method on the EPMC residual at fixed λ = log10 q, from the curve's
//             unknowns interpolated linearly in λ. The prediction is so the curve's own value, free
//             of the interpolation error of the adaptive continuation points (which would move with
//             the parameters and make S rough at the 1e-4 level).
//   frf       trace_frf (analysis.frf settings) at the target's level; then at each measured
//             frequency the harmonic balance solution by Newton's method at fixed Ω from the
//             interpolated coefficients (the largest-amplitude branch where folds give several);
//             the fundamental amplitude of analysis.frf.output_dof.
//   modal     linear modes of the stuck system (hb::linear_modes): f_k = ω_k / 2π and
//             ζ_k = φ_kᵀ C φ_k / (2 ω_k) (mass-normalised φ_k).
// A point whose Newton iteration does not converge in 20 iterations keeps the interpolated value.

#include <string>
#include <vector>

#include "jointhb/fit/fitter.hpp"
#include "jointhb/fit/targets.hpp"
#include "jointhb/pipeline/discrete_problem.hpp"

namespace jointhb::pipeline {

/// The names a discrete case offers: per contact i contacts[i].kt0, .mu, .normal_force (and .n
/// for gaul-mayer); damping.rayleigh.alpha/.beta (damping model rayleigh), damping.modal[k]
/// (modal), none for a damping matrix.
std::vector<std::string> discrete_parameter_names(const DiscreteProblem& c);

/// Sets the named parameters and rebuilds what depends on them (C for the damping parameters:
/// αM + βK, or the modal damping matrix of (K, M) as the case reader builds it), then checks the
/// system (DiscreteSystem::validate). Throws std::invalid_argument naming an unknown parameter
/// (with the valid names) or the violated constraint.
void set_model_parameters(DiscreteProblem& c, const std::vector<std::string>& names,
                          const std::vector<double>& values);

/// The case's curves for the targets (one PredictedCurve per target, with at_points).
fit::ModelPrediction predict(const DiscreteProblem& c, const std::vector<fit::Target>& targets);

/// fit()'s model for a discrete case: set_model_parameters on a copy of `base`, predict,
/// residuals. Failures (a continuation that stops short of a measured point, an invalid parameter
/// combination) return !ok.
fit::Model discrete_model(const DiscreteProblem& base, const std::vector<std::string>& names,
                     const std::vector<fit::Target>& targets);

}  // namespace jointhb::pipeline
