#include "hex_shape.hpp"

#include <cmath>
#include <stdexcept>

namespace jointhb::fe::detail {

namespace {
constexpr std::array<std::array<double, 3>, 20> kReferenceNodes = {{
    {-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},  // corners ζ = -1
    {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1},   // corners ζ = +1
    {0, -1, -1},  {1, 0, -1},  {0, 1, -1}, {-1, 0, -1},  // mid-edges ζ = -1
    {0, -1, 1},   {1, 0, 1},   {0, 1, 1},  {-1, 0, 1},   // mid-edges ζ = +1
    {-1, -1, 0},  {1, -1, 0},  {1, 1, 0},  {-1, 1, 0},   // vertical mid-edges
}};
}  // namespace

Eigen::Vector3d reference_node(int a) {
  const auto& r = kReferenceNodes.at(static_cast<std::size_t>(a));
  return {r[0], r[1], r[2]};
}

Eigen::Matrix3Xd shape_derivatives(ElementType type, const Eigen::Vector3d& xi) {
  const int n = node_count(type);
  Eigen::Matrix3Xd dn(3, n);
  for (int a = 0; a < n; ++a) {
    const Eigen::Vector3d r = reference_node(a);
    // One factor (1 + ξ_d r_d) per axis, or (1 - ξ_d²) where r_d = 0 (hex20 mid-edge nodes).
    Eigen::Vector3d f;
    Eigen::Vector3d df;
    for (int d = 0; d < 3; ++d) {
      if (r[d] == 0.0) {
        f[d] = 1.0 - xi[d] * xi[d];
        df[d] = -2.0 * xi[d];
      } else {
        f[d] = 1.0 + xi[d] * r[d];
        df[d] = r[d];
      }
    }
    if (n == 8) {
      dn.col(a) << 0.125 * df[0] * f[1] * f[2], 0.125 * f[0] * df[1] * f[2],
          0.125 * f[0] * f[1] * df[2];
    } else if (r.cwiseAbs().minCoeff() > 0.0) {
      const double s = xi.dot(r) - 2.0;  // ξξ_a + ηη_a + ζζ_a - 2
      const double p = f.prod();
      for (int d = 0; d < 3; ++d) {
        const double others = f[(d + 1) % 3] * f[(d + 2) % 3];
        dn(d, a) = 0.125 * (df[d] * others * s + p * r[d]);
      }
    } else {
      dn.col(a) << 0.25 * df[0] * f[1] * f[2], 0.25 * f[0] * df[1] * f[2],
          0.25 * f[0] * f[1] * df[2];
    }
  }
  return dn;
}

Eigen::Matrix3d jacobian(const Mesh& mesh, int element, const Eigen::Vector3d& xi) {
  const Element& e = mesh.elements.at(static_cast<std::size_t>(element));
  const Eigen::Matrix3Xd dn = shape_derivatives(e.type, xi);
  Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
  for (Eigen::Index a = 0; a < dn.cols(); ++a) {
    j += mesh.coordinates.col(e.nodes[static_cast<std::size_t>(a)]) * dn.col(a).transpose();
  }
  return j;
}

GaussRule gauss_rule(int n) {
  GaussRule rule;
  rule.size = n;
  if (n == 2) {
    const double g = 1.0 / std::sqrt(3.0);
    rule.points = {-g, g, 0.0};
    rule.weights = {1.0, 1.0, 0.0};
  } else if (n == 3) {
    const double g = std::sqrt(0.6);
    rule.points = {-g, 0.0, g};
    rule.weights = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  } else {
    throw std::invalid_argument("gauss_rule: n must be 2 or 3");
  }
  return rule;
}

}  // namespace jointhb::fe::detail
