#pragma once
// Geometry of the hexahedra (private to the fe layer): shape-function derivatives on the
// reference cube [-1, 1]³ and the Jacobian J = ∂x/∂ξ = Σ_a x_a (∂N_a/∂ξ)ᵀ.
//   hex8:  N_a = ⅛ (1 + ξξ_a)(1 + ηη_a)(1 + ζζ_a)
//   hex20 (serendipity): corners N_a = ⅛ (1 + ξξ_a)(1 + ηη_a)(1 + ζζ_a)(ξξ_a + ηη_a + ζζ_a - 2),
//          mid-edge with ξ_a = 0: N_a = ¼ (1 - ξ²)(1 + ηη_a)(1 + ζζ_a) (and cyclically).
// Node numbering of mesh.hpp (Abaqus).

#include <Eigen/Core>
#include <array>

#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe::detail {

/// Reference coordinates (ξ, η, ζ) of local node a.
[[nodiscard]] Eigen::Vector3d reference_node(int a);

/// ∂N_a/∂(ξ, η, ζ), column a = node a; 3 × node_count(type).
[[nodiscard]] Eigen::Matrix3Xd shape_derivatives(ElementType type, const Eigen::Vector3d& xi);

/// J = ∂x/∂ξ of element `element` at reference point xi.
[[nodiscard]] Eigen::Matrix3d jacobian(const Mesh& mesh, int element, const Eigen::Vector3d& xi);

/// Gauss–Legendre points and weights on [-1, 1] with `n` = 2 or 3 points.
struct GaussRule {
  std::array<double, 3> points{};
  std::array<double, 3> weights{};
  int size = 0;
};
[[nodiscard]] GaussRule gauss_rule(int n);

}  // namespace jointhb::fe::detail
