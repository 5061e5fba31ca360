#pragma once
// Static loads on a mesh besides the bolts: nodal forces and uniform surface pressures, applied
// in the preload (docs/bolts-and-preload.md §"Static loads").
//
// A pressure p on a face is the traction t = −p n (n: the outward normal, so p > 0 pushes into
// the body, as Abaqus' *DSLOAD P). Its consistent nodal forces are (Zienkiewicz, Taylor & Zhu,
// The Finite Element Method, vol. 1, §6.5.2, the boundary term ∫ Nᵀ t̄ dΓ):
//   f_a = −p ∫_face N_a n dA = −p ∫∫ N_a(ξ, η) (∂x/∂ξ × ∂x/∂η) dξ dη,                      (L-1)
// where the face's nodes are ordered with the outward normal by the right-hand rule (mesh.hpp),
// so that ∂x/∂ξ × ∂x/∂η = n dA/(dξ dη). Shape functions N_a of the face:
//   quad4  N_a = ¼ (1 + ξ ξ_a)(1 + η η_a), nodes (−1,−1), (1,−1), (1,1), (−1,1);
//   quad8  the serendipity functions of the same corners plus the mid-edge nodes between corners
//          k and k+1 (ibid. §6.3, eq. 6.30): corners ¼ (1 + ξ ξ_a)(1 + η η_a)(ξ ξ_a + η η_a − 1),
//          mid-edge ½ (1 − ξ²)(1 + η η_a) for ξ_a = 0, and ½ (1 + ξ ξ_a)(1 − η²) for η_a = 0;
//   tri3   N = (1 − ξ − η, ξ, η) on the unit triangle, nodes (0,0), (1,0), (0,1);
//   tri6   corners L_a (2 L_a − 1), mid-edge nodes between corners k and k+1: 4 L_k L_{k+1}
//          (L: the area coordinates; ibid. §6.6).
// Integration: Gauss 2×2 (quad4), 3×3 (quad8), the 3-point degree-2 rule (tri3) and Dunavant's
// 6-point degree-4 rule (tri6; Dunavant 1985, Int. J. Numer. Meth. Eng. 21:1129–1148, table for
// p = 4): exact for flat faces, and for curved quadratic faces up to the degree of N_a times the
// cross product. For a flat quad4 of area A the forces are −pA n/4 per node; for a flat
// rectangular quad8 they are +pA n/12 at the corners (a pull) and −pA n/3 at the mid-edge nodes.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

/// The same force on each of a set of nodes.
struct NodalForces {
  std::string label;          ///< where it was defined, for messages (e.g. "model.loads[0]")
  std::vector<int> nodes;     ///< node indices (may repeat: the force is then added again)
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  ///< per node [N]
};

/// A uniform pressure on a set of faces.
struct SurfacePressure {
  std::string label;
  std::vector<Face> faces;
  double pressure = 0.0;  ///< [Pa]; > 0 pushes into the body (traction −p n)
};

struct StaticLoads {
  std::vector<NodalForces> forces;
  std::vector<SurfacePressure> pressures;

  [[nodiscard]] bool empty() const { return forces.empty() && pressures.empty(); }
};

/// The consistent nodal forces of one face under pressure p, eq. (L-1): 3 × k (column a = node
/// a of face_nodes()). Throws std::invalid_argument for a face with other than 3, 4, 6 or 8
/// nodes.
[[nodiscard]] Eigen::Matrix3Xd face_pressure_forces(const Eigen::Matrix3Xd& face_coordinates,
                                                   double pressure);

/// The full load vector (3 × num_nodes entries, DOF 3i + d) of `loads`. Throws
/// std::invalid_argument naming the load's label for a node or face outside the mesh or a
/// non-finite value.
[[nodiscard]] Eigen::VectorXd static_load_vector(const Mesh& mesh, const StaticLoads& loads);

/// Resultant force Σ f_i and moment Σ x_i × f_i about the origin of a full load vector.
struct LoadResultant {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
};
[[nodiscard]] LoadResultant load_resultant(const Mesh& mesh, const Eigen::VectorXd& load);

/// Empty when `load` is self-equilibrated — resultant force below 1e-9 Σ|f_i| and moment about
/// the mesh centre below 1e-9 Σ|f_i| times the mesh's radius —, else "a resultant force of F N and
/// a moment of M N m about the mesh centre": what a free-free model cannot carry.
[[nodiscard]] std::string equilibrium_problem(const Mesh& mesh, const Eigen::VectorXd& load);

}  // namespace jointhb::fe
