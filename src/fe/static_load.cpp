#include "jointhb/fe/static_load.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace jointhb::fe {

namespace {

struct FacePoint {
  double xi = 0.0, eta = 0.0, weight = 0.0;
};

// The rules of static_load.hpp: Gauss 2×2 / 3×3 on [−1, 1]², the 3-point degree-2 and
// Dunavant's 6-point degree-4 rules on the unit triangle (weights sum to its area ½).
std::vector<FacePoint> face_rule(int nodes) {
  if (nodes == 4 || nodes == 8) {
    const double a = 1.0 / std::sqrt(3.0), b = std::sqrt(0.6);
    const std::vector<std::pair<double, double>> line =
        nodes == 4 ? std::vector<std::pair<double, double>>{{-a, 1.0}, {a, 1.0}}
                   : std::vector<std::pair<double, double>>{{-b, 5.0 / 9.0}, {0.0, 8.0 / 9.0}, {b, 5.0 / 9.0}};
    std::vector<FacePoint> rule;
    for (const auto& [eta, we] : line)
      for (const auto& [xi, wx] : line) rule.push_back({xi, eta, wx * we});
    return rule;
  }
  if (nodes == 3) {
    return {{1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0}, {2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0},
            {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0}};
  }
  // Dunavant (1985), p = 4: two orbits of three points.
  const double a = 0.445948490915965, wa = 0.5 * 0.223381589678011;
  const double b = 0.091576213509771, wb = 0.5 * 0.109951743655322;
  return {{a, a, wa}, {1.0 - 2.0 * a, a, wa}, {a, 1.0 - 2.0 * a, wa},
          {b, b, wb}, {1.0 - 2.0 * b, b, wb}, {b, 1.0 - 2.0 * b, wb}};
}

// Shape functions of the face (static_load.hpp) and their derivatives: row 0 N, row 1 ∂N/∂ξ,
// row 2 ∂N/∂η.
Eigen::Matrix3Xd face_shape(int nodes, double xi, double eta) {
  Eigen::Matrix3Xd s(3, nodes);
  if (nodes == 4 || nodes == 8) {
    static constexpr std::array<double, 4> cx = {-1.0, 1.0, 1.0, -1.0}, cy = {-1.0, -1.0, 1.0, 1.0};
    for (int a = 0; a < 4; ++a) {
      const double x = cx[static_cast<std::size_t>(a)], y = cy[static_cast<std::size_t>(a)];
      const double fx = 1.0 + xi * x, fy = 1.0 + eta * y;
      if (nodes == 4) {
        s.col(a) << 0.25 * fx * fy, 0.25 * x * fy, 0.25 * y * fx;
      } else {
        const double g = xi * x + eta * y - 1.0;
        s.col(a) << 0.25 * fx * fy * g, 0.25 * x * fy * (g + fx), 0.25 * y * fx * (g + fy);
      }
    }
    if (nodes == 8) {
      for (int k = 0; k < 4; ++k) {  // mid-edge node between corners k and k+1
        const auto c0 = static_cast<std::size_t>(k), c1 = static_cast<std::size_t>((k + 1) % 4);
        if (cx[c0] != cx[c1]) {  // ξ_a = 0 on a horizontal edge, η_a = ±1
          const double y = cy[c0];
          s.col(4 + k) << 0.5 * (1.0 - xi * xi) * (1.0 + eta * y), -xi * (1.0 + eta * y),
              0.5 * (1.0 - xi * xi) * y;
        } else {  // η_a = 0, ξ_a = ±1
          const double x = cx[c0];
          s.col(4 + k) << 0.5 * (1.0 + xi * x) * (1.0 - eta * eta), 0.5 * x * (1.0 - eta * eta),
              -(1.0 + xi * x) * eta;
        }
      }
    }
    return s;
  }
  // Area coordinates L0 = 1 − ξ − η, L1 = ξ, L2 = η and their (ξ, η) derivatives.
  const std::array<double, 3> L = {1.0 - xi - eta, xi, eta};
  static constexpr std::array<double, 3> dx = {-1.0, 1.0, 0.0}, dy = {-1.0, 0.0, 1.0};
  for (std::size_t a = 0; a < 3; ++a) {
    const auto col = static_cast<Eigen::Index>(a);
    if (nodes == 3) {
      s.col(col) << L[a], dx[a], dy[a];
    } else {
      s.col(col) << L[a] * (2.0 * L[a] - 1.0), (4.0 * L[a] - 1.0) * dx[a], (4.0 * L[a] - 1.0) * dy[a];
    }
  }
  if (nodes == 6) {
    for (std::size_t k = 0; k < 3; ++k) {  // mid-edge node between corners k and k+1
      const std::size_t m = (k + 1) % 3;
      s.col(static_cast<Eigen::Index>(3 + k)) << 4.0 * L[k] * L[m], 4.0 * (dx[k] * L[m] + L[k] * dx[m]),
          4.0 * (dy[k] * L[m] + L[k] * dy[m]);
    }
  }
  return s;
}

}  // namespace

