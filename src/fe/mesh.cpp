#include "jointhb/fe/mesh.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace jointhb::fe {

ElementFamily family(ElementType type) {
  switch (type) {
    case ElementType::tet4:
    case ElementType::tet10: return ElementFamily::tetrahedron;
    case ElementType::wedge6:
    case ElementType::wedge15: return ElementFamily::wedge;
    default: return ElementFamily::hexahedron;
  }
}

bool is_quadratic(ElementType type) {
  return type == ElementType::hex20 || type == ElementType::hex20_reduced ||
         type == ElementType::tet10 || type == ElementType::wedge15;
}

int node_count(ElementType type) {
  switch (type) {
    case ElementType::hex20:
    case ElementType::hex20_reduced: return 20;
    case ElementType::tet4: return 4;
    case ElementType::tet10: return 10;
    case ElementType::wedge6: return 6;
    case ElementType::wedge15: return 15;
    default: return 8;
  }
}

int corner_count(ElementType type) {
  switch (family(type)) {
    case ElementFamily::tetrahedron: return 4;
    case ElementFamily::wedge: return 6;
    default: return 8;
  }
}

int face_count(ElementType type) {
  switch (family(type)) {
    case ElementFamily::tetrahedron: return 4;
    case ElementFamily::wedge: return 5;
    default: return 6;
  }
}

int face_node_count(ElementType type) {
  if (family(type) != ElementFamily::hexahedron)
    throw std::invalid_argument(std::string("face_node_count: ") + abaqus_name(type) +
                                " has triangular faces; use face_node_count(type, face)");
  return node_count(type) == 20 ? 8 : 4;
}

const char* abaqus_name(ElementType type) {
  switch (type) {
    case ElementType::hex8: return "C3D8";
    case ElementType::hex8_incompatible: return "C3D8I";
    case ElementType::hex20: return "C3D20";
    case ElementType::hex20_reduced: return "C3D20R";
    case ElementType::tet4: return "C3D4";
    case ElementType::tet10: return "C3D10";
    case ElementType::wedge6: return "C3D6";
    case ElementType::wedge15: return "C3D15";
  }
  return "?";
}

std::optional<ElementType> element_type_of_abaqus_name(std::string_view name) {
  for (ElementType type : {ElementType::hex8, ElementType::hex8_incompatible, ElementType::hex20,
                           ElementType::hex20_reduced, ElementType::tet4, ElementType::tet10,
                           ElementType::wedge6, ElementType::wedge15})
    if (name == abaqus_name(type)) return type;
  return std::nullopt;
}

const std::array<std::array<int, 2>, 12>& hex_edge_corners() {
  static constexpr std::array<std::array<int, 2>, 12> edges = {
      {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}}};
  return edges;
}

std::span<const std::array<int, 2>> edge_corners(ElementType type) {
  // Edge k carries the mid-edge node corner_count + k (mesh.hpp).
  static constexpr std::array<std::array<int, 2>, 6> tet = {
      {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};
  static constexpr std::array<std::array<int, 2>, 9> wedge = {
      {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5}, {5, 3}, {0, 3}, {1, 4}, {2, 5}}};
  switch (family(type)) {
    case ElementFamily::tetrahedron: return tet;
    case ElementFamily::wedge: return wedge;
    default: return hex_edge_corners();
  }
}

namespace {
// Corners of S1..S6 with outward normals (right-hand rule), then the mid-edge nodes between
// consecutive corners (hex20 numbering of mesh.hpp).
constexpr std::array<std::array<int, 8>, 6> kFaces = {{
    {0, 3, 2, 1, 11, 10, 9, 8},
    {4, 5, 6, 7, 12, 13, 14, 15},
    {0, 1, 5, 4, 8, 17, 12, 16},
    {1, 2, 6, 5, 9, 18, 13, 17},
    {2, 3, 7, 6, 10, 19, 14, 18},
    {3, 0, 4, 7, 11, 16, 15, 19},
}};
// Tetrahedron S1..S4: 3 corners (outward), then the tet10 mid-edge nodes of edges (0 1), (1 2),
// (2 0) of the face.
constexpr std::array<std::array<int, 6>, 4> kTetFaces = {{
    {0, 2, 1, 6, 5, 4},
    {0, 1, 3, 4, 8, 7},
    {1, 2, 3, 5, 9, 8},
    {2, 0, 3, 6, 7, 9},
}};
// Wedge S1..S5: triangles S1, S2 (3 + 3 nodes), quadrilaterals S3..S5 (4 + 4 nodes).
constexpr std::array<std::array<int, 8>, 5> kWedgeFaces = {{
    {0, 2, 1, 8, 7, 6, -1, -1},
    {3, 4, 5, 9, 10, 11, -1, -1},
    {0, 1, 4, 3, 6, 13, 9, 12},
    {1, 2, 5, 4, 7, 14, 10, 13},
    {2, 0, 3, 5, 8, 12, 11, 14},
}};

void check_face(ElementType type, int face) {
  if (face < 0 || face >= face_count(type))
    throw std::out_of_range(std::string(abaqus_name(type)) + ": face index " +
                            std::to_string(face) + " must be 0.." +
                            std::to_string(face_count(type) - 1));
}
}  // namespace

