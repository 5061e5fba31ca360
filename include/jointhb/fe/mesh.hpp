#pragma once
// The finite-element mesh shared by every FE stage: nodes, hexahedral elements grouped in parts,
// node sets, element sets and surfaces (element faces). SI units throughout (metres).
//
// Node ordering of every element is Abaqus/CalculiX's (identical to VTK's VTK_HEXAHEDRON = 12 and
// VTK_QUADRATIC_HEXAHEDRON = 25):
//   corners 0-3 on the face ζ = -1 (counter-clockwise seen from +ζ), corners 4-7 above them;
//   hex20 mid-edge nodes 8-11 on edges 0-1, 1-2, 2-3, 3-0; 12-15 on edges 4-5, 5-6, 6-7, 7-4;
//   16-19 on the vertical edges 0-4, 1-5, 2-6, 3-7.
// Faces are numbered as Abaqus' S1..S6 (0-based here), each listed with its outward normal by the
// right-hand rule: S1 = (0 3 2 1), S2 = (4 5 6 7), S3 = (0 1 5 4), S4 = (1 2 6 5), S5 = (2 3 7 6),
// S6 = (3 0 4 7); for hex20 the face also has its four mid-edge nodes (face_nodes()).

#include <Eigen/Core>
#include <array>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace jointhb::fe {

enum class ElementType {
  hex8,               ///< C3D8: trilinear, full 2×2×2 integration (locks in bending)
  hex8_incompatible,  ///< C3D8I: trilinear + Wilson–Taylor incompatible modes (bending-accurate)
  hex20,              ///< C3D20: serendipity quadratic, 3×3×3 integration
  hex20_reduced,      ///< C3D20R: serendipity quadratic, 2×2×2 integration
};

/// 8 or 20.
[[nodiscard]] int node_count(ElementType type);
/// 4 (hex8 faces) or 8 (hex20 faces: 4 corners then 4 mid-edge nodes).
[[nodiscard]] int face_node_count(ElementType type);
/// "C3D8", "C3D8I", "C3D20", "C3D20R".
[[nodiscard]] const char* abaqus_name(ElementType type);
/// The type whose abaqus_name is `name` (case-sensitive), or none.
[[nodiscard]] std::optional<ElementType> element_type_of_abaqus_name(std::string_view name);

/// The corners (local numbering) of the 12 edges of a hexahedron; hex20 mid-edge node 8 + k lies
/// on edge k (the numbering above).
[[nodiscard]] const std::array<std::array<int, 2>, 12>& hex_edge_corners();

struct Element {
  ElementType type = ElementType::hex8_incompatible;
  int part = 0;                      ///< index into Mesh::parts
  std::array<int, 20> nodes{};       ///< 0-based node indices; the first node_count(type) are used
  [[nodiscard]] std::span<const int> node_span() const {
    return {nodes.data(), static_cast<std::size_t>(node_count(type))};
  }
};

/// Face `face` (0..5, = Abaqus S(face+1)) of element `element`.
struct Face {
  int element = 0;
  int face = 0;
  friend bool operator==(const Face&, const Face&) = default;
};

struct Mesh {
  Eigen::Matrix3Xd coordinates;     ///< [m], column i = node i
  std::vector<long> node_ids;       ///< external node number of node i (for messages; 1-based)
  std::vector<Element> elements;
  std::vector<long> element_ids;    ///< external element number of element e (for messages)
  std::vector<std::string> parts;   ///< part names; Element::part indexes this
  std::map<std::string, std::vector<int>> node_sets;     ///< sorted, unique node indices
  std::map<std::string, std::vector<int>> element_sets;  ///< sorted, unique element indices
  std::map<std::string, std::vector<Face>> surfaces;

  [[nodiscard]] int num_nodes() const { return static_cast<int>(coordinates.cols()); }
  [[nodiscard]] int num_elements() const { return static_cast<int>(elements.size()); }
  [[nodiscard]] int num_dofs() const { return 3 * num_nodes(); }  ///< DOF 3i+d = node i, axis d
};

/// The face's node indices (local numbering 0..19 of the element) with outward normal by the
/// right-hand rule: 4 corners, then (hex20) the 4 mid-edge nodes between corners k and k+1.
[[nodiscard]] std::span<const int> face_local_nodes(ElementType type, int face);

/// The face's global node indices, in the order of face_local_nodes.
[[nodiscard]] std::vector<int> face_nodes(const Mesh& mesh, const Face& face);

/// The mean of the face's corner nodes [m] (its centre for straight-edged faces).
[[nodiscard]] Eigen::Vector3d face_centre(const Mesh& mesh, const Face& face);

/// Appends `other` to `mesh` (nodes, elements, parts, sets, surfaces; names must not clash, else
/// std::invalid_argument naming the clash). Indices of `other` are shifted. No nodes are merged.
void append(Mesh& mesh, const Mesh& other);

}  // namespace jointhb::fe