Eigen::Matrix3Xd face_pressure_forces(const Eigen::Matrix3Xd& x, double pressure) {
  const int k = static_cast<int>(x.cols());
  if (k != 3 && k != 4 && k != 6 && k != 8)
    throw std::invalid_argument(fmt::format("pressure load: a face has {} nodes (3, 4, 6 or 8 expected)", k));
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, k);
  for (const FacePoint& q : face_rule(k)) {
    const Eigen::Matrix3Xd s = face_shape(k, q.xi, q.eta);
    const Eigen::Vector3d dx_dxi = x * s.row(1).transpose();
    const Eigen::Vector3d dx_deta = x * s.row(2).transpose();
    const Eigen::Vector3d n_dA = dx_dxi.cross(dx_deta);  // n dA / (dξ dη), eq. (L-1)
    for (int a = 0; a < k; ++a) f.col(a) -= pressure * q.weight * s(0, a) * n_dA;
  }
  return f;
}

Eigen::VectorXd static_load_vector(const Mesh& mesh, const StaticLoads& loads) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(mesh.num_dofs());
  for (const NodalForces& load : loads.forces) {
    if (!load.force.allFinite())
      throw std::invalid_argument(fmt::format("{}: the force is not finite", load.label));
    for (int node : load.nodes) {
      if (node < 0 || node >= mesh.num_nodes())
        throw std::invalid_argument(fmt::format("{}: node index {} is outside the mesh", load.label, node));
      f.segment<3>(3 * node) += load.force;
    }
  }
  for (const SurfacePressure& load : loads.pressures) {
    if (!std::isfinite(load.pressure))
      throw std::invalid_argument(fmt::format("{}: the pressure is not finite", load.label));
    for (const Face& face : load.faces) {
      if (face.element < 0 || face.element >= mesh.num_elements())
        throw std::invalid_argument(fmt::format("{}: element index {} is outside the mesh", load.label, face.element));
      const std::vector<int> nodes = face_nodes(mesh, face);
      Eigen::Matrix3Xd x(3, static_cast<Eigen::Index>(nodes.size()));
      for (std::size_t a = 0; a < nodes.size(); ++a) x.col(static_cast<Eigen::Index>(a)) = mesh.coordinates.col(nodes[a]);
      const Eigen::Matrix3Xd fa = face_pressure_forces(x, load.pressure);
      for (std::size_t a = 0; a < nodes.size(); ++a) f.segment<3>(3 * nodes[a]) += fa.col(static_cast<Eigen::Index>(a));
    }
  }
  return f;
}

LoadResultant load_resultant(const Mesh& mesh, const Eigen::VectorXd& load) {
  LoadResultant r;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Eigen::Vector3d fi = load.segment<3>(3 * i);
    r.force += fi;
    r.moment += mesh.coordinates.col(i).cross(fi);
  }
  return r;
}

std::string equilibrium_problem(const Mesh& mesh, const Eigen::VectorXd& load) {
  const double total = load.cwiseAbs().sum();
  if (total == 0.0) return {};
  const Eigen::Vector3d centre = mesh.coordinates.rowwise().mean();
  const double size = (mesh.coordinates.colwise() - centre).colwise().norm().maxCoeff();
  const LoadResultant r = load_resultant(mesh, load);
  const Eigen::Vector3d moment = r.moment - centre.cross(r.force);  // about the centre
  if (r.force.norm() <= 1e-9 * total && moment.norm() <= 1e-9 * total * std::max(size, 1e-300)) return {};
  return fmt::format("a resultant force of {:.6g} N and a moment of {:.6g} N m about the mesh centre",
                     r.force.norm(), moment.norm());
}

}  // namespace jointhb::fe
