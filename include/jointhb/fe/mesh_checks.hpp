#pragma once
// Checks of a Mesh before it is assembled, each problem naming the entity by its external id
// (Mesh::element_ids, Mesh::node_ids), and the connectivity of its elements.
//
// Element shape: the Jacobian determinant det J(ξ) of the map from the reference element is
// sampled at the 8 corners and the centre (hex8) or at the 27 points of the 3×3×3 Gauss rule
// (hex20); at the corners and the centre (tet4, wedge6: det J is constant on a tet4) or at the
// points of the mass rule (tet10: 14 points, wedge15: 7×3; simplex_elements.hpp).
//   ratio = min det J / max |det J| over the sample points
//   inverted:    ratio < -min_jacobian_ratio (a corner folded through, or the node order mirrored)
//   degenerate:  -min_jacobian_ratio ≤ ratio < min_jacobian_ratio (collapsed edges or faces), or
//                flat: max det J < min_jacobian_ratio · (longest edge / 2)³.

#include <string>
#include <vector>

#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

struct MeshCheckOptions {
  /// (0, 1): smallest accepted min det J / max |det J| (and det J against the longest edge).
  double min_jacobian_ratio = 1e-6;

  /// Empty when valid, else "field: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

struct MeshProblem {
  enum class Kind {
    inconsistent_sizes,  ///< node_ids / element_ids sizes differ from the node / element counts
    bad_part,            ///< Element::part outside Mesh::parts
    node_out_of_range,   ///< an element's node index outside [0, num_nodes)
    repeated_node,       ///< the same node twice in one element
    inverted_element,    ///< det J < 0 somewhere
    degenerate_element,  ///< det J tiny relative to its maximum or to the element's size
    bad_set,             ///< a node set, element set or surface refers to a missing entity
  };
  Kind kind = Kind::inconsistent_sizes;
  int element = -1;     ///< element index, or -1
  std::string message;  ///< one line naming the entity by its external id
};

/// Every problem found (empty: the mesh is fit for assembly). Unused nodes are not problems.
/// Throws std::invalid_argument for invalid options.
[[nodiscard]] std::vector<MeshProblem> check_mesh(const Mesh& mesh,
                                                  const MeshCheckOptions& options = {});

/// min det J / max |det J| over the sample points above (1 for a parallelepiped, negative when
/// inverted, 0 when flat). The element's nodes must be in range.
[[nodiscard]] double jacobian_ratio(const Mesh& mesh, int element);

/// ∫ det J dξ over the reference element [m³]: by the 3×3×3 Gauss rule for hexahedra (exact for
/// hex8 and hex20), by the mass rule for tetrahedra and wedges (exact for tet4, wedge6 and
/// straight-edged tet10 and wedge15).
[[nodiscard]] double element_volume(const Mesh& mesh, int element);

/// Groups of elements connected through shared nodes: each group's element indices ascending,
/// groups ordered by their first element. A mesh of separate parts has at least one group per
/// part; parts that should be joined must be so by contact elements or constraints. Throws
/// std::invalid_argument for a node index out of range.
[[nodiscard]] std::vector<std::vector<int>> connected_components(const Mesh& mesh);

}  // namespace jointhb::fe
