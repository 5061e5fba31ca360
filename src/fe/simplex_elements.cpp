// Tetrahedra and wedges: the shape functions and rules of simplex_elements.hpp.
#include "jointhb/fe/simplex_elements.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace jointhb::fe {

namespace {

using Vec3 = Eigen::Vector3d;

// Volume coordinates of the tetrahedron and their (constant) natural gradients.
std::array<double, 4> tet_coordinates(const Vec3& xi) {
  return {1.0 - xi(0) - xi(1) - xi(2), xi(0), xi(1), xi(2)};
}
const std::array<Vec3, 4>& tet_gradients() {
  static const std::array<Vec3, 4> g = {Vec3(-1, -1, -1), Vec3(1, 0, 0), Vec3(0, 1, 0),
                                        Vec3(0, 0, 1)};
  return g;
}

// Area coordinates of the wedge's triangle and their natural gradients (no ζ component).
std::array<double, 3> triangle_coordinates(const Vec3& xi) {
  return {1.0 - xi(0) - xi(1), xi(0), xi(1)};
}
const std::array<Vec3, 3>& triangle_gradients() {
  static const std::array<Vec3, 3> g = {Vec3(-1, -1, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  return g;
}

// Corners of the tet10 / wedge15 mid-edge nodes (edge_corners of mesh.hpp).
constexpr std::array<std::array<int, 2>, 6> kTetEdges = {
    {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};
constexpr std::array<std::array<int, 2>, 3> kTriangleEdges = {{{0, 1}, {1, 2}, {2, 0}}};

// triangle × Gauss–Legendre in ζ (points and weights of Abramowitz & Stegun, table 25.4), ζ slowest.
std::vector<GaussPoint> line_times_triangle(const std::vector<GaussPoint>& triangle,
                                            int line_points) {
  std::vector<double> x, w;
  switch (line_points) {
    case 1: x = {0.0}; w = {2.0}; break;
    case 2: x = {-1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0)}; w = {1.0, 1.0}; break;
    case 3: x = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}; w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0}; break;
    default:
      throw std::invalid_argument("wedge_rule: line_points = " + std::to_string(line_points) +
                                  " must be 1, 2 or 3");
  }
  std::vector<GaussPoint> rule;
  for (std::size_t k = 0; k < x.size(); ++k)
    for (const GaussPoint& t : triangle)
      rule.push_back({Vec3(t.xi(0), t.xi(1), x[k]), t.weight * w[k]});
  return rule;
}

}  // namespace

Eigen::Vector3d simplex_node_natural_coordinates(ElementType type, int node) {
  const ElementFamily f = family(type);
  if (f == ElementFamily::hexahedron)
    throw std::invalid_argument("simplex_node_natural_coordinates: not a tetrahedron or wedge");
  if (node < 0 || node >= node_count(type))
    throw std::out_of_range(std::string(abaqus_name(type)) + ": node index out of range");
  if (f == ElementFamily::tetrahedron) {
    static const std::array<Vec3, 4> corners = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
                                                Vec3(0, 0, 1)};
    if (node < 4) return corners[static_cast<std::size_t>(node)];
    const auto& e = kTetEdges[static_cast<std::size_t>(node - 4)];
    return 0.5 * (corners[static_cast<std::size_t>(e[0])] + corners[static_cast<std::size_t>(e[1])]);
  }
  static const std::array<Vec3, 6> corners = {Vec3(0, 0, -1), Vec3(1, 0, -1), Vec3(0, 1, -1),
                                              Vec3(0, 0, 1),  Vec3(1, 0, 1),  Vec3(0, 1, 1)};
  if (node < 6) return corners[static_cast<std::size_t>(node)];
  const auto& e = edge_corners(type)[static_cast<std::size_t>(node - 6)];
  return 0.5 * (corners[static_cast<std::size_t>(e[0])] + corners[static_cast<std::size_t>(e[1])]);
}

