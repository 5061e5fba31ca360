#pragma once
// Zero-thickness interface elements of Gaul & Mayer, eq. (13)-(24)
// (docs/zero-thickness-elements.md).
//
// An interface joins two surfaces of a Mesh (faces tri3, tri6, quad4, quad8). Matching meshes:
// every bottom face is paired with the top face whose nodes coincide with its own, one
// zero-thickness element per pair. Non-matching meshes: each bottom face with the top faces over
// it, by segment-to-segment (mortar) integration (docs/zero-thickness-elements.md §4a, eq. M-1 to
// M-4; there the top displacement at a point is Σ_k top_shape_k u_k instead of the coincident
// node's). The interface is represented by its integration points p = 0..P-1:
//
//   relative displacement, eq. (19), in the local frame R_p (rows t1, t2, n) of point p:
//     g_p = R_p Σ_i h_i(ξ_p, η_p) (u_i^top - u_i^bottom),   g = G u   (G: 3P × 3N, "gap operator")
//   virtual work of the tractions, eq. (22):  δW_C = Σ_p a_p δg_pᵀ t_p = δuᵀ Gᵀ A t
//     → internal force f = Gᵀ A t  (add to K_s u in the residual K_s u + f - f_ext = 0)
//   tangent stiffness, eq. (23)/(24):  K = ∂f/∂u = Gᵀ A C G,  C_p = ∂t_p/∂g_p
//
// with a_p = w_p det J_p the area weight of the point. Sign conventions are those of the contact
// layer (contact/normal_law.hpp): g_N is the gap (opening positive), t_N = -p_N. The frame comes
// from the bottom surface: n is the bottom face's outward normal (it points from the bottom body
// into the top body), t1 = ∂x/∂ξ normalised, t2 = n × t1. Small displacements: G is built once
// on the undeformed geometry (no large rotations, no finite sliding).
//
// Integration points are kept per element (the paper integrates element by element): with nodal
// integration a node pair shared by 4 elements carries 4 points, each with its own element's
// frame and area share. P is therefore (points per element) × (number of elements).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

enum class InterfaceIntegration {
  nodal,  ///< Newton–Cotes / Lobatto 2×2 at the 4 corner nodes (quad4 faces only): node pairs
          ///< decouple, no traction oscillations (docs/zero-thickness-elements.md §4)
  gauss,  ///< Gauss–Legendre 2×2 (quad4 faces) or 3×3 (quad8 faces), as in the paper
};

/// "nodal" or "gauss".
[[nodiscard]] const char* to_string(InterfaceIntegration integration);

/// How the two surfaces' meshes relate.
enum class InterfaceMeshes {
  matching,      ///< every bottom face has a top face with coincident nodes (else an error)
  non_matching,  ///< meshed independently: segment-to-segment (mortar) integration of the gap
  automatic,     ///< matching where every face has a coincident partner, else non_matching
};

/// "matching", "non-matching" or "automatic".
[[nodiscard]] const char* to_string(InterfaceMeshes meshes);

struct InterfaceOptions {
  std::string name;            ///< label for messages (may be empty)
  std::string bottom_surface;  ///< Mesh::surfaces key; its outward normals define n
  std::string top_surface;     ///< Mesh::surfaces key; faces coincide with the bottom's
  InterfaceIntegration integration = InterfaceIntegration::nodal;
  double match_tolerance = 1e-6;  ///< [-], in (0, 0.1]: node coincidence distance / face size
  InterfaceMeshes meshes = InterfaceMeshes::matching;

  /// Empty when valid, otherwise a message naming the field and the violated constraint.
  [[nodiscard]] std::string validate() const;
};

/// One integration point of the interface.
struct InterfacePoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();   ///< [m], on the bottom face
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();  ///< rows t1, t2, n (orthonormal, det +1)
  double area = 0.0;                                    ///< a_p = w_p det J_p [m²]
  int element = 0;                                      ///< index into Interface::elements
  Eigen::Vector2d natural = Eigen::Vector2d::Zero();    ///< (ξ, η) on the bottom face
  std::array<double, 8> shape{};  ///< h_i(ξ, η) of the bottom face's nodes, eq. (14) (3..8 used)
  /// Weights of the element's top_nodes: the top displacement at the point is
  /// Σ_k top_shape[k] u_{top_nodes[k]} (matching: equal to shape; non-matching: the top face's
  /// shape functions at the projected point, or the dual-mortar weights M_ij / D_i, eq. M-4).
  std::vector<double> top_shape;
};

/// One zero-thickness element: a bottom face and the top surface over it.
struct InterfaceElement {
  Face bottom;                    ///< the bottom face (its element's external id in messages)
  Face top;                       ///< the coincident top face (non-matching: the one overlapping most)
  std::vector<Face> top_faces;    ///< every top face over it ({top} when matching)
  std::vector<int> bottom_nodes;  ///< the bottom face's node indices (face_nodes order: 3, 4, 6, 8)
  /// Matching: top_nodes[k] coincides with bottom_nodes[k]. Non-matching: the nodes of top_faces
  /// (each once), in the order of InterfacePoint::top_shape.
  std::vector<int> top_nodes;
  int first_point = 0;            ///< its points are first_point .. first_point + num_points - 1
  int num_points = 0;
  double area = 0.0;  ///< its share of the interface area: Σ a_p of its points (dual mortar:
                      ///< Σ_i D̃_i of its corners; a node's point sits in the node's first element)
};

struct NodePair {
  int bottom = 0;  ///< node index on the bottom surface
  int top = 0;     ///< the coincident node index on the top surface
  friend bool operator==(const NodePair&, const NodePair&) = default;
};

