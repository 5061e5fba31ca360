#pragma once
// Isoparametric hexahedra: shape functions, their natural derivatives and Gauss rules.
//
// Natural coordinates ξ = (ξ, η, ζ) ∈ [−1, 1]³; node numbering as in mesh.hpp (Abaqus/VTK):
//   corners 0..7 at (∓1, ∓1, ∓1) — 0 (−1,−1,−1), 1 (1,−1,−1), 2 (1,1,−1), 3 (−1,1,−1), 4..7 the
//   same at ζ = +1; hex20 mid-edge nodes 8..11 (ζ = −1), 12..15 (ζ = +1) on edges 0-1, 1-2, 2-3,
//   3-0 (resp. 4-5 …), 16..19 on the vertical edges 0-4, 1-5, 2-6, 3-7 (ζ = 0).
//
// hex8 (trilinear, Zienkiewicz, Taylor & Zhu vol. 1, eq. 6.47):
//   N_a = ⅛ (1 + ξ ξ_a)(1 + η η_a)(1 + ζ ζ_a)
// hex20 (serendipity quadratic, ibid. §6.5 / Hughes, The Finite Element Method, §3.8):
//   corners     N_a = ⅛ (1 + ξ ξ_a)(1 + η η_a)(1 + ζ ζ_a)(ξ ξ_a + η η_a + ζ ζ_a − 2)
//   mid-edge    N_a = ¼ (1 − ξ²)(1 + η η_a)(1 + ζ ζ_a)   for ξ_a = 0, and cyclically.
// Derivative matrices are 3 × n: row k holds ∂N_a/∂ξ_k, column a the node.

#include <Eigen/Core>
#include <vector>

#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

/// Natural coordinates of local node `node` (0..19; 0..7 are the corners, shared by hex8).
[[nodiscard]] Eigen::Vector3d hex_node_natural_coordinates(int node);

[[nodiscard]] Eigen::Matrix<double, 8, 1> hex8_shape_functions(const Eigen::Vector3d& xi);
[[nodiscard]] Eigen::Matrix<double, 3, 8> hex8_shape_derivatives(const Eigen::Vector3d& xi);
[[nodiscard]] Eigen::Matrix<double, 20, 1> hex20_shape_functions(const Eigen::Vector3d& xi);
[[nodiscard]] Eigen::Matrix<double, 3, 20> hex20_shape_derivatives(const Eigen::Vector3d& xi);

/// The shape functions of `type` (node_count(type) of them) at ξ; every family (tetrahedra and
/// wedges in the natural coordinates of simplex_elements.hpp).
[[nodiscard]] Eigen::VectorXd shape_functions(ElementType type, const Eigen::Vector3d& xi);
/// The 3 × node_count(type) natural derivatives of `type` at ξ.
[[nodiscard]] Eigen::Matrix3Xd shape_derivatives(ElementType type, const Eigen::Vector3d& xi);

struct GaussPoint {
  Eigen::Vector3d xi;  ///< natural coordinates
  double weight = 0.0;
};

/// Tensor-product Gauss–Legendre rule with `points_per_direction` = 1, 2 or 3 points per
/// direction (exact for polynomials of degree 2n − 1 in each variable); the weights sum to 8.
/// Points ordered with ξ fastest, then η, then ζ. Throws std::invalid_argument for other n.
[[nodiscard]] const std::vector<GaussPoint>& hex_gauss_rule(int points_per_direction);

}  // namespace jointhb::fe
