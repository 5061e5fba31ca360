#pragma once
// Stiffness and consistent mass of the isoparametric solid elements of mesh.hpp (hexahedra,
// tetrahedra, wedges).
//
// Local DOF 3a + d = node a, axis d; node coordinates are passed as a 3 × n matrix (column a =
// node a, n = node_count(type)). With the gradients g_a = ∇N_a = J⁻¹ ∂N_a/∂ξ (J_kj = ∂x_j/∂ξ_k)
// the isotropic stiffness is, node block by node block,
//   K_ab = Σ_q w_q det J_q [ λ g_a g_bᵀ + μ g_b g_aᵀ + μ (g_a · g_b) I₃ ]            (1)
// which equals ∫ B_aᵀ D B_b dV for D of material.hpp (Hughes, The Finite Element Method, §2.8,
// eq. 2.8.27 written out for isotropy), and the consistent mass is
//   M_ab = ρ Σ_q w_q det J_q N_a N_b I₃.                                            (2)
//
// Element types and integration (stiffness rule; the mass always uses the full rule):
//   hex8               2×2×2 (C3D8): trilinear, locks in bending (parasitic shear).
//   hex8_incompatible  2×2×2 (C3D8I-like): trilinear + the 9 incompatible modes
//                      u_α = Σ_m α_m P_m(ξ), P = (1 − ξ², 1 − η², 1 − ζ²) per direction
//                      (Wilson, Taylor, Doherty & Ghaboussi 1973), condensed statically,
//                        K = K_uu − K_uα K_αα⁻¹ K_αu,                                  (3)
//                      with Taylor's modification (Taylor, Beresford & Wilson 1976, Int. J. Numer.
//                      Meth. Eng. 10:1211–1219; also Simo & Rifai 1990, eq. 4.10): the
//                      incompatible-mode gradients use the centre Jacobian J₀ and the factor
//                      det J₀ / det J,
//                        g_m = (det J₀ / det J) J₀⁻¹ ∂P_m/∂ξ,                                (4)
//                      so that ∫ g_m dV = det J₀ J₀⁻¹ ∫ ∂P_m/∂ξ dξ = 0: a constant stress does
//                      no work on the incompatible modes and the patch test passes on distorted
//                      elements. (Abaqus' C3D8I adds 4 more volumetric modes, 13 in all; this is
//                      the classical 9-mode QM6-type element.)
//   hex20              3×3×3 (C3D20); mass 3×3×3.
//   hex20_reduced      2×2×2 (C3D20R); mass 3×3×3. A single element has 6 spurious zero-energy
//                      modes besides the 6 rigid-body ones (they do not propagate in a mesh of
//                      two or more elements).
//   tet4               1 point (C3D4, constant strain, exact); mass 4 points (degree 2: exact).
//   tet10              4 points (C3D10 as Abaqus; degree 2: exact for straight edges, whose
//                      gradients are linear); mass 14 points (degree 5 ≥ 4: exact for straight
//                      edges). Rules and sources in simplex_elements.hpp.
//   wedge6             3-point triangle × 2-point Gauss (exact for a prism with parallel
//                      triangles); mass the same rule (exact there too).
//   wedge15            3-point triangle × 3-point Gauss (9 points, as Abaqus' C3D15); mass 7-point
//                      (degree 5) triangle × 3-point Gauss (exact for a straight-sided prism).
// The equations are the same for every family: only N_a, ∂N_a/∂ξ and the rule change.

#include <Eigen/Core>

#include "jointhb/fe/material.hpp"
#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

struct ElementMatrices {
  Eigen::MatrixXd
      stiffness;         ///< 3n × 3n [N/m], eq. (1) (condensed, eq. (3), for hex8_incompatible)
  Eigen::MatrixXd mass;  ///< 3n × 3n [kg], eq. (2)
  double volume = 0.0;   ///< [m³], Σ_q w_q det J_q with the mass rule
};

/// Hexahedra: Gauss points per direction of the stiffness rule of `type` (2 or 3). Tetrahedra
/// and wedges have no tensor-product rule: std::invalid_argument (see integration_rule of
/// simplex_elements.hpp).
[[nodiscard]] int stiffness_rule(ElementType type);
/// Hexahedra: Gauss points per direction of the (consistent) mass rule of `type` (2 for hex8, 3
/// for hex20); std::invalid_argument for the other families.
[[nodiscard]] int mass_rule(ElementType type);

/// Stiffness, consistent mass and volume of one element. `coordinates` is 3 × node_count(type).
/// Throws std::invalid_argument for a wrong column count, an invalid material, or a non-positive
/// Jacobian determinant at an integration point or at the centre (inverted or degenerate element).
[[nodiscard]] ElementMatrices element_matrices(ElementType type,
                                               const Eigen::Matrix3Xd& coordinates,
                                               const Material& material);
[[nodiscard]] Eigen::MatrixXd element_stiffness(ElementType type,
                                                const Eigen::Matrix3Xd& coordinates,
                                                const Material& material);
[[nodiscard]] Eigen::MatrixXd element_mass(ElementType type, const Eigen::Matrix3Xd& coordinates,
                                           const Material& material);

/// Small strain (Voigt, engineering shears) at the element centre (ξ = 0 for hexahedra, the
/// centroid of the reference element for tetrahedra and wedges: centre_natural_coordinates of
/// simplex_elements.hpp) from the element's nodal displacements (3n, DOF 3a + d). For hex8_incompatible the incompatible modes contribute nothing
/// there (∂P_m/∂ξ = 0 at ξ = 0), so no condensed variables are needed.
[[nodiscard]] Vector6d element_centre_strain(ElementType type, const Eigen::Matrix3Xd& coordinates,
                                             const Eigen::VectorXd& displacements);
/// σ = D ε at the element centre [Pa] (Voigt order xx, yy, zz, xy, yz, zx).
[[nodiscard]] Vector6d element_centre_stress(ElementType type, const Eigen::Matrix3Xd& coordinates,
                                             const Material& material,
                                             const Eigen::VectorXd& displacements);

}  // namespace jointhb::fe