int face_corner_count(ElementType type, int face) {
  check_face(type, face);
  switch (family(type)) {
    case ElementFamily::tetrahedron: return 3;
    case ElementFamily::wedge: return face < 2 ? 3 : 4;
    default: return 4;
  }
}

int face_node_count(ElementType type, int face) {
  const int corners = face_corner_count(type, face);
  return is_quadratic(type) ? 2 * corners : corners;
}

std::span<const int> face_local_nodes(ElementType type, int face) {
  const auto count = static_cast<std::size_t>(face_node_count(type, face));
  const auto f = static_cast<std::size_t>(face);
  switch (family(type)) {
    case ElementFamily::tetrahedron: return {kTetFaces[f].data(), count};
    case ElementFamily::wedge: return {kWedgeFaces[f].data(), count};
    default: return {kFaces[f].data(), count};
  }
}

std::vector<int> face_nodes(const Mesh& mesh, const Face& face) {
  const Element& element = mesh.elements.at(static_cast<std::size_t>(face.element));
  std::vector<int> nodes;
  for (int local : face_local_nodes(element.type, face.face))
    nodes.push_back(element.nodes[static_cast<std::size_t>(local)]);
  return nodes;
}

Eigen::Vector3d face_centre(const Mesh& mesh, const Face& face) {
  const Element& element = mesh.elements.at(static_cast<std::size_t>(face.element));
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  const int corners = face_corner_count(element.type, face.face);
  for (int local : face_local_nodes(element.type, face.face).first(static_cast<std::size_t>(corners)))
    centre += mesh.coordinates.col(element.nodes[static_cast<std::size_t>(local)]);
  return centre / static_cast<double>(corners);
}

void append(Mesh& mesh, const Mesh& other) {
  const int node_offset = mesh.num_nodes();
  const int element_offset = mesh.num_elements();
  const int part_offset = static_cast<int>(mesh.parts.size());
  for (const auto& name : other.parts)
    for (const auto& existing : mesh.parts)
      if (existing == name) throw std::invalid_argument("part '" + name + "' defined twice");
  auto check_names = [](const auto& into, const auto& from, const char* what) {
    for (const auto& [name, unused] : from)
      if (into.count(name)) throw std::invalid_argument(std::string(what) + " '" + name + "' defined twice");
  };
  check_names(mesh.node_sets, other.node_sets, "node set");
  check_names(mesh.element_sets, other.element_sets, "element set");
  check_names(mesh.surfaces, other.surfaces, "surface");

  Eigen::Matrix3Xd coordinates(3, node_offset + other.num_nodes());
  coordinates << mesh.coordinates, other.coordinates;
  mesh.coordinates = std::move(coordinates);
  mesh.node_ids.insert(mesh.node_ids.end(), other.node_ids.begin(), other.node_ids.end());
  for (Element element : other.elements) {
    element.part += part_offset;
    for (int& n : element.nodes) n += node_offset;
    mesh.elements.push_back(element);
  }
  mesh.element_ids.insert(mesh.element_ids.end(), other.element_ids.begin(),
                          other.element_ids.end());
  mesh.parts.insert(mesh.parts.end(), other.parts.begin(), other.parts.end());
  for (auto [name, nodes] : other.node_sets) {
    for (int& n : nodes) n += node_offset;
    mesh.node_sets.emplace(name, std::move(nodes));
  }
  for (auto [name, elements] : other.element_sets) {
    for (int& e : elements) e += element_offset;
    mesh.element_sets.emplace(name, std::move(elements));
  }
  for (auto [name, faces] : other.surfaces) {
    for (Face& f : faces) f.element += element_offset;
    mesh.surfaces.emplace(name, std::move(faces));
  }
}

std::string element_name(const Mesh& mesh, int e) {
  const auto i = static_cast<std::size_t>(e);
  std::string name = i < mesh.element_ids.size() ? fmt::format("element {}", mesh.element_ids[i])
                                                 : fmt::format("element #{}", e);
  const int part = i < mesh.elements.size() ? mesh.elements[i].part : -1;
  if (part >= 0 && static_cast<std::size_t>(part) < mesh.parts.size())
    name += " of part " + mesh.parts[static_cast<std::size_t>(part)];
  return name;
}

}  // namespace jointhb::fe