Eigen::Matrix<double, 4, 1> tet4_shape_functions(const Vec3& xi) {
  const auto l = tet_coordinates(xi);
  return {l[0], l[1], l[2], l[3]};
}

Eigen::Matrix<double, 3, 4> tet4_shape_derivatives(const Vec3& /*xi*/) {
  Eigen::Matrix<double, 3, 4> d;
  for (int a = 0; a < 4; ++a) d.col(a) = tet_gradients()[static_cast<std::size_t>(a)];
  return d;
}

Eigen::Matrix<double, 10, 1> tet10_shape_functions(const Vec3& xi) {
  const auto l = tet_coordinates(xi);
  Eigen::Matrix<double, 10, 1> n;
  for (std::size_t a = 0; a < 4; ++a) n(static_cast<Eigen::Index>(a)) = l[a] * (2.0 * l[a] - 1.0);
  for (std::size_t k = 0; k < 6; ++k) {
    const auto a = static_cast<std::size_t>(kTetEdges[k][0]);
    const auto b = static_cast<std::size_t>(kTetEdges[k][1]);
    n(static_cast<Eigen::Index>(4 + k)) = 4.0 * l[a] * l[b];
  }
  return n;
}

Eigen::Matrix<double, 3, 10> tet10_shape_derivatives(const Vec3& xi) {
  const auto l = tet_coordinates(xi);
  const auto& g = tet_gradients();
  Eigen::Matrix<double, 3, 10> d;
  // ∇[L(2L − 1)] = (4L − 1) ∇L;  ∇[4 L_a L_b] = 4 (L_b ∇L_a + L_a ∇L_b).
  for (std::size_t a = 0; a < 4; ++a) d.col(static_cast<Eigen::Index>(a)) = (4.0 * l[a] - 1.0) * g[a];
  for (std::size_t k = 0; k < 6; ++k) {
    const auto a = static_cast<std::size_t>(kTetEdges[k][0]);
    const auto b = static_cast<std::size_t>(kTetEdges[k][1]);
    d.col(static_cast<Eigen::Index>(4 + k)) = 4.0 * (l[b] * g[a] + l[a] * g[b]);
  }
  return d;
}

Eigen::Matrix<double, 6, 1> wedge6_shape_functions(const Vec3& xi) {
  const auto l = triangle_coordinates(xi);
  Eigen::Matrix<double, 6, 1> n;
  for (std::size_t a = 0; a < 3; ++a) {
    n(static_cast<Eigen::Index>(a)) = 0.5 * l[a] * (1.0 - xi(2));
    n(static_cast<Eigen::Index>(a + 3)) = 0.5 * l[a] * (1.0 + xi(2));
  }
  return n;
}

Eigen::Matrix<double, 3, 6> wedge6_shape_derivatives(const Vec3& xi) {
  const auto l = triangle_coordinates(xi);
  const auto& g = triangle_gradients();
  Eigen::Matrix<double, 3, 6> d;
  for (std::size_t a = 0; a < 3; ++a) {
    const auto bottom = static_cast<Eigen::Index>(a), top = static_cast<Eigen::Index>(a + 3);
    d.col(bottom) = 0.5 * (1.0 - xi(2)) * g[a];
    d(2, bottom) = -0.5 * l[a];
    d.col(top) = 0.5 * (1.0 + xi(2)) * g[a];
    d(2, top) = 0.5 * l[a];
  }
  return d;
}

Eigen::Matrix<double, 15, 1> wedge15_shape_functions(const Vec3& xi) {
  const auto l = triangle_coordinates(xi);
  const double z = xi(2), bubble = 1.0 - z * z;
  Eigen::Matrix<double, 15, 1> n;
  for (std::size_t a = 0; a < 3; ++a) {
    const auto i = static_cast<Eigen::Index>(a);
    n(i) = 0.5 * l[a] * ((2.0 * l[a] - 1.0) * (1.0 - z) - bubble);
    n(i + 3) = 0.5 * l[a] * ((2.0 * l[a] - 1.0) * (1.0 + z) - bubble);
    n(i + 12) = l[a] * bubble;
  }
  for (std::size_t k = 0; k < 3; ++k) {
    const auto a = static_cast<std::size_t>(kTriangleEdges[k][0]);
    const auto b = static_cast<std::size_t>(kTriangleEdges[k][1]);
    const auto i = static_cast<Eigen::Index>(k);
    n(6 + i) = 2.0 * l[a] * l[b] * (1.0 - z);
    n(9 + i) = 2.0 * l[a] * l[b] * (1.0 + z);
  }
  return n;
}

