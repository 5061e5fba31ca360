#pragma once
// The `fit:` section of a discrete case (docs/case-files.md, "fit"): the parameters to identify,
// the measured targets (read from CSV files next to the case) and the search settings.

#include <vector>

#include "jointhb/fit/fitter.hpp"
#include "jointhb/fit/parameters.hpp"
#include "jointhb/fit/targets.hpp"

namespace jointhb::io {

struct FitSection {
  std::vector<fit::FitParameter> parameters;  ///< names the case offers (discrete or FE)
  std::vector<fit::Target> targets;
  fit::FitOptions options;
  /// Finite-element cases (fit.friction_in_dynamics_only): the interfaces' mu and n enter only
  /// the dynamics; preload, modes and condensation keep the case's values and are not redone
  /// (docs/identification.md §9).
  bool friction_in_dynamics_only = false;
};

}  // namespace jointhb::io
