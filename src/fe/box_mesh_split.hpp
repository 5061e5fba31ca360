#pragma once
// Internal: the box mesh of box_mesh.hpp for tetrahedra and wedges, each lattice cell split into
// 6 tetrahedra or 2 wedges.

#include "jointhb/fe/box_mesh.hpp"

namespace jointhb::fe::detail {

/// box_mesh for a tetrahedron or wedge type (options already validated).
[[nodiscard]] Mesh split_box_mesh(const BoxOptions& options);

}  // namespace jointhb::fe::detail