Eigen::Matrix<double, 3, 15> wedge15_shape_derivatives(const Vec3& xi) {
  const auto l = triangle_coordinates(xi);
  const auto& g = triangle_gradients();
  const double z = xi(2), bubble = 1.0 - z * z;
  Eigen::Matrix<double, 3, 15> d;
  for (std::size_t a = 0; a < 3; ++a) {
    const auto i = static_cast<Eigen::Index>(a);
    // ∂/∂(ξ, η) of ½ L [(2L − 1)(1 ∓ ζ) − (1 − ζ²)] = ½ [(4L − 1)(1 ∓ ζ) − (1 − ζ²)] ∇L;
    // ∂/∂ζ = ½ L [∓(2L − 1) + 2ζ].
    d.col(i) = 0.5 * ((4.0 * l[a] - 1.0) * (1.0 - z) - bubble) * g[a];
    d(2, i) = 0.5 * l[a] * (-(2.0 * l[a] - 1.0) + 2.0 * z);
    d.col(i + 3) = 0.5 * ((4.0 * l[a] - 1.0) * (1.0 + z) - bubble) * g[a];
    d(2, i + 3) = 0.5 * l[a] * ((2.0 * l[a] - 1.0) + 2.0 * z);
    d.col(i + 12) = bubble * g[a];
    d(2, i + 12) = -2.0 * z * l[a];
  }
  for (std::size_t k = 0; k < 3; ++k) {
    const auto a = static_cast<std::size_t>(kTriangleEdges[k][0]);
    const auto b = static_cast<std::size_t>(kTriangleEdges[k][1]);
    const auto i = static_cast<Eigen::Index>(k);
    const Vec3 grad = 2.0 * (l[b] * g[a] + l[a] * g[b]);  // ∇(2 L_a L_b)
    d.col(6 + i) = (1.0 - z) * grad;
    d(2, 6 + i) = -2.0 * l[a] * l[b];
    d.col(9 + i) = (1.0 + z) * grad;
    d(2, 9 + i) = 2.0 * l[a] * l[b];
  }
  return d;
}

const std::vector<GaussPoint>& tet_rule(int points) {
  static const std::vector<GaussPoint> one = {{Vec3(0.25, 0.25, 0.25), 1.0 / 6.0}};
  static const std::vector<GaussPoint> four = [] {
    const double a = (5.0 - std::sqrt(5.0)) / 20.0, b = 1.0 - 3.0 * a;
    return std::vector<GaussPoint>{{Vec3(a, a, a), 1.0 / 24.0},
                                   {Vec3(b, a, a), 1.0 / 24.0},
                                   {Vec3(a, b, a), 1.0 / 24.0},
                                   {Vec3(a, a, b), 1.0 / 24.0}};
  }();
  static const std::vector<GaussPoint> fourteen = [] {
    std::vector<GaussPoint> rule;
    // Walkington's degree-5 rule (header): (a, a, a, 1 − 3a) in volume coordinates.
    const std::array<std::array<double, 2>, 2> corner_groups = {
        {{0.0927352503108912, 0.01224884051939366}, {0.3108859192633006, 0.01878132095300264}}};
    for (const auto& [a, w] : corner_groups) {
      const double b = 1.0 - 3.0 * a;
      for (const Vec3& p : {Vec3(a, a, a), Vec3(b, a, a), Vec3(a, b, a), Vec3(a, a, b)})
        rule.push_back({p, w});
    }
    // (b, b, ½ − b, ½ − b) and its 6 distinct permutations over (L0, L1, L2, L3).
    const double b = 0.0455037041256496, c = 0.5 - b, w = 0.007091003462846911;
    for (const Vec3& p : {Vec3(b, b, c), Vec3(b, c, b), Vec3(c, b, b), Vec3(b, c, c),
                          Vec3(c, b, c), Vec3(c, c, b)})
      rule.push_back({p, w});  // L0 = 1 − ξ − η − ζ is then c or b as needed
    return rule;
  }();
  switch (points) {
    case 1: return one;
    case 4: return four;
    case 14: return fourteen;
    default:
      throw std::invalid_argument("tet_rule: points = " + std::to_string(points) +
                                  " must be 1, 4 or 14");
  }
}

