#pragma once
// The `fit:` section of a discrete case (private to the io layer): parameters, targets (CSV files
// relative to the case file) and search settings, every problem reported at its key or, for the
// CSV files, at FILE:LINE:COLUMN of the offending cell. Schema: docs/case-files.md, "fit".

#include <filesystem>

#include "jointhb/io/discrete_case.hpp"
#include "jointhb/io/fit_section.hpp"
#include "yaml_support.hpp"

namespace jointhb::io {

/// `c` is the case read so far (its contacts, damping model and analyses decide which parameter
/// names and targets are valid). `case_dir` resolves relative target files.
FitSection read_fit_section(const yaml::Reader& reader, const YAML::Node& node,
                            const std::string& path, const DiscreteCase& c,
                            const std::filesystem::path& case_dir);

}  // namespace jointhb::io
