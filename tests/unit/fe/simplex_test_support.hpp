#pragma once
// Helpers of the tetrahedron and wedge tests: distorted box meshes of any type, the linear patch
// test and the free-free axial frequency of a bar (closed form with ν = 0).

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <random>
#include <set>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/fe/material.hpp"
#include "jointhb/fe/mesh.hpp"
#include "jointhb/fe/solid_element.hpp"

namespace jointhb::fe::testing {

inline Material steel(double poisson = 0.3) {
  Material m;
  m.youngs_modulus = 210e9;
  m.poissons_ratio = poisson;
  m.density = 7800.0;
  return m;
}

/// box_mesh of `type` on [0, size] with `divisions`.
inline Mesh box_of(ElementType type, const Eigen::Vector3d& size, std::array<int, 3> divisions) {
  BoxOptions o;
  o.type = type;
  o.size = size;
  o.divisions = divisions;
  return box_mesh(o);
}

/// Moves every corner node strictly inside the bounding box by up to `amount` × the smallest
/// cell size per axis (random, reproducible), then puts every mid-edge node back at the middle of
/// its straight edge.
inline void distort_mesh(Mesh& mesh, const std::array<int, 3>& divisions, double amount,
                         unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  const Eigen::Vector3d lo = mesh.coordinates.rowwise().minCoeff();
  const Eigen::Vector3d hi = mesh.coordinates.rowwise().maxCoeff();
  std::set<int> corners;
  for (const Element& e : mesh.elements)
    for (int a = 0; a < corner_count(e.type); ++a) corners.insert(e.nodes[static_cast<std::size_t>(a)]);
  for (int n : corners) {
    bool interior = true;
    for (int d = 0; d < 3; ++d)
      if (std::abs(mesh.coordinates(d, n) - lo(d)) < 1e-12 ||
          std::abs(mesh.coordinates(d, n) - hi(d)) < 1e-12)
        interior = false;
    if (!interior) continue;
    for (int d = 0; d < 3; ++d)
      mesh.coordinates(d, n) += u(gen) * (hi(d) - lo(d)) / divisions[static_cast<std::size_t>(d)];
  }
  for (const Element& e : mesh.elements) {
    if (!is_quadratic(e.type)) continue;
    const auto edges = edge_corners(e.type);
    for (std::size_t k = 0; k < edges.size(); ++k) {
      const auto node = [&](int a) { return e.nodes[static_cast<std::size_t>(a)]; };
      mesh.coordinates.col(node(corner_count(e.type) + static_cast<int>(k))) =
          0.5 * (mesh.coordinates.col(node(edges[k][0])) + mesh.coordinates.col(node(edges[k][1])));
    }
  }
}

/// The element's nodal coordinates, 3 × n.
inline Eigen::Matrix3Xd element_coordinates(const Mesh& mesh, int e) {
  const Element& element = mesh.elements[static_cast<std::size_t>(e)];
  Eigen::Matrix3Xd x(3, node_count(element.type));
  for (int a = 0; a < node_count(element.type); ++a)
    x.col(a) = mesh.coordinates.col(element.nodes[static_cast<std::size_t>(a)]);
  return x;
}

struct PatchResult {
  double displacement_error = 0.0;  ///< max |u − u_exact| over the free nodes / max |u_exact|
  double stress_error = 0.0;        ///< max |σ_centre − σ_exact| / max |σ_exact| over elements
};

/// Patch test (Zienkiewicz, Taylor & Zhu §9.3): u = A x + b prescribed on the boundary nodes of
/// the box, K u = 0 solved for the interior ones.
inline PatchResult patch_test(const Mesh& mesh, const Material& material) {
  Eigen::Matrix3d a;
  a << 1.0, 0.4, -0.3, 0.2, -0.7, 0.5, 0.6, 0.1, 0.9;
  a *= 1e-3;
  const Eigen::Vector3d b(1e-4, -2e-4, 3e-4);
  const auto exact = [&](int n) -> Eigen::Vector3d { return a * mesh.coordinates.col(n) + b; };
  const Eigen::Vector3d lo = mesh.coordinates.rowwise().minCoeff();
  const Eigen::Vector3d hi = mesh.coordinates.rowwise().maxCoeff();
  std::vector<FixedNodes> fixed(1);
  for (int n = 0; n < mesh.num_nodes(); ++n)
    for (int d = 0; d < 3; ++d)
      if (std::abs(mesh.coordinates(d, n) - lo(d)) < 1e-12 ||
          std::abs(mesh.coordinates(d, n) - hi(d)) < 1e-12) {
        fixed[0].nodes.push_back(n);
        break;
      }
  const StructuralMatrices m = assemble(mesh, {material});
  const DofMap map = DofMap::from_fixed_nodes(mesh.num_nodes(), fixed);
  Eigen::VectorXd prescribed = Eigen::VectorXd::Zero(mesh.num_dofs());
  for (int n : fixed[0].nodes) prescribed.segment<3>(3 * n) = exact(n);
  // K_ff u_f = −K_fp u_p, with K u_p restricted to the free rows.
  const Eigen::VectorXd rhs = -map.restrict(Eigen::VectorXd(m.stiffness * prescribed));
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(map.restrict(m.stiffness));
  const Eigen::VectorXd u = prescribed + map.expand(solver.solve(rhs));
  PatchResult r;
  double scale = 0.0;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    scale = std::max(scale, exact(n).norm());
    r.displacement_error = std::max(r.displacement_error, (u.segment<3>(3 * n) - exact(n)).norm());
  }
  r.displacement_error /= scale;
  Vector6d strain;
  strain << a(0, 0), a(1, 1), a(2, 2), a(0, 1) + a(1, 0), a(1, 2) + a(2, 1), a(2, 0) + a(0, 2);
  const Vector6d sigma = elasticity_matrix(material) * strain;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const Element& element = mesh.elements[static_cast<std::size_t>(e)];
    Eigen::VectorXd ue(3 * node_count(element.type));
    for (int k = 0; k < node_count(element.type); ++k)
      ue.segment<3>(3 * k) = u.segment<3>(3 * element.nodes[static_cast<std::size_t>(k)]);
    const Vector6d s =
        element_centre_stress(element.type, element_coordinates(mesh, e), material, ue);
    r.stress_error = std::max(r.stress_error, (s - sigma).cwiseAbs().maxCoeff());
  }
  r.stress_error /= sigma.cwiseAbs().maxCoeff();
  return r;
}