const std::vector<GaussPoint>& triangle_rule(int points) {
  static const std::vector<GaussPoint> one = {{Vec3(1.0 / 3.0, 1.0 / 3.0, 0.0), 0.5}};
  static const std::vector<GaussPoint> three = {{Vec3(1.0 / 6.0, 1.0 / 6.0, 0.0), 1.0 / 6.0},
                                                {Vec3(2.0 / 3.0, 1.0 / 6.0, 0.0), 1.0 / 6.0},
                                                {Vec3(1.0 / 6.0, 2.0 / 3.0, 0.0), 1.0 / 6.0}};
  static const std::vector<GaussPoint> seven = [] {
    const double s = std::sqrt(15.0);
    const double a1 = (6.0 - s) / 21.0, w1 = (155.0 - s) / 2400.0;
    const double a2 = (6.0 + s) / 21.0, w2 = (155.0 + s) / 2400.0;
    std::vector<GaussPoint> rule = {{Vec3(1.0 / 3.0, 1.0 / 3.0, 0.0), 9.0 / 80.0}};
    for (const auto& [a, w] : {std::array<double, 2>{a1, w1}, std::array<double, 2>{a2, w2}}) {
      const double b = 1.0 - 2.0 * a;
      rule.push_back({Vec3(a, a, 0.0), w});
      rule.push_back({Vec3(b, a, 0.0), w});
      rule.push_back({Vec3(a, b, 0.0), w});
    }
    return rule;
  }();
  switch (points) {
    case 1: return one;
    case 3: return three;
    case 7: return seven;
    default:
      throw std::invalid_argument("triangle_rule: points = " + std::to_string(points) +
                                  " must be 1, 3 or 7");
  }
}

std::vector<GaussPoint> wedge_rule(int triangle_points, int line_points) {
  return line_times_triangle(triangle_rule(triangle_points), line_points);
}

Eigen::Vector3d centre_natural_coordinates(ElementType type) {
  switch (family(type)) {
    case ElementFamily::tetrahedron: return Vec3(0.25, 0.25, 0.25);
    case ElementFamily::wedge: return Vec3(1.0 / 3.0, 1.0 / 3.0, 0.0);
    default: return Vec3::Zero();
  }
}

const std::vector<GaussPoint>& integration_rule(ElementType type, bool mass) {
  static const std::vector<GaussPoint> wedge_3x2 = wedge_rule(3, 2);
  static const std::vector<GaussPoint> wedge_3x3 = wedge_rule(3, 3);
  static const std::vector<GaussPoint> wedge_7x3 = wedge_rule(7, 3);
  switch (type) {
    case ElementType::tet4: return tet_rule(mass ? 4 : 1);
    case ElementType::tet10: return tet_rule(mass ? 14 : 4);
    case ElementType::wedge6: return wedge_3x2;
    case ElementType::wedge15: return mass ? wedge_7x3 : wedge_3x3;
    case ElementType::hex20: return hex_gauss_rule(3);
    case ElementType::hex20_reduced: return hex_gauss_rule(mass ? 3 : 2);
    default: return hex_gauss_rule(2);
  }
}

}  // namespace jointhb::fe
