#include "jointhb/fe/box_mesh.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "box_mesh_split.hpp"

namespace jointhb::fe {

std::string BoxOptions::validate() const {
  if (part.empty()) return "part: must be a non-empty name";
  constexpr const char* axes = "xyz";
  for (int d = 0; d < 3; ++d) {
    if (!std::isfinite(origin[d])) {
      return fmt::format("origin.{}: must be finite, got {}", axes[d], origin[d]);
    }
    if (!(size[d] > 0.0) || !std::isfinite(size[d])) {
      return fmt::format("size.{}: must be finite and > 0, got {}", axes[d], size[d]);
    }
    if (divisions[static_cast<std::size_t>(d)] < 1) {
      return fmt::format("divisions.{}: must be >= 1, got {}", axes[d],
                         divisions[static_cast<std::size_t>(d)]);
    }
  }
  return {};
}

namespace {

// The mesh lives on a lattice of "steps" points per element edge (1 for hex8, 2 for hex20: the
// mid-edge nodes sit on odd lattice indices). A hex20 node has at most one odd index; lattice
// points with two or three odd indices (face and cell centres) are not nodes.
//
// Lattice offsets of the element's local nodes (mesh.hpp numbering), in units of half an element.
constexpr std::array<std::array<int, 3>, 20> kLocalOffsets = {{
    {0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0},  // corners ζ = -1
    {0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2},  // corners ζ = +1
    {1, 0, 0}, {2, 1, 0}, {1, 2, 0}, {0, 1, 0},  // mid-edges ζ = -1
    {1, 0, 2}, {2, 1, 2}, {1, 2, 2}, {0, 1, 2},  // mid-edges ζ = +1
    {0, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1},  // vertical mid-edges
}};

// Faces S1..S6 (0-based) lying on each side of an element: zmin, zmax, ymin, xmax, ymax, xmin.
struct Side {
  const char* suffix;
  int axis;
  bool at_max;
  int face;
};
constexpr std::array<Side, 6> kSides = {{
    {"xmin", 0, false, 5},
    {"xmax", 0, true, 3},
    {"ymin", 1, false, 2},
    {"ymax", 1, true, 4},
    {"zmin", 2, false, 0},
    {"zmax", 2, true, 1},
}};

}  // namespace

Mesh box_mesh(const BoxOptions& options) {
  if (const std::string message = options.validate(); !message.empty()) {
    throw std::invalid_argument("box_mesh: " + message);
  }
  if (family(options.type) != ElementFamily::hexahedron) return detail::split_box_mesh(options);
  const int n_local = node_count(options.type);
  const int steps = n_local == 20 ? 2 : 1;
  std::array<int, 3> points{};  // lattice points along each axis
  for (std::size_t d = 0; d < 3; ++d) points[d] = steps * options.divisions[d] + 1;
  const auto lattice_index = [&](int i, int j, int k) {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(points[1]) +
            static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(points[0]) +
           static_cast<std::size_t>(i);
  };

  Mesh mesh;
  mesh.parts = {options.part};
  std::vector<int> node_at(lattice_index(0, 0, points[2]), -1);
  std::vector<Eigen::Vector3d> coordinates;
  for (int k = 0; k < points[2]; ++k) {
    for (int j = 0; j < points[1]; ++j) {
      for (int i = 0; i < points[0]; ++i) {
        if (steps == 2 && (i % 2) + (j % 2) + (k % 2) > 1) continue;
        node_at[lattice_index(i, j, k)] = static_cast<int>(coordinates.size());
        Eigen::Vector3d x;
        const std::array<int, 3> index = {i, j, k};
        for (std::size_t d = 0; d < 3; ++d) {
          x[static_cast<Eigen::Index>(d)] =
              options.origin[static_cast<Eigen::Index>(d)] +
              options.size[static_cast<Eigen::Index>(d)] * index[d] / (points[d] - 1);
        }
        coordinates.push_back(x);
      }
    }
  }
  mesh.coordinates.resize(3, static_cast<Eigen::Index>(coordinates.size()));
  for (std::size_t n = 0; n < coordinates.size(); ++n) {
    mesh.coordinates.col(static_cast<Eigen::Index>(n)) = coordinates[n];
    mesh.node_ids.push_back(static_cast<long>(n) + 1);
  }

  const auto& divisions = options.divisions;
  for (int ek = 0; ek < divisions[2]; ++ek) {
    for (int ej = 0; ej < divisions[1]; ++ej) {
      for (int ei = 0; ei < divisions[0]; ++ei) {
        Element element;
        element.type = options.type;
        element.part = 0;
        for (std::size_t local = 0; local < static_cast<std::size_t>(n_local); ++local) {
          // kLocalOffsets is in half-elements; hex8 lattices have one step per element.
          const auto& o = kLocalOffsets[local];
          const int half = 2 / steps;
          element.nodes[local] = node_at[lattice_index(
              steps * ei + o[0] / half, steps * ej + o[1] / half, steps * ek + o[2] / half)];
        }
        mesh.element_ids.push_back(static_cast<long>(mesh.elements.size()) + 1);
        mesh.elements.push_back(element);
      }
    }
  }
  std::vector<int> all_elements(mesh.elements.size());
  for (std::size_t e = 0; e < all_elements.size(); ++e) all_elements[e] = static_cast<int>(e);
  mesh.element_sets[options.part] = std::move(all_elements);

  for (const Side& side : kSides) {
    const std::string name = options.part + "." + side.suffix;
    const auto axis = static_cast<std::size_t>(side.axis);
    std::vector<int>& nodes = mesh.node_sets[name];
    for (int k = 0; k < points[2]; ++k) {
      for (int j = 0; j < points[1]; ++j) {
        for (int i = 0; i < points[0]; ++i) {
          const std::array<int, 3> index = {i, j, k};
          const int node = node_at[lattice_index(i, j, k)];
          if (node >= 0 && index[axis] == (side.at_max ? points[axis] - 1 : 0)) {
            nodes.push_back(node);
          }
        }
      }
    }
    std::vector<Face>& faces = mesh.surfaces[name];
    for (int ek = 0; ek < divisions[2]; ++ek) {
      for (int ej = 0; ej < divisions[1]; ++ej) {
        for (int ei = 0; ei < divisions[0]; ++ei) {
          const std::array<int, 3> index = {ei, ej, ek};
          if (index[axis] != (side.at_max ? divisions[axis] - 1 : 0)) continue;
          const int element = (ek * divisions[1] + ej) * divisions[0] + ei;
          faces.push_back({element, side.face});
        }
      }
    }
  }
  return mesh;
}

}  // namespace jointhb::fe
