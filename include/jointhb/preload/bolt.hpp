#pragma once
// Bolts of a bolted assembly (docs/bolts-and-preload.md).
//
// A bolt is a pre-tensioned axial spring between two footprints: the faces under the head and
// under the nut, selected on two surfaces by the distance of their centroid c_f from the bolt
// axis (point p, unit direction a) — a disc (r_i = 0) or the annulus of a washer around a hole:
//   F = { faces f of the surface : r_i ≤ |(c_f − p) − ((c_f − p)·a) a| ≤ r_o }.             (B-4)
// Its axial motion is the footprint-averaged displacement along the axis a (unit vector from
// the nut side towards the head side):
//   e(u) = bᵀu = Σ_{i∈head} w_i a·u_i − Σ_{j∈nut} w_j a·u_j,   Σ w_i = Σ w_j = 1,           (B-1)
// with w_i the consistent-load weight ∫_footprint N_i dA / A_footprint (area weights), so that the
// preload is a uniform pressure on each footprint (a distributing coupling, like Abaqus' RBE3 /
// *COUPLING, DISTRIBUTING, in the axial direction only). The bolt acts on the structure with
//   preload (force control):  f_ext = −P b          (head pushed towards the nut and vice versa) (B-2)
//   dynamics (locked bolt):   K_bolt = k_b b bᵀ     (axial stiffness of shank + head + nut)      (B-3)
// The forces are self-equilibrated (Σ f = 0 and, for a footprint symmetric about the axis, no
// moment). Neglected: the bolt's bending and shear stiffness, its mass, the thread and head
// contact compliance beyond k_b, the washers as bodies (their footprint is where they press), the
// shank's contact with the hole wall (a hole, when the mesh has one, is traction-free), and the
// change of the bolt force while the joint settles (force control during the preload).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "jointhb/fe/mesh.hpp"

namespace jointhb::preload {

struct BoltOptions {
  std::string name;
  Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();      ///< a point on the bolt axis [m]
  Eigen::Vector3d axis_direction = Eigen::Vector3d::UnitZ();  ///< from nut towards head (≠ 0)
  std::string head_surface;  ///< surface under the head (its faces selected by eq. B-4)
  std::string nut_surface;   ///< surface under the nut
  double head_radius = 0.0;  ///< r_o [m] > 0: footprint (washer) outer radius about the axis
  double nut_radius = 0.0;   ///< r_o [m] > 0
  double head_inner_radius = 0.0;  ///< r_i [m] in [0, head_radius): 0 is a disc, > 0 an annulus
  double nut_inner_radius = 0.0;   ///< r_i [m] in [0, nut_radius)
  double axial_stiffness = 0.0;  ///< k_b [N/m] > 0
  double preload = 0.0;          ///< P [N] ≥ 0: bolt tension after tightening

  /// Empty when valid, else "field: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

struct Bolt {
  std::string name;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< unit, nut → head
  std::vector<int> head_nodes;                       ///< footprint nodes (sorted)
  std::vector<int> nut_nodes;
  double head_area = 0.0;  ///< [m²] footprint areas (faces whose centroid lies in [r_i, r_o], B-4)
  double nut_area = 0.0;
  double head_inner_radius = 0.0;  ///< r_i [m] of the footprints as selected (B-4)
  double nut_inner_radius = 0.0;
  Eigen::SparseVector<double> coupling;  ///< b (3N), eq. (B-1)
  double axial_stiffness = 0.0;          ///< k_b
  double preload = 0.0;                  ///< P
  std::vector<int> parts;                ///< parts touched by the footprints (sorted, unique)
};

/// Selects the footprints (eq. B-4) and builds b. Throws std::invalid_argument naming the bolt
/// and the field: unknown surface, no face of the surface in [r_i, r_o], a footprint whose faces
/// are not perpendicular to the axis (|n·a| < 0.9), head and nut on the same side.
[[nodiscard]] Bolt build_bolt(const fe::Mesh& mesh, const BoltOptions& options);

/// Triplets of k_b b bᵀ, eq. (B-3), for every bolt (dense over the footprint DOFs).
void add_bolt_stiffness(const std::vector<Bolt>& bolts,
                        std::vector<Eigen::Triplet<double>>& triplets);

/// Σ k_b b bᵀ, eq. (B-3), as a num_dofs × num_dofs sparse matrix.
[[nodiscard]] Eigen::SparseMatrix<double> bolt_stiffness(const std::vector<Bolt>& bolts, int num_dofs);

/// −Σ s P_b b_b, eq. (B-2), at load factor s (num_dofs).
[[nodiscard]] Eigen::VectorXd bolt_load(const std::vector<Bolt>& bolts, int num_dofs,
                                        double load_factor = 1.0);

}  // namespace jointhb::preload
