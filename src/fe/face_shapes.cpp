// Shape functions, rules and inverse map of interface faces (face_shapes.hpp).
#include "face_shapes.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

namespace jointhb::fe::face {

namespace {

constexpr std::array<double, 8> kXi = {-1.0, 1.0, 1.0, -1.0, 0.0, 1.0, 0.0, -1.0};
constexpr std::array<double, 8> kEta = {-1.0, -1.0, 1.0, 1.0, -1.0, 0.0, 1.0, 0.0};

Shape quadrilateral(int nodes, double xi, double eta) {
  Shape s;
  if (nodes == 4) {
    for (std::size_t k = 0; k < 4; ++k) {  // eq. (14): h = (1 ± ξ)(1 ± η)/4
      s.h[k] = 0.25 * (1.0 + kXi[k] * xi) * (1.0 + kEta[k] * eta);
      s.dxi[k] = 0.25 * kXi[k] * (1.0 + kEta[k] * eta);
      s.deta[k] = 0.25 * (1.0 + kXi[k] * xi) * kEta[k];
    }
    return s;
  }
  for (std::size_t k = 0; k < 4; ++k) {  // serendipity corners: (1+ξξk)(1+ηηk)(ξξk+ηηk-1)/4
    const double a = 1.0 + kXi[k] * xi;
    const double b = 1.0 + kEta[k] * eta;
    const double c = kXi[k] * xi + kEta[k] * eta - 1.0;
    s.h[k] = 0.25 * a * b * c;
    s.dxi[k] = 0.25 * kXi[k] * b * (c + a);
    s.deta[k] = 0.25 * kEta[k] * a * (c + b);
  }
  for (std::size_t k = 4; k < 8; ++k) {
    if (kXi[k] == 0.0) {  // (1-ξ²)(1+ηηk)/2
      s.h[k] = 0.5 * (1.0 - xi * xi) * (1.0 + kEta[k] * eta);
      s.dxi[k] = -xi * (1.0 + kEta[k] * eta);
      s.deta[k] = 0.5 * (1.0 - xi * xi) * kEta[k];
    } else {  // (1+ξξk)(1-η²)/2
      s.h[k] = 0.5 * (1.0 + kXi[k] * xi) * (1.0 - eta * eta);
      s.dxi[k] = 0.5 * kXi[k] * (1.0 - eta * eta);
      s.deta[k] = -(1.0 + kXi[k] * xi) * eta;
    }
  }
  return s;
}

Shape triangle(int nodes, double xi, double eta) {
  const std::array<double, 3> l = {1.0 - xi - eta, xi, eta};
  const std::array<double, 3> dl_xi = {-1.0, 1.0, 0.0};
  const std::array<double, 3> dl_eta = {-1.0, 0.0, 1.0};
  Shape s;
  if (nodes == 3) {
    for (std::size_t k = 0; k < 3; ++k) s.h[k] = l[k], s.dxi[k] = dl_xi[k], s.deta[k] = dl_eta[k];
    return s;
  }
  for (std::size_t k = 0; k < 3; ++k) {  // corners L(2L - 1)
    s.h[k] = l[k] * (2.0 * l[k] - 1.0);
    s.dxi[k] = (4.0 * l[k] - 1.0) * dl_xi[k];
    s.deta[k] = (4.0 * l[k] - 1.0) * dl_eta[k];
  }
  for (std::size_t k = 0; k < 3; ++k) {  // mid-edge 3+k between corners k and k+1: 4 L_k L_{k+1}
    const std::size_t j = (k + 1) % 3;
    s.h[3 + k] = 4.0 * l[k] * l[j];
    s.dxi[3 + k] = 4.0 * (dl_xi[k] * l[j] + l[k] * dl_xi[j]);
    s.deta[3 + k] = 4.0 * (dl_eta[k] * l[j] + l[k] * dl_eta[j]);
  }
  return s;
}

}  // namespace

Shape shape(int nodes, double xi, double eta) {
  return is_triangle(nodes) ? triangle(nodes, xi, eta) : quadrilateral(nodes, xi, eta);
}

Eigen::Vector2d corner(int nodes, int k) {
  if (is_triangle(nodes)) return k == 0 ? Eigen::Vector2d(0, 0) : k == 1 ? Eigen::Vector2d(1, 0) : Eigen::Vector2d(0, 1);
  return {kXi[static_cast<std::size_t>(k)], kEta[static_cast<std::size_t>(k)]};
}

Eigen::Vector2d centre(int nodes) {
  return is_triangle(nodes) ? Eigen::Vector2d(1.0 / 3.0, 1.0 / 3.0) : Eigen::Vector2d(0.0, 0.0);
}

std::vector<std::array<double, 2>> gauss_legendre(int n) {
  switch (n) {
    case 1: return {{0.0, 2.0}};
    case 2: {
      const double g = 1.0 / std::sqrt(3.0);
      return {{-g, 1.0}, {g, 1.0}};
    }
    case 3: {
      const double g = std::sqrt(0.6);
      return {{-g, 5.0 / 9.0}, {0.0, 8.0 / 9.0}, {g, 5.0 / 9.0}};
    }
    case 4: {  // ±sqrt(3/7 ∓ 2/7 sqrt(6/5)), (18 ± sqrt(30))/36
      const double a = std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * std::sqrt(1.2));
      const double b = std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * std::sqrt(1.2));
      const double wa = (18.0 + std::sqrt(30.0)) / 36.0;
      const double wb = (18.0 - std::sqrt(30.0)) / 36.0;
      return {{-b, wb}, {-a, wa}, {a, wa}, {b, wb}};
    }
    case 5: {  // 0, ±(1/3) sqrt(5 ∓ 2 sqrt(10/7)); 128/225, (322 ± 13 sqrt(70))/900
      const double a = std::sqrt(5.0 - 2.0 * std::sqrt(10.0 / 7.0)) / 3.0;
      const double b = std::sqrt(5.0 + 2.0 * std::sqrt(10.0 / 7.0)) / 3.0;
      const double wa = (322.0 + 13.0 * std::sqrt(70.0)) / 900.0;
      const double wb = (322.0 - 13.0 * std::sqrt(70.0)) / 900.0;
      return {{-b, wb}, {-a, wa}, {0.0, 128.0 / 225.0}, {a, wa}, {b, wb}};
    }
    default: throw std::invalid_argument("gauss_legendre: n must be 1..5");
  }
}

