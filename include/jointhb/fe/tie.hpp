#pragma once
// Bonded (tied) surfaces: a slave surface glued to a master surface so that their relative
// displacement vanishes (Abaqus/CalculiX *TIE; docs/ties.md).
//
// The tie is built on the interface gap operator of fe/interface.hpp with the slave surface as the
// bottom and the master as the top: g = G u (3P), point areas a_p. It acts as a bilateral linear
// penalty in all three directions, t_p = k g_p, so that its virtual work Σ_p a_p δg_pᵀ t_p gives
//
//   K_tie = k Gᵀ A G,   A = diag(a_p) ⊗ I_3                                          (TIE-1)
//
// (eq. (22)/(23) of the interface with C_p = k I). The rows of point p are G_p = R_p D_p, with D_p
// the interpolated difference u^top − u^bottom and R_p its orthonormal frame, so
// G_pᵀ G_p = D_pᵀ D_p: the frame drops out and the tie has no preferred direction. K_tie is symmetric positive semi-definite and annihilates every rigid-body
// motion of the whole (G u = 0 for coincident nodes moving together). It is linear and carries no
// contact law: it adds to the structure's stiffness (pipeline::preload_model).
//
// The penalty follows the adjacent material and mesh:
//
//   k = α E_max / h                                                                  (TIE-2)
//
// with E_max the largest Young's modulus of the elements that own the tie's faces (both sides), h
// the smallest edge of those elements, and α the dimensionless penalty factor (default 1e3). A
// node pair then carries about α times the stiffness of one element layer, and the tie's
// compliance adds a relative error O(1/α) to the frequencies (measured in docs/ties.md).
//
// Small displacements: G is built once on the undeformed geometry, like an interface's. The
// initial offset between slave and master nodes (within the matching tolerance) carries no force:
// the tie bonds the displacements, not the positions.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <span>
#include <string>
#include <vector>

#include "jointhb/fe/interface.hpp"
#include "jointhb/fe/material.hpp"
#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

struct TieOptions {
  std::string name;            ///< label for messages and outputs (may be empty)
  std::string slave_surface;   ///< Mesh::surfaces key: the interface's bottom surface
  std::string master_surface;  ///< Mesh::surfaces key: the interface's top surface
  double penalty_factor = 1e3;     ///< α [-], in [1, 1e6]: k = α E_max / h, eq. (TIE-2)
  double match_tolerance = 1e-6;   ///< [-], in (0, 0.1]: as InterfaceOptions::match_tolerance
  /// Slave nodes to tie (node indices, e.g. Abaqus' TIED NSET); empty: every slave node. Only
  /// with points at the slave nodes (nodal integration of quad4 faces): the points of the other
  /// slave nodes get no stiffness.
  std::vector<int> tied_nodes;

  /// Empty when valid, otherwise a message naming the field and the violated constraint.
  [[nodiscard]] std::string validate() const;
};

struct Tie {
  std::string name, slave_surface, master_surface;
  /// The gap operator's interface: bottom = slave, top = master; nodal integration for linear
  /// faces, Gauss for quadratic ones.
  Interface geometry;
  Eigen::VectorXd point_area;  ///< a_p of the tied points (P) [m²]; 0 for slave nodes not tied
  double area = 0.0;           ///< Σ point_area [m²]
  double penalty_factor = 0.0;  ///< α [-]
  double youngs_modulus = 0.0;  ///< E_max [Pa] of the elements owning the tie's faces
  double element_size = 0.0;    ///< h [m]: their smallest edge
  double penalty = 0.0;         ///< k = α E_max / h [Pa/m], eq. (TIE-2)

  /// Points that carry stiffness (point_area > 0).
  [[nodiscard]] int num_tied_points() const;
};

/// Builds the tie. `material_per_part[p]` is the material of Mesh::parts[p]. Throws
/// std::invalid_argument (one line, "tie 'NAME' ...") on invalid options, a material list that
/// does not fit the mesh, or any error of build_interface (unknown or empty surface, faces
/// without a partner, surfaces that do not face each other, ...), and when tied_nodes leaves no
/// point or needs points at the nodes that the faces do not have.
[[nodiscard]] Tie build_tie(const Mesh& mesh, const std::vector<Material>& material_per_part,
                            const TieOptions& options);

/// Appends the triplets of K_tie = k Gᵀ A G, eq. (TIE-1), to `triplets` (Mesh DOF numbering,
/// duplicates to be summed as setFromTriplets does).
void add_tie_stiffness(const Tie& tie, std::vector<Eigen::Triplet<double>>& triplets);

/// Σ K_tie of all ties as a num_dofs × num_dofs sparse matrix (symmetric, both triangles).
[[nodiscard]] Eigen::SparseMatrix<double> tie_stiffness(std::span<const Tie> ties, int num_dofs);

}  // namespace jointhb::fe
