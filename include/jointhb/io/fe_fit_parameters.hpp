#pragma once
// Identification parameters of a finite-element case (docs/identification.md, "Finite-element
// cases"): the names a case offers and the case text with new values. A parameter is a number of
// the case file itself, so a fitted case is re-read as any case and every stage is keyed by its
// inputs (io/stage_cache.hpp): a value that enters only the dynamics (damping) recomputes no
// stage; a contact-law value recomputes the preload, modes and condensation it enters (jointhb's
// preload is frictional, so μ and n enter it too).
//
//   interfaces.<name>.pressure | decay | mu | n (gaul-mayer) | stiffness_ratio | kt
//       → model.interfaces[i].contact.<key>          (the keys the interface has)
//   bolts.<name>.preload                → model.bolts[j].preload
//   damping.ratio                       → analysis.damping.ratio            (when given)
//   damping.rayleigh.alpha | .beta      → analysis.damping.rayleigh.<key>  (when given)

#include <string>
#include <vector>

#include "jointhb/io/fe_case.hpp"

namespace jointhb::io {

/// The names `c` offers (interfaces and bolts by their names).
std::vector<std::string> fe_fit_parameter_names(const FeCase& c);

/// The case text (YAML) with the named values set (17 significant digits) and the top-level `fit`
/// section removed. Throws std::invalid_argument naming an unknown parameter or a case text that
/// lacks the node (the names come from fe_fit_parameter_names of the same text).
std::string set_fe_fit_parameters(const std::string& case_text, const std::vector<std::string>& names,
                                  const std::vector<double>& values);

}  // namespace jointhb::io
