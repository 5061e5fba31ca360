// Box meshes of tetrahedra and wedges (box_mesh.hpp).
//
// Every cell of the structured grid is split the same way, so neighbouring cells share their
// face diagonals and the mesh is conforming:
//   tetrahedra: Kuhn's (Freudenthal's) split into 6 tetrahedra around the diagonal from the
//     cell's least corner to its greatest, one per permutation π of the axes:
//     (0, e_π1, e_π1 + e_π2, e_π1 + e_π2 + e_π3) (Kuhn 1960; Bey, "Simplicial grid refinement",
//     BIT 40 (2000) 1–25), two corners swapped where needed for a positive volume;
//   wedges: the cell's bottom square split along its diagonal from (0, 0) to (1, 1) into the
//     triangles (00, 10, 11) and (00, 11, 01), each extruded along z.
// Quadratic types get a node at the middle of every edge (edge_corners of mesh.hpp). Nodes are
// numbered in lattice order (x fastest, then y, then z) over a lattice of half cells.

#include "box_mesh_split.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace jointhb::fe::detail {

namespace {

using Point = std::array<int, 3>;  // lattice index in half cells

// The corners (offsets in half cells from the cell's least corner) of the sub-elements of a cell.
std::vector<std::vector<Point>> cell_split(ElementType type) {
  std::vector<std::vector<Point>> elements;
  if (family(type) == ElementFamily::tetrahedron) {
    std::array<int, 3> axes = {0, 1, 2};
    do {
      std::vector<Point> corners(4, Point{0, 0, 0});
      for (std::size_t c = 1; c < 4; ++c) {
        corners[c] = corners[c - 1];
        corners[c][static_cast<std::size_t>(axes[c - 1])] = 2;
      }
      // Signed volume: det [v1 − v0, v2 − v0, v3 − v0] (v0 = 0); odd permutations are negative.
      const auto det = [&] {
        const Point &a = corners[1], &b = corners[2], &c = corners[3];
        return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
               a[2] * (b[0] * c[1] - b[1] * c[0]);
      }();
      if (det < 0) std::swap(corners[1], corners[2]);
      elements.push_back(corners);
    } while (std::next_permutation(axes.begin(), axes.end()));
    return elements;
  }
  const std::array<std::array<Point, 3>, 2> triangles = {
      {{Point{0, 0, 0}, Point{2, 0, 0}, Point{2, 2, 0}},
       {Point{0, 0, 0}, Point{2, 2, 0}, Point{0, 2, 0}}}};
  for (const auto& triangle : triangles) {
    std::vector<Point> corners(triangle.begin(), triangle.end());
    for (const Point& p : triangle) corners.push_back({p[0], p[1], 2});
    elements.push_back(corners);
  }
  return elements;
}

// Corners then (quadratic types) the mid-edge points, in the local numbering of mesh.hpp.
std::vector<Point> with_mid_edges(ElementType type, std::vector<Point> points) {
  if (!is_quadratic(type)) return points;
  for (const auto& [a, b] : edge_corners(type)) {
    Point mid{};
    for (std::size_t d = 0; d < 3; ++d)
      mid[d] = (points[static_cast<std::size_t>(a)][d] + points[static_cast<std::size_t>(b)][d]) / 2;
    points.push_back(mid);
  }
  return points;
}

const std::array<const char*, 6> kSideNames = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};

}  // namespace

Mesh split_box_mesh(const BoxOptions& options) {
  const ElementType type = options.type;
  std::array<int, 3> points{};  // half-cell lattice points along each axis
  for (std::size_t d = 0; d < 3; ++d) points[d] = 2 * options.divisions[d] + 1;
  const auto lattice_index = [&](const Point& p) {
    return (static_cast<std::size_t>(p[2]) * static_cast<std::size_t>(points[1]) +
            static_cast<std::size_t>(p[1])) *
               static_cast<std::size_t>(points[0]) +
           static_cast<std::size_t>(p[0]);
  };

  // Elements as lattice points, then the used points numbered in lattice order.
  const std::vector<std::vector<Point>> split = cell_split(type);
  std::vector<std::vector<Point>> element_points;
  for (int ek = 0; ek < options.divisions[2]; ++ek)
    for (int ej = 0; ej < options.divisions[1]; ++ej)
      for (int ei = 0; ei < options.divisions[0]; ++ei)
        for (const std::vector<Point>& corners : split) {
          std::vector<Point> shifted = corners;
          for (Point& p : shifted) p = {p[0] + 2 * ei, p[1] + 2 * ej, p[2] + 2 * ek};
          element_points.push_back(with_mid_edges(type, shifted));
        }
  std::vector<int> node_at(lattice_index({0, 0, points[2]}), -1);
  for (const auto& element : element_points)
    for (const Point& p : element) node_at[lattice_index(p)] = 0;

  Mesh mesh;
  mesh.parts = {options.part};
  std::vector<Point> node_points;
  for (int k = 0; k < points[2]; ++k)
    for (int j = 0; j < points[1]; ++j)
      for (int i = 0; i < points[0]; ++i) {
        int& node = node_at[lattice_index({i, j, k})];
        if (node < 0) continue;
        node = static_cast<int>(node_points.size());
        node_points.push_back({i, j, k});
      }
  mesh.coordinates.resize(3, static_cast<Eigen::Index>(node_points.size()));
  for (std::size_t n = 0; n < node_points.size(); ++n) {
    for (std::size_t d = 0; d < 3; ++d) {
      const auto dd = static_cast<Eigen::Index>(d);
      mesh.coordinates(dd, static_cast<Eigen::Index>(n)) =
          options.origin[dd] + options.size[dd] * node_points[n][d] / (points[d] - 1);
    }
    mesh.node_ids.push_back(static_cast<long>(n) + 1);
  }
  for (const auto& element_point : element_points) {
    Element element;
    element.type = type;
    for (std::size_t a = 0; a < element_point.size(); ++a)
      element.nodes[a] = node_at[lattice_index(element_point[a])];
    mesh.element_ids.push_back(static_cast<long>(mesh.elements.size()) + 1);
    mesh.elements.push_back(element);
  }
  std::vector<int> all(mesh.elements.size());
  for (std::size_t e = 0; e < all.size(); ++e) all[e] = static_cast<int>(e);
  mesh.element_sets[options.part] = std::move(all);

  // Sides: side s lies on axis s / 2 at its least (even s) or greatest lattice index.
  for (std::size_t s = 0; s < 6; ++s) {
    const std::size_t axis = s / 2;
    const int at = s % 2 == 0 ? 0 : points[axis] - 1;
    const std::string name = options.part + "." + kSideNames[s];
    std::vector<int>& nodes = mesh.node_sets[name];
    for (std::size_t n = 0; n < node_points.size(); ++n)
      if (node_points[n][axis] == at) nodes.push_back(static_cast<int>(n));
    std::vector<Face>& faces = mesh.surfaces[name];
    for (int e = 0; e < mesh.num_elements(); ++e) {
      const auto& element_point = element_points[static_cast<std::size_t>(e)];
      for (int f = 0; f < face_count(type); ++f) {
        const auto local = face_local_nodes(type, f);
        const bool on_side = std::all_of(local.begin(), local.end(), [&](int a) {
          return element_point[static_cast<std::size_t>(a)][axis] == at;
        });
        if (on_side) faces.push_back({e, f});
      }
    }
  }
  return mesh;
}

}  // namespace jointhb::fe::detail