struct Interface {
  std::string name;
  InterfaceIntegration integration = InterfaceIntegration::nodal;
  InterfaceMeshes meshes = InterfaceMeshes::matching;  ///< as built: matching or non_matching
  int num_mesh_nodes = 0;                    ///< N: G has 3N columns (Mesh DOF 3i+d)
  std::vector<InterfacePoint> points;        ///< P points, grouped by element
  std::vector<InterfaceElement> elements;    ///< the facets (bottom face node lists for output)
  std::vector<NodePair> node_pairs;          ///< unique, sorted by bottom node (empty when non-matching)
  Eigen::SparseMatrix<double> gap_operator;  ///< G, 3P × 3N: g = G u, eq. (19)
  double total_area = 0.0;                   ///< Σ a_p [m²]
  double uncovered_area = 0.0;  ///< non-matching: bottom area with no top face over it [m²]

  [[nodiscard]] int num_points() const { return static_cast<int>(points.size()); }
  [[nodiscard]] int num_mesh_dofs() const { return 3 * num_mesh_nodes; }
};

/// Builds the interface between two surfaces of `mesh` (faces tri3, tri6, quad4, quad8). Matching
/// meshes: each bottom face with its coincident top face. Non-matching meshes (options.meshes):
/// the segment-to-segment (mortar) integration of interface_mortar.cpp. Throws
/// std::invalid_argument (one line, naming the interface, surface and the element's external id)
/// on invalid options, an unknown or empty surface, mixed face types on a matching interface,
/// nodal integration of quadratic faces, a face without a coincident partner (matching), faces
/// that share nodes, coincident faces whose outward normals are not opposite (surfaces that do not
/// face each other), or non-matching surfaces that do not overlap.
[[nodiscard]] Interface build_interface(const Mesh& mesh, const InterfaceOptions& options);

/// g = G u (3P, point p at rows 3p..3p+2 = (g_Tx, g_Ty, g_N) in its frame), eq. (19), evaluated
/// from the node pairs' differences u^top - u^bottom (a rigid-body motion gives exactly 0).
[[nodiscard]] Eigen::VectorXd gaps(const Interface& interface, const Eigen::VectorXd& u);

/// f = Gᵀ A t (3N), eq. (22), for the tractions t (3P, local frames).
[[nodiscard]] Eigen::VectorXd interface_force(const Interface& interface,
                                              const Eigen::VectorXd& tractions);

/// Appends the triplets of K = Gᵀ A C G, eq. (23)/(24), to `triplets` (duplicates to be summed, as
/// setFromTriplets does), global Mesh DOF numbering shifted by `dof_offset`. C_p = tangents[p] is
/// ∂t_p/∂g_p in the local frame of point p (3×3, need not be symmetric).
void add_interface_stiffness(const Interface& interface, std::span<const Eigen::Matrix3d> tangents,
                             std::vector<Eigen::Triplet<double>>& triplets, int dof_offset = 0);

struct InterfaceAssembly {
  Eigen::VectorXd force;                  ///< f = Gᵀ A t (3N), eq. (22)
  Eigen::SparseMatrix<double> stiffness;  ///< K = Gᵀ A C G (3N × 3N), eq. (23)/(24)
};

/// Force and tangent stiffness from per-point tractions (3P) and tangents (P matrices).
[[nodiscard]] InterfaceAssembly assemble_interface_force_and_tangent(
    const Interface& interface, const Eigen::VectorXd& tractions,
    std::span<const Eigen::Matrix3d> tangents);

/// The contact laws evaluated at every point, with the assembled force and tangent.
struct InterfaceContactState {
  Eigen::VectorXd gap;                   ///< g = G u + (0, 0, g_N0,p) (3P)
  Eigen::VectorXd traction;              ///< t = (t_Tx, t_Ty, t_N) per point (3P)
  Eigen::VectorXd pressure;              ///< p_N = -t_N (P) [Pa]
  std::vector<Eigen::Matrix3d> tangent;  ///< C_p = ∂t_p/∂g_p (P)
  std::vector<bool> open;                ///< p_N below the law's gapping floor (P)
  int num_open = 0;
  Eigen::VectorXd force;                  ///< f = Gᵀ A t (3N)
  Eigen::SparseMatrix<double> stiffness;  ///< K = Gᵀ A C G (3N × 3N); empty without with_stiffness
};

/// Static contact state for the displacement u (3N): each point steps from (t_T0 = 0, g_0 = 0)
/// to g_1 = G u + g_N0 e_N, i.e. the tangential traction is the virgin response to the tangential
/// displacement since the unloaded, stress-free state (the preload's tangential convention).
/// `initial_normal_gap` (P or empty = zero) adds g_N0,p to each normal gap (geometric offsets,
/// bolt-hole clearances). One law for every point. `with_stiffness` = false skips assembling K
/// (the tangents C_p are still returned), for callers that only need the force or build their own
/// matrix from the tangents.
[[nodiscard]] InterfaceContactState evaluate_static_contact(
    const Interface& interface, const contact::ContactPoint& law, const Eigen::VectorXd& u,
    const Eigen::VectorXd& initial_normal_gap = {}, bool with_stiffness = true);

/// As above with one law per point (laws.size() == P).
[[nodiscard]] InterfaceContactState evaluate_static_contact(
    const Interface& interface, std::span<const contact::ContactPoint> laws,
    const Eigen::VectorXd& u, const Eigen::VectorXd& initial_normal_gap = {},
    bool with_stiffness = true);

}  // namespace jointhb::fe
