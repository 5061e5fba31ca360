#pragma once
// A structured mesh of an axis-aligned box: one part, hex8 or hex20 elements (hex20 with one
// shared mid-edge node per edge), or each hexahedral cell split into 6 tetrahedra or 2 wedges
// (tet4, tet10, wedge6, wedge15: box_mesh_split.cpp), and its six sides as node sets and surfaces.
//
// Names: the part, its element set, and the sides "<part>.xmin", "<part>.xmax", "<part>.ymin",
// "<part>.ymax", "<part>.zmin", "<part>.zmax" — each a node set (every node on the side, mid-edge
// nodes included) and a surface (the element faces on the side, outward normals).
// Numbering: nodes x fastest, then y, then z; elements likewise (the 6 or 2 elements of a cell
// together); external ids are index + 1.
// Separate boxes stay separate when appended (fe::append): interfaces are joined by contact
// elements, never by merging nodes.

#include <Eigen/Core>
#include <array>
#include <string>

#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

struct BoxOptions {
  std::string part = "box";                           ///< part name, non-empty
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   ///< [m] corner of least x, y, z; finite
  Eigen::Vector3d size = Eigen::Vector3d::Ones();     ///< [m] edge lengths along x, y, z; > 0
  std::array<int, 3> divisions = {1, 1, 1};           ///< elements along x, y, z; >= 1
  ElementType type = ElementType::hex8_incompatible;  ///< any ElementType

  /// Empty when valid, else "field: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

/// The box mesh. Throws std::invalid_argument("box_mesh: " + validate()) for invalid options.
[[nodiscard]] Mesh box_mesh(const BoxOptions& options);

}  // namespace jointhb::fe
