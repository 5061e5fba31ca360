#pragma once
// A lumped (discrete) model and its analyses as typed values: the discrete counterpart of
// FeModel + FeAnalysis (pipeline/fe_model.hpp), without preload and reduction. The case reader
// (io/discrete_case.hpp) fills one; code and Python build one from matrices.
//
//   M ẍ + C ẋ + K x + f_nl(x) = f_ex(t), friction contacts (hb/discrete_system.hpp)

#include <optional>
#include <string>
#include <vector>

#include "jointhb/continuation/backbone.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/hb/discrete_system.hpp"

namespace jointhb::pipeline {

struct DiscreteProblem {
  hb::DiscreteSystem system;             ///< M, C, K and contacts; validate() is empty
  std::vector<hb::Excitation> levels;    ///< one per excitation level (none without excitation)
  std::vector<double> level_amplitudes;  ///< label of each level: its largest |amplitude| [N]
  std::optional<continuation::FrfOptions> frf;  ///< the nonlinear FRF, when asked for
  /// The EPMC damping curve of one mode, when asked for.
  std::optional<continuation::BackboneOptions> nonlinear_modes;
  /// The modes whose damping curves are asked for; nonlinear_modes->mode.mode is the first.
  std::vector<int> modes;
  // How C was given (parameters and their rebuild of C depend on it):
  std::string damping_model = "none";        ///< "none", "rayleigh", "matrix" or "modal"
  double rayleigh_alpha = 0.0;               ///< α of C = αM + βK [1/s] (damping_model rayleigh)
  double rayleigh_beta = 0.0;                ///< β of C = αM + βK [s] (damping_model rayleigh)
  std::vector<double> modal_damping_ratios;  ///< ζ_i of the lowest modes (damping_model modal)
};

}  // namespace jointhb::pipeline
