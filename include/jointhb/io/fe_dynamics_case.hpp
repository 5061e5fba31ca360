#pragma once
// The dynamic analyses of a finite-element case as read (docs/case-files.md, "Finite-element
// cases: dynamics"); the types are the pipeline's (pipeline/fe_analysis.hpp).
//
//   analysis:
//     damping: {ratio: 0.005}                 # or {ratio: ζ, frequency_hz: f} or
//                                             #    {rayleigh: {alpha: a [1/s], beta: b [s]}}
//     reduction: {cutoff_factor: 20, contact_patch: 0}   # or {cutoff_hz: 25000}
//     excitation: {point: [0.16, 0.015, 0.008], direction: [0, 0, 1]}
//     outputs: [{name: tip, point: [0.16, 0.015, 0.008], direction: [0, 0, 1]}]
//     nonlinear_modes: {mode: 1, log10_amplitude: [-9, -4], frequency_drop: 0.05, harmonics: 1}
//     frf: {frequency_hz: [900, 1000], force: [1, 5, 20], harmonics: 1}

#include "jointhb/pipeline/fe_analysis.hpp"

namespace jointhb::io {

using pipeline::FeDynamicsSpec;
using pipeline::FeFrfSpec;
using pipeline::FeNodeDirection;
using pipeline::FeNonlinearModesSpec;

}  // namespace jointhb::io