/// First axial frequency [Hz] of a free-free bar [0, length] × [0, b]² meshed with `n` cells along
/// x and 1 × 1 across, ν = 0 and u_y = u_z = 0 everywhere; closed form f = c / (2 L), c = √(E/ρ)
/// (with ν = 0 the 3-D solution u_x = cos(π x / L) has no lateral strain: exact).
struct AxialFrequency {
  double computed = 0.0;
  double exact = 0.0;
  [[nodiscard]] double relative_error() const { return std::abs(computed - exact) / exact; }
};

inline AxialFrequency axial_frequency(ElementType type, int n, double length = 1.0,
                                      double b = 0.1) {
  const Material material = steel(0.0);
  const Mesh mesh = box_of(type, {length, b, b}, {n, 1, 1});
  const StructuralMatrices m = assemble(mesh, {material});
  // The x DOFs only (every u_y, u_z fixed).
  std::vector<FixedNodes> fixed(1);
  fixed[0].directions = {false, true, true};
  for (int i = 0; i < mesh.num_nodes(); ++i) fixed[0].nodes.push_back(i);
  const DofMap map = DofMap::from_fixed_nodes(mesh.num_nodes(), fixed);
  const Eigen::MatrixXd k = Eigen::MatrixXd(map.restrict(m.stiffness));
  const Eigen::MatrixXd mm = Eigen::MatrixXd(map.restrict(m.mass));
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, mm);
  AxialFrequency f;
  f.computed = std::sqrt(std::max(eig.eigenvalues()(1), 0.0)) / (2.0 * M_PI);  // (0): translation
  f.exact = std::sqrt(material.youngs_modulus / material.density) / (2.0 * length);
  return f;
}

}  // namespace jointhb::fe::testing
