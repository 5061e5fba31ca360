#include "jointhb/fe/hexahedron.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "jointhb/fe/simplex_elements.hpp"

namespace jointhb::fe {

namespace {

// (ξ_a, η_a, ζ_a) of the 20 nodes, numbering of mesh.hpp.
constexpr std::array<std::array<double, 3>, 20> kNodes = {{
    {-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},  // corners, ζ = −1
    {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1},   // corners, ζ = +1
    {0, -1, -1},  {1, 0, -1},  {0, 1, -1}, {-1, 0, -1},  // mid-edge, ζ = −1
    {0, -1, 1},   {1, 0, 1},   {0, 1, 1},  {-1, 0, 1},   // mid-edge, ζ = +1
    {-1, -1, 0},  {1, -1, 0},  {1, 1, 0},  {-1, 1, 0},   // vertical edges
}};

}  // namespace

Eigen::Vector3d hex_node_natural_coordinates(int node) {
  if (node < 0 || node >= 20) throw std::out_of_range("hexahedron node index must be 0..19");
  const auto& c = kNodes[static_cast<std::size_t>(node)];
  return {c[0], c[1], c[2]};
}

Eigen::Matrix<double, 8, 1> hex8_shape_functions(const Eigen::Vector3d& xi) {
  Eigen::Matrix<double, 8, 1> n;
  for (std::size_t a = 0; a < 8; ++a) {
    const auto& c = kNodes[a];
    n(static_cast<Eigen::Index>(a)) =
        0.125 * (1.0 + xi(0) * c[0]) * (1.0 + xi(1) * c[1]) * (1.0 + xi(2) * c[2]);
  }
  return n;
}

Eigen::Matrix<double, 3, 8> hex8_shape_derivatives(const Eigen::Vector3d& xi) {
  Eigen::Matrix<double, 3, 8> d;
  for (std::size_t a = 0; a < 8; ++a) {
    const auto& c = kNodes[a];
    const double f0 = 1.0 + xi(0) * c[0], f1 = 1.0 + xi(1) * c[1], f2 = 1.0 + xi(2) * c[2];
    const auto col = static_cast<Eigen::Index>(a);
    d(0, col) = 0.125 * c[0] * f1 * f2;
    d(1, col) = 0.125 * f0 * c[1] * f2;
    d(2, col) = 0.125 * f0 * f1 * c[2];
  }
  return d;
}

Eigen::Matrix<double, 20, 1> hex20_shape_functions(const Eigen::Vector3d& xi) {
  Eigen::Matrix<double, 20, 1> n;
  for (std::size_t a = 0; a < 20; ++a) {
    const auto& c = kNodes[a];
    const auto row = static_cast<Eigen::Index>(a);
    if (a < 8) {
      const double s = xi(0) * c[0] + xi(1) * c[1] + xi(2) * c[2];
      n(row) =
          0.125 * (1.0 + xi(0) * c[0]) * (1.0 + xi(1) * c[1]) * (1.0 + xi(2) * c[2]) * (s - 2.0);
    } else {
      // f_k = 1 − ξ_k² along the edge's own direction (c[k] = 0), else 1 + ξ_k c_k.
      double product = 0.25;
      for (int k = 0; k < 3; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        product *= (c[kk] == 0.0) ? (1.0 - xi(k) * xi(k)) : (1.0 + xi(k) * c[kk]);
      }
      n(row) = product;
    }
  }
  return n;
}

Eigen::Matrix<double, 3, 20> hex20_shape_derivatives(const Eigen::Vector3d& xi) {
  Eigen::Matrix<double, 3, 20> d;
  for (std::size_t a = 0; a < 20; ++a) {
    const auto& c = kNodes[a];
    const auto col = static_cast<Eigen::Index>(a);
    if (a < 8) {
      // ∂N_a/∂ξ = ⅛ ξ_a (1 + η η_a)(1 + ζ ζ_a)(2 ξ ξ_a + η η_a + ζ ζ_a − 1), and cyclically.
      const std::array<double, 3> t = {xi(0) * c[0], xi(1) * c[1], xi(2) * c[2]};
      for (int k = 0; k < 3; ++k) {
        const auto k0 = static_cast<std::size_t>(k), k1 = static_cast<std::size_t>((k + 1) % 3),
                   k2 = static_cast<std::size_t>((k + 2) % 3);
        d(k, col) =
            0.125 * c[k0] * (1.0 + t[k1]) * (1.0 + t[k2]) * (2.0 * t[k0] + t[k1] + t[k2] - 1.0);
      }
    } else {
      std::array<double, 3> f{}, df{};
      for (std::size_t k = 0; k < 3; ++k) {
        const double x = xi(static_cast<Eigen::Index>(k));
        if (c[k] == 0.0) {
          f[k] = 1.0 - x * x;
          df[k] = -2.0 * x;
        } else {
          f[k] = 1.0 + x * c[k];
          df[k] = c[k];
        }
      }
      d(0, col) = 0.25 * df[0] * f[1] * f[2];
      d(1, col) = 0.25 * f[0] * df[1] * f[2];
      d(2, col) = 0.25 * f[0] * f[1] * df[2];
    }
  }
  return d;
}

Eigen::VectorXd shape_functions(ElementType type, const Eigen::Vector3d& xi) {
  switch (type) {
    case ElementType::tet4: return tet4_shape_functions(xi);
    case ElementType::tet10: return tet10_shape_functions(xi);
    case ElementType::wedge6: return wedge6_shape_functions(xi);
    case ElementType::wedge15: return wedge15_shape_functions(xi);
    default: break;
  }
  if (node_count(type) == 20) return hex20_shape_functions(xi);
  return hex8_shape_functions(xi);
}

Eigen::Matrix3Xd shape_derivatives(ElementType type, const Eigen::Vector3d& xi) {
  switch (type) {
    case ElementType::tet4: return tet4_shape_derivatives(xi);
    case ElementType::tet10: return tet10_shape_derivatives(xi);
    case ElementType::wedge6: return wedge6_shape_derivatives(xi);
    case ElementType::wedge15: return wedge15_shape_derivatives(xi);
    default: break;
  }
  if (node_count(type) == 20) return hex20_shape_derivatives(xi);
  return hex8_shape_derivatives(xi);
}

namespace {

std::vector<GaussPoint> tensor_rule(const std::vector<double>& points,
                                    const std::vector<double>& weights) {
  std::vector<GaussPoint> rule;
  for (std::size_t k = 0; k < points.size(); ++k)
    for (std::size_t j = 0; j < points.size(); ++j)
      for (std::size_t i = 0; i < points.size(); ++i)
        rule.push_back({Eigen::Vector3d(points[i], points[j], points[k]),
                        weights[i] * weights[j] * weights[k]});
  return rule;
}

}  // namespace

const std::vector<GaussPoint>& hex_gauss_rule(int points_per_direction) {
  // Gauss–Legendre points and weights (Abramowitz & Stegun, table 25.4).
  static const std::vector<GaussPoint> one = tensor_rule({0.0}, {2.0});
  static const std::vector<GaussPoint> two =
      tensor_rule({-1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0)}, {1.0, 1.0});
  static const std::vector<GaussPoint> three =
      tensor_rule({-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0});
  switch (points_per_direction) {
    case 1:
      return one;
    case 2:
      return two;
    case 3:
      return three;
    default:
      throw std::invalid_argument("hex_gauss_rule: points_per_direction = " +
                                  std::to_string(points_per_direction) + " must be 1, 2 or 3");
  }
}

}  // namespace jointhb::fe
