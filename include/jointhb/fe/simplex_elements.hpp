#pragma once
// Isoparametric tetrahedra and wedges: shape functions, natural derivatives and integration rules.
// Node numbering as in mesh.hpp (Abaqus; VTK for tetrahedra).
//
// Tetrahedra: natural coordinates ξ = (ξ, η, ζ) with ξ, η, ζ ≥ 0, ξ + η + ζ ≤ 1 (volume 1/6);
// volume coordinates L0 = 1 − ξ − η − ζ, L1 = ξ, L2 = η, L3 = ζ; corner a at L_a = 1
// (Zienkiewicz, Taylor & Zhu, The Finite Element Method: Its Basis and Fundamentals, 7th ed.,
// §6.6 and eq. 6.56–6.57):
//   tet4   N_a = L_a
//   tet10  corners N_a = L_a (2 L_a − 1),   mid-edge on edge (a b): N = 4 L_a L_b.
//
// Wedges: (ξ, η) area coordinates of the triangle (ξ, η ≥ 0, ξ + η ≤ 1) and ζ ∈ [−1, 1] along the
// prism axis (volume 1); L0 = 1 − ξ − η, L1 = ξ, L2 = η; bottom corners a = 0..2 at ζ = −1, top
// corners a + 3 at ζ = +1 (ibid. §6.7; Abaqus Theory Manual §3.2.4 for C3D15):
//   wedge6   N_a = ½ L_a (1 − ζ),   N_{a+3} = ½ L_a (1 + ζ)
//   wedge15  bottom corner   N_a     = ½ L_a [(2 L_a − 1)(1 − ζ) − (1 − ζ²)]
//            top corner      N_{a+3} = ½ L_a [(2 L_a − 1)(1 + ζ) − (1 − ζ²)]
//            triangle edge (a b) at ζ = ∓1:  N = 2 L_a L_b (1 ∓ ζ)
//            vertical edge above corner a:   N = L_a (1 − ζ²).
// Derivative matrices are 3 × n: row k holds ∂N_a/∂ξ_k, column a the node.
//
// Integration rules (weights sum to the reference volume; points in natural coordinates):
//   tet_rule(1)   centroid, weight 1/6: exact for degree 1.
//   tet_rule(4)   (a, a, a) and permutations with a = (5 − √5)/20, weights 1/24: degree 2
//                 (Zienkiewicz, Taylor & Zhu, table 6.4; the C3D10 stiffness rule of Abaqus).
//   tet_rule(14)  the 14-point degree-5 rule with positive weights (Walkington, "Quadrature on
//                 simplices of arbitrary dimension", CMU 2000; tabulated by Jaśkowiec & Sukumar,
//                 IJNME 121 (2020) 2418–2436, table for p = 5): 4 + 4 points (a, a, a, 1 − 3a),
//                 6 points (b, b, ½ − b, ½ − b).
//   triangle_rule(1)  centroid, weight ½ (degree 1); triangle_rule(3) the points (⅙, ⅙), (⅔, ⅙),
//                 (⅙, ⅔), weights ⅙ (degree 2, Strang & Fix); triangle_rule(7) Radon's 7-point
//                 degree-5 rule (Zienkiewicz, Taylor & Zhu, table 6.3).
//   wedge_rule(t, g)  triangle_rule(t) × Gauss–Legendre with g points in ζ.

#include <Eigen/Core>
#include <vector>

#include "jointhb/fe/hexahedron.hpp"
#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

/// Natural coordinates of local node `node` of a tetrahedron (0..9) or wedge (0..14) type.
/// Throws std::invalid_argument for hexahedra and std::out_of_range for a bad node.
[[nodiscard]] Eigen::Vector3d simplex_node_natural_coordinates(ElementType type, int node);

[[nodiscard]] Eigen::Matrix<double, 4, 1> tet4_shape_functions(const Eigen::Vector3d& xi);
[[nodiscard]] Eigen::Matrix<double, 3, 4> tet4_shape_derivatives(const Eigen::Vector3d& xi);
[[nodiscard]] Eigen::Matrix<double, 10, 1> tet10_shape_functions(const Eigen::Vector3d& xi);
[[nodiscard]] Eigen::Matrix<double, 3, 10> tet10_shape_derivatives(const Eigen::Vector3d& xi);
[[nodiscard]] Eigen::Matrix<double, 6, 1> wedge6_shape_functions(const Eigen::Vector3d& xi);
[[nodiscard]] Eigen::Matrix<double, 3, 6> wedge6_shape_derivatives(const Eigen::Vector3d& xi);
[[nodiscard]] Eigen::Matrix<double, 15, 1> wedge15_shape_functions(const Eigen::Vector3d& xi);
[[nodiscard]] Eigen::Matrix<double, 3, 15> wedge15_shape_derivatives(const Eigen::Vector3d& xi);

/// Tetrahedron rules with 1, 4 or 14 points (header); std::invalid_argument otherwise.
[[nodiscard]] const std::vector<GaussPoint>& tet_rule(int points);
/// Triangle rules with 1, 3 or 7 points in (ξ, η) (the third coordinate is 0).
[[nodiscard]] const std::vector<GaussPoint>& triangle_rule(int points);
/// triangle_rule(triangle_points) × Gauss–Legendre (1, 2 or 3 points) in ζ.
[[nodiscard]] std::vector<GaussPoint> wedge_rule(int triangle_points, int line_points);

/// The natural coordinates of the element centre: 0 (hexahedra), (¼, ¼, ¼) (tetrahedra),
/// (⅓, ⅓, 0) (wedges).
[[nodiscard]] Eigen::Vector3d centre_natural_coordinates(ElementType type);

/// The rule of `type` for the stiffness (mass = false) or the consistent mass and volume
/// (mass = true): hexahedra hex_gauss_rule(stiffness_rule / mass_rule of solid_element.hpp);
///   tet4 1 / 4 points, tet10 4 / 14, wedge6 3×2 / 3×2, wedge15 3×3 / 7×3.
[[nodiscard]] const std::vector<GaussPoint>& integration_rule(ElementType type, bool mass);

}  // namespace jointhb::fe
