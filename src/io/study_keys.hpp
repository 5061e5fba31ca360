#pragma once
// The `study:` section of a case (private to the io layer): the design, the parameters (the names
// a fit section may use), what each sample reports, every problem reported at its key. Schema:
// docs/case-files.md, "study"; docs/studies.md.

#include "fit_keys.hpp"
#include "jointhb/study/study.hpp"
#include "yaml_support.hpp"

namespace jointhb::io {

/// `c` (the case's fit context) says which parameter names are valid and which modes, levels and
/// ranges the outputs may use; the defaults of the outputs come from it too.
study::StudySpec read_study_section(const yaml::Reader& reader, const YAML::Node& node, const std::string& path,
                                    const FitContext& c);

}  // namespace jointhb::io
