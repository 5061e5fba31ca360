#pragma once
// A tiny structured box mesh for the FE unit tests only (the library's own generator lives
// elsewhere): [0, lx] × [0, ly] × [0, lz] split into nx × ny × nz hexahedra of one type, plus
// helpers to distort interior nodes, impose tractions and find nodes by position.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <tuple>

#include "jointhb/fe/hexahedron.hpp"
#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe::testing {

struct TestBox {
  Mesh mesh;
  std::vector<std::array<int, 3>> grid;  // grid index of node i on the (2n + 1)-point lattice
  std::array<int, 3> cells{};
};

inline TestBox make_test_box(ElementType type, double lx, double ly, double lz, int nx, int ny,
                             int nz) {
  TestBox box;
  box.cells = {nx, ny, nz};
  box.mesh.parts = {"box"};
  std::map<std::tuple<int, int, int>, int> index;
  std::vector<Eigen::Vector3d> points;
  auto node_at = [&](int i, int j, int k) {
    const auto key = std::make_tuple(i, j, k);
    if (auto it = index.find(key); it != index.end()) return it->second;
    const int id = static_cast<int>(points.size());
    index.emplace(key, id);
    points.emplace_back(lx * i / (2.0 * nx), ly * j / (2.0 * ny), lz * k / (2.0 * nz));
    box.grid.push_back({i, j, k});
    return id;
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        Element element;
        element.type = type;
        for (int a = 0; a < node_count(type); ++a) {
          const Eigen::Vector3d xi = hex_node_natural_coordinates(a);
          element.nodes[static_cast<std::size_t>(a)] =
              node_at(2 * i + 1 + static_cast<int>(xi(0)), 2 * j + 1 + static_cast<int>(xi(1)),
                      2 * k + 1 + static_cast<int>(xi(2)));
        }
        box.mesh.elements.push_back(element);
        box.mesh.element_ids.push_back(static_cast<long>(box.mesh.elements.size()));
      }
  box.mesh.coordinates.resize(3, static_cast<Eigen::Index>(points.size()));
  for (std::size_t n = 0; n < points.size(); ++n) {
    box.mesh.coordinates.col(static_cast<Eigen::Index>(n)) = points[n];
    box.mesh.node_ids.push_back(static_cast<long>(n) + 1);
  }
  return box;
}

/// Moves every interior corner-lattice node (all grid indices even, not on the boundary) by a
/// random offset of up to `amount` × cell size per axis, then puts every mid-edge node back at
/// the middle of its (straight) edge. Boundary nodes stay put.
inline void distort_interior(TestBox& box, double amount, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  Mesh& mesh = box.mesh;
  const Eigen::Vector3d extent = mesh.coordinates.rowwise().maxCoeff();
  std::map<std::array<int, 3>, int> of_grid;
  for (std::size_t n = 0; n < box.grid.size(); ++n) of_grid[box.grid[n]] = static_cast<int>(n);
  for (std::size_t n = 0; n < box.grid.size(); ++n) {
    const auto& g = box.grid[n];
    bool interior = true, corner = true;
    for (int d = 0; d < 3; ++d) {
      const auto dd = static_cast<std::size_t>(d);
      if (g[dd] == 0 || g[dd] == 2 * box.cells[dd]) interior = false;
      if (g[dd] % 2 != 0) corner = false;
    }
    if (!interior || !corner) continue;
    for (int d = 0; d < 3; ++d)
      mesh.coordinates(d, static_cast<Eigen::Index>(n)) +=
          u(gen) * extent(d) / box.cells[static_cast<std::size_t>(d)];
  }
  for (std::size_t n = 0; n < box.grid.size(); ++n) {
    const auto& g = box.grid[n];
    for (std::size_t d = 0; d < 3; ++d)
      if (g[d] % 2 != 0) {
        auto lo = g, hi = g;
        --lo[d];
        ++hi[d];
        mesh.coordinates.col(static_cast<Eigen::Index>(n)) =
            0.5 * (mesh.coordinates.col(of_grid.at(lo)) + mesh.coordinates.col(of_grid.at(hi)));
      }
  }
}

/// Nodes with |x_axis − value| ≤ tol.
inline std::vector<int> nodes_where(const Mesh& mesh, int axis, double value, double tol = 1e-9) {
  std::vector<int> nodes;
  for (int n = 0; n < mesh.num_nodes(); ++n)
    if (std::abs(mesh.coordinates(axis, n) - value) <= tol) nodes.push_back(n);
  return nodes;
}

/// Consistent nodal forces f_a = ∫ N_a t dA of the traction t(x) over the face ξ = +1 of every
/// element whose nodes at ξ = +1 all lie at x = `x_face` (3×3 Gauss on the face).
inline Eigen::VectorXd face_load(const Mesh& mesh, double x_face,
                                 const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& t) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(mesh.num_dofs());
  const double g[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
  const double w[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  for (const Element& element : mesh.elements) {
    const int n = node_count(element.type);
    Eigen::Matrix3Xd x(3, n);
    for (int a = 0; a < n; ++a)
      x.col(a) = mesh.coordinates.col(element.nodes[static_cast<std::size_t>(a)]);
    if (std::abs(x(0, 1) - x_face) > 1e-9 || std::abs(x(0, 6) - x_face) > 1e-9) continue;
    for (int q = 0; q < 3; ++q)
      for (int p = 0; p < 3; ++p) {
        const Eigen::Vector3d xi(1.0, g[p], g[q]);
        const Eigen::VectorXd shape = shape_functions(element.type, xi);
        const Eigen::Matrix3Xd dn = shape_derivatives(element.type, xi);
        const Eigen::Matrix3d j = dn * x.transpose();  // row k = ∂x/∂ξ_k
        const double area = j.row(1).cross(j.row(2)).norm();
        const Eigen::Vector3d traction = t(x * shape);
        for (int a = 0; a < n; ++a)
          f.segment<3>(3 * element.nodes[static_cast<std::size_t>(a)]) +=
              w[p] * w[q] * area * shape(a) * traction;
      }
  }
  return f;
}

}  // namespace jointhb::fe::testing
