#pragma once
// Internal: the element kernel behind solid_element.hpp, writing into caller-owned storage so the
// assembly can compute many elements without allocating.

#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe::detail {

struct IsotropicConstants {
  double lambda = 0.0;   // Lamé λ [Pa]
  double mu = 0.0;       // shear modulus μ [Pa]
  double density = 0.0;  // ρ [kg/m³]
};

/// Writes the 3n × 3n stiffness and mass (column-major) of one element and returns its volume.
/// `coordinates` is 3 × n column-major (n = node_count(type)). Returns a negative value, leaving
/// the outputs unspecified, when det J ≤ 0 at an integration point or at the centre.
double element_kernel(ElementType type, const double* coordinates, const IsotropicConstants& c,
                      double* stiffness, double* mass);

}  // namespace jointhb::fe::detail
