#pragma once
// The discrete-model case: a lumped system M ẍ + C ẋ + K x + f_nl(x) = f_ex(t) with friction
// contacts (hb/discrete_system.hpp), its excitation at one or more levels, and the analyses to run
// on it (so far the nonlinear frequency response, continuation/frf.hpp). Schema and error format:
// docs/case-files.md.
//
//   model:
//     type: discrete
//     mass: [[1.0, 0.0], [0.0, 1.0]]          # kg (a plain number for one DOF)
//     stiffness: [[2.0, -1.0], [-1.0, 2.0]]   # N/m
//     damping: {rayleigh: {alpha: 0.0, beta: 0.001}}   # or {matrix: ...} or {modal: [ζ...]}
//   contacts:
//     - {law: jenkins, dofs: [1], kt0: 1.0, mu: 0.3, normal_force: 1.0}
//   excitation:
//     - {dof: 0, amplitude: [0.05, 0.1, 0.2]}   # N, cos(Ωt): one FRF curve per level
//   analysis:
//     frf: {omega: [0.5, 2.0], harmonics: 7, output_dof: 1}

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/continuation/backbone.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/io/fit_section.hpp"
#include "jointhb/study/study.hpp"
#include "jointhb/pipeline/discrete_problem.hpp"

namespace jointhb::io {

/// A discrete case as read: the typed problem (pipeline/discrete_problem.hpp) plus what only the
/// reader knows.
struct DiscreteCase : pipeline::DiscreteProblem {
  std::string source;  ///< the case file it was read from
  /// fit: the parameters to identify from measured targets (`jointhb fit`, docs/identification.md)
  std::optional<FitSection> fit;
  /// study: a parameter study of this case (`jointhb study`, docs/studies.md)
  std::optional<study::StudySpec> study;
};

/// Reads a discrete-model case file. Throws InputError naming file, line, column, key path and
/// constraint for an unreadable file, YAML syntax errors, unknown or duplicate keys, wrong types,
/// non-finite or non-physical values and an inconsistent system (sizes, symmetry, definiteness,
/// DOF indices).
DiscreteCase read_discrete_case(const std::filesystem::path& file);

/// As read_discrete_case, from text; `file_name` is what the errors call the file.
DiscreteCase parse_discrete_case(const std::string& text, const std::string& file_name);

/// The default number of AFT samples per period for H harmonics: the smallest power of two
/// ≥ max(128, 16 H) (8 samples per period of the highest harmonic, at least 128).
int default_time_samples(int harmonics);

}  // namespace jointhb::io
