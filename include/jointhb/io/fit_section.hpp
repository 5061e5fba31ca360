#pragma once
// The `fit:` section of a discrete case (docs/case-files.md, "fit"): the parameters to identify,
// the measured targets (read from CSV files next to the case) and the search settings.

#include <vector>

#include "jointhb/fit/fitter.hpp"
#include "jointhb/fit/parameters.hpp"
#include "jointhb/fit/targets.hpp"

namespace jointhb::io {

struct FitSection {
  std::vector<fit::FitParameter> parameters;  ///< names from fit::discrete_parameter_names
  std::vector<fit::Target> targets;
  fit::FitOptions options;
};

}  // namespace jointhb::io
