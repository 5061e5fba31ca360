#include "jointhb/fe/mesh.hpp"

#include <stdexcept>

namespace jointhb::fe {

int node_count(ElementType type) {
  return (type == ElementType::hex20 || type == ElementType::hex20_reduced) ? 20 : 8;
}

int face_node_count(ElementType type) { return node_count(type) == 20 ? 8 : 4; }

const char* abaqus_name(ElementType type) {
  switch (type) {
    case ElementType::hex8: return "C3D8";
    case ElementType::hex8_incompatible: return "C3D8I";
    case ElementType::hex20: return "C3D20";
    case ElementType::hex20_reduced: return "C3D20R";
  }
  return "?";
}

std::optional<ElementType> element_type_of_abaqus_name(std::string_view name) {
  for (ElementType type : {ElementType::hex8, ElementType::hex8_incompatible, ElementType::hex20,
                           ElementType::hex20_reduced})
    if (name == abaqus_name(type)) return type;
  return std::nullopt;
}

const std::array<std::array<int, 2>, 12>& hex_edge_corners() {
  static constexpr std::array<std::array<int, 2>, 12> edges = {
      {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}}};
  return edges;
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
}  // namespace

std::span<const int> face_local_nodes(ElementType type, int face) {
  if (face < 0 || face > 5) throw std::out_of_range("face index must be 0..5");
  return {kFaces[static_cast<std::size_t>(face)].data(),
          static_cast<std::size_t>(face_node_count(type))};
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
  for (int local : face_local_nodes(element.type, face.face).first(4))
    centre += mesh.coordinates.col(element.nodes[static_cast<std::size_t>(local)]);
  return centre / 4.0;
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

}  // namespace jointhb::fe
