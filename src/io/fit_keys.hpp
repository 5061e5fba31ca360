#pragma once
// The `fit:` section of a discrete case (private to the io layer): parameters, targets (CSV files
// relative to the case file) and search settings, every problem reported at its key or, for the
// CSV files, at FILE:LINE:COLUMN of the offending cell. Schema: docs/case-files.md, "fit".

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "jointhb/io/discrete_case.hpp"
#include "jointhb/io/fit_section.hpp"
#include "yaml_support.hpp"

namespace jointhb::io {

/// What the case read so far allows: the parameter names, the modes a target may name, the
/// excitation levels, and the ranges of the analyses (none: that target type is not available).
struct FitContext {
  std::vector<std::string> names;
  int modes = 0;                                    ///< modal and backbone targets: modes 1..modes
  std::vector<int> backbone_modes;                  ///< non-empty: the modes that have a damping curve
  int levels = 0;                                   ///< frf targets: levels 0..levels−1
  std::optional<std::pair<double, double>> backbone;  ///< log10 q range of analysis.nonlinear_modes
  std::optional<std::pair<double, double>> frf;       ///< frequency range of analysis.frf [Hz]
  bool finite_element = false;  ///< offers friction_in_dynamics_only
};

/// The context of a discrete case (its contacts, damping model and analyses).
FitContext fit_context(const DiscreteCase& c);

/// `c` says which parameter names and targets are valid. `case_dir` resolves relative target
/// files.
FitSection read_fit_section(const yaml::Reader& reader, const YAML::Node& node,
                            const std::string& path, const FitContext& c,
                            const std::filesystem::path& case_dir);

}  // namespace jointhb::io