std::vector<RulePoint> triangle_rule(int n) {
  const auto g = gauss_legendre(n);
  std::vector<RulePoint> r;
  r.reserve(g.size() * g.size());
  for (const auto& [x, wx] : g) {
    const double s = 0.5 * (1.0 + x);
    for (const auto& [y, wy] : g) {
      const double t = 0.5 * (1.0 + y);
      r.push_back({s, t * (1.0 - s), 0.25 * wx * wy * (1.0 - s)});
    }
  }
  return r;
}

std::vector<RulePoint> rule(InterfaceIntegration integration, int nodes) {
  const bool tri = is_triangle(nodes);
  const bool quadratic = nodes == 6 || nodes == 8;
  if (integration == InterfaceIntegration::nodal) {
    if (quadratic) throw std::invalid_argument("nodal integration needs linear faces (tri3, quad4)");
    std::vector<RulePoint> r;
    for (int k = 0; k < corner_count(nodes); ++k) {
      const Eigen::Vector2d c = corner(nodes, k);
      r.push_back({c.x(), c.y(), tri ? 1.0 / 6.0 : 1.0});
    }
    return r;
  }
  if (tri) return triangle_rule(quadratic ? 3 : 2);
  std::vector<RulePoint> r;
  const auto g = gauss_legendre(quadratic ? 3 : 2);
  for (const auto& [y, wy] : g)
    for (const auto& [x, wx] : g) r.push_back({x, y, wx * wy});
  return r;
}

bool inverse_map(const Eigen::Matrix2Xd& nodes2d, const Eigen::Vector2d& x, Eigen::Vector2d& natural) {
  const int n = static_cast<int>(nodes2d.cols());
  double size = 0.0;
  for (int i = 0; i < corner_count(n); ++i)
    for (int j = i + 1; j < corner_count(n); ++j) size = std::max(size, (nodes2d.col(i) - nodes2d.col(j)).norm());
  natural = centre(n);
  for (int it = 0; it < 30; ++it) {
    const Shape s = shape(n, natural.x(), natural.y());
    Eigen::Vector2d r = -x;
    Eigen::Matrix2d j = Eigen::Matrix2d::Zero();
    for (int k = 0; k < n; ++k) {
      const auto ku = static_cast<std::size_t>(k);
      r += s.h[ku] * nodes2d.col(k);
      j.col(0) += s.dxi[ku] * nodes2d.col(k);
      j.col(1) += s.deta[ku] * nodes2d.col(k);
    }
    if (r.norm() <= 1e-12 * size) return true;
    const double det = j.determinant();
    if (!(std::abs(det) > 1e-14 * size * size)) return false;
    natural -= j.inverse() * r;
  }
  return false;
}

}  // namespace jointhb::fe::face
