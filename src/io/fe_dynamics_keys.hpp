#pragma once
// Reads the dynamic analyses of a finite-element case (analysis.damping, reduction, excitation,
// outputs, nonlinear_modes, frf) into io::FeDynamicsSpec (private to the io layer; schema:
// docs/case-files.md, "Finite-element cases: dynamics").

#include "jointhb/fe/mesh.hpp"
#include "jointhb/io/fe_dynamics_case.hpp"
#include "yaml_support.hpp"

namespace jointhb::io {

/// `analysis` holds the analysis mapping's entries; the result is meaningful when it has
/// nonlinear_modes or frf (the settings alone are an error naming the key).
FeDynamicsSpec read_fe_dynamics(const yaml::Reader& reader, const yaml::Fields& analysis,
                                const fe::Mesh& mesh);

}  // namespace jointhb::io
