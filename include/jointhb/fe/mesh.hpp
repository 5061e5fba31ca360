#pragma once
// The finite-element mesh shared by every FE stage: nodes, solid elements (hexahedra, tetrahedra,
// wedges) grouped in parts, node sets, element sets and surfaces (element faces). SI units
// throughout (metres).
//
// Node ordering of every element is Abaqus/CalculiX's. Hexahedra (identical to VTK's
// VTK_HEXAHEDRON = 12 and VTK_QUADRATIC_HEXAHEDRON = 25):
//   corners 0-3 on the face ζ = -1 (counter-clockwise seen from +ζ), corners 4-7 above them;
//   hex20 mid-edge nodes 8-11 on edges 0-1, 1-2, 2-3, 3-0; 12-15 on edges 4-5, 5-6, 6-7, 7-4;
//   16-19 on the vertical edges 0-4, 1-5, 2-6, 3-7.
// Faces are numbered as Abaqus' S1..S6 (0-based here), each listed with its outward normal by the
// right-hand rule: S1 = (0 3 2 1), S2 = (4 5 6 7), S3 = (0 1 5 4), S4 = (1 2 6 5), S5 = (2 3 7 6),
// S6 = (3 0 4 7); for hex20 the face also has its four mid-edge nodes (face_nodes()).
//
// Tetrahedra (C3D4, C3D10; identical to VTK_TETRA = 10 and VTK_QUADRATIC_TETRA = 24): corners 0-2
// counter-clockwise seen from corner 3; tet10 mid-edge nodes 4-9 on edges 0-1, 1-2, 2-0, 0-3,
// 1-3, 2-3. Faces S1..S4 (Abaqus: 1-2-3, 1-4-2, 2-4-3, 3-4-1, listed there with the inward normal)
// with outward normals: S1 = (0 2 1), S2 = (0 1 3), S3 = (1 2 3), S4 = (2 0 3).
//
// Wedges (C3D6, C3D15): corners 0-2 on the bottom triangle, counter-clockwise seen from the top
// triangle 3-5 (corner 3 above 0, 4 above 1, 5 above 2); wedge15 mid-edge nodes 6-8 on edges 0-1,
// 1-2, 2-0, 9-11 on 3-4, 4-5, 5-3, 12-14 on the vertical edges 0-3, 1-4, 2-5. Faces S1..S5
// (Abaqus: 1-2-3, 4-6-5, 1-4-5-2, 2-5-6-3, 3-6-4-1, inward) with outward normals: S1 = (0 2 1),
// S2 = (3 4 5), S3 = (0 1 4 3), S4 = (1 2 5 4), S5 = (2 0 3 5). VTK's VTK_WEDGE = 13 and
// VTK_QUADRATIC_WEDGE = 26 number the same nodes with the bottom triangle the other way round
// (VTK: "(0,1,2) ... forms a triangle whose normal points outward, away from (3,4,5)"): the VTK
// writer permutes them (vtk_writer.cpp).
//
// Every face lists its corners (3 or 4, outward normal by the right-hand rule), then for the
// quadratic types the mid-edge node between corners k and k+1 for each k.

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
  tet4,               ///< C3D4: linear tetrahedron, 1-point integration (constant strain)
  tet10,              ///< C3D10: quadratic tetrahedron, 4-point integration
  wedge6,             ///< C3D6: linear wedge (triangle × line), 3×2 integration
  wedge15,            ///< C3D15: quadratic serendipity wedge, 3×3 integration
};

enum class ElementFamily { hexahedron, tetrahedron, wedge };

/// The shape of `type`.
[[nodiscard]] ElementFamily family(ElementType type);
/// True for the types with mid-edge nodes (hex20, hex20_reduced, tet10, wedge15).
[[nodiscard]] bool is_quadratic(ElementType type);
/// 8, 20 (hexahedra), 4, 10 (tetrahedra), 6, 15 (wedges).
[[nodiscard]] int node_count(ElementType type);
/// 8 (hexahedra), 4 (tetrahedra) or 6 (wedges): the first corner_count nodes are the corners.
[[nodiscard]] int corner_count(ElementType type);
/// 6 (hexahedra), 4 (tetrahedra) or 5 (wedges).
[[nodiscard]] int face_count(ElementType type);
/// Hexahedra only (every face alike): 4 (hex8) or 8 (hex20: 4 corners then 4 mid-edge nodes).
/// Throws std::invalid_argument for the other families, whose faces are triangles (and, for
/// wedges, also quadrilaterals): use the per-face overload.
[[nodiscard]] int face_node_count(ElementType type);
/// Nodes of face `face` (0-based) of `type`: 3 or 4 corners, doubled for the quadratic types.
[[nodiscard]] int face_node_count(ElementType type, int face);
/// Corners of face `face` (0-based) of `type`: 3 (triangle) or 4 (quadrilateral).
[[nodiscard]] int face_corner_count(ElementType type, int face);
/// "C3D8", "C3D8I", "C3D20", "C3D20R", "C3D4", "C3D10", "C3D6", "C3D15".
[[nodiscard]] const char* abaqus_name(ElementType type);
/// The type whose abaqus_name is `name` (case-sensitive), or none.
[[nodiscard]] std::optional<ElementType> element_type_of_abaqus_name(std::string_view name);

/// The corners (local numbering) of the 12 edges of a hexahedron; hex20 mid-edge node 8 + k lies
/// on edge k (the numbering above).
[[nodiscard]] const std::array<std::array<int, 2>, 12>& hex_edge_corners();

/// The corners (local numbering) of the edges of `type`'s family: 12 (hexahedra), 6
/// (tetrahedra), 9 (wedges). For every quadratic type the mid-edge node corner_count + k lies on
/// edge k.
[[nodiscard]] std::span<const std::array<int, 2>> edge_corners(ElementType type);

struct Element {
  ElementType type = ElementType::hex8_incompatible;
  int part = 0;                      ///< index into Mesh::parts
  std::array<int, 20> nodes{};       ///< 0-based node indices; the first node_count(type) are used
  [[nodiscard]] std::span<const int> node_span() const {
    return {nodes.data(), static_cast<std::size_t>(node_count(type))};
  }
};

/// Face `face` (0 .. face_count − 1, = Abaqus S(face+1)) of element `element`.
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

/// The face's node indices (local numbering of the element) with outward normal by the right-hand
/// rule: 3 or 4 corners, then (quadratic types) the mid-edge nodes between corners k and k+1.
/// Throws std::out_of_range for a face outside 0 .. face_count(type) − 1.
[[nodiscard]] std::span<const int> face_local_nodes(ElementType type, int face);

/// The face's global node indices, in the order of face_local_nodes.
[[nodiscard]] std::vector<int> face_nodes(const Mesh& mesh, const Face& face);

/// The mean of the face's corner nodes (3 or 4) [m] (its centroid for flat triangles, its centre
/// for straight-edged parallelograms).
[[nodiscard]] Eigen::Vector3d face_centre(const Mesh& mesh, const Face& face);

/// Appends `other` to `mesh` (nodes, elements, parts, sets, surfaces; names must not clash, else
/// std::invalid_argument naming the clash). Indices of `other` are shifted. No nodes are merged.
void append(Mesh& mesh, const Mesh& other);

/// How messages name element index `e`: "element 17 of part BRACKET" (ids come from each part's own
/// file, so two parts may both have an element 17; the part tells them apart), or "element #e"
/// when the mesh carries no id for it.
[[nodiscard]] std::string element_name(const Mesh& mesh, int e);

}  // namespace jointhb::fe
