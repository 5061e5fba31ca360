#pragma once
// Any case file `jointhb run` accepts: a file with a top-level `model:` is a discrete-model case
// (io/discrete_case.hpp) or, with model.type fe, a finite-element case (io/fe_case.hpp), any other file a loop-sweep case (io/loop_sweep_case.hpp). Schema and
// error format: docs/case-files.md.

#include <filesystem>
#include <string>
#include <variant>

#include "jointhb/io/discrete_case.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/loop_sweep_case.hpp"

namespace jointhb::io {

using CaseFile = std::variant<LoopSweepCase, DiscreteCase, FeCase>;

/// Reads a case file of either kind. Throws InputError as the two readers do; a file without
/// `model:` that asks for what only a model can have (analysis.frf, contacts, excitation) is
/// reported as a missing `model`.
CaseFile read_case_file(const std::filesystem::path& file);

/// As read_case_file, from text; `file_name` is what the errors call the file.
CaseFile parse_case_file(const std::string& text, const std::string& file_name);

/// The built-in default case of `jointhb run` without a case file (docs/case-files.md, "The
/// built-in default case"): the bolted lap of cases/05-bolted-lap on a coarse mesh (20 × 6 × 1
/// C3D8I per plate, 192 contact points): preload, modes and the damping curve of the first
/// elastic mode from the linear limit to a 3 % frequency drop, at H = 1.
const std::string& default_case_text();

}  // namespace jointhb::io
