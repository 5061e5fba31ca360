// Solid elements: equations (1)–(4) of solid_element.hpp.
#include "jointhb/fe/solid_element.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "jointhb/fe/hexahedron.hpp"
#include "jointhb/fe/simplex_elements.hpp"
#include "solid_element_kernel.hpp"

namespace jointhb::fe {

namespace {

// Shape functions and natural derivatives tabulated at the points of one Gauss rule.
template <int N>
struct RuleTable {
  std::vector<Eigen::Matrix<double, N, 1>> shape;
  std::vector<Eigen::Matrix<double, 3, N>> derivatives;
  std::vector<double> weights;
  std::vector<Eigen::Vector3d> points;
};

// The node count identifies the shape functions: 8 hex8, 20 hex20, 4 tet4, 10 tet10, 6 wedge6,
// 15 wedge15.
template <int N>
Eigen::Matrix<double, N, 1> shape_at(const Eigen::Vector3d& xi) {
  if constexpr (N == 8)
    return hex8_shape_functions(xi);
  else if constexpr (N == 20)
    return hex20_shape_functions(xi);
  else if constexpr (N == 4)
    return tet4_shape_functions(xi);
  else if constexpr (N == 10)
    return tet10_shape_functions(xi);
  else if constexpr (N == 6)
    return wedge6_shape_functions(xi);
  else
    return wedge15_shape_functions(xi);
}

template <int N>
Eigen::Matrix<double, 3, N> derivatives_at(const Eigen::Vector3d& xi) {
  if constexpr (N == 8)
    return hex8_shape_derivatives(xi);
  else if constexpr (N == 20)
    return hex20_shape_derivatives(xi);
  else if constexpr (N == 4)
    return tet4_shape_derivatives(xi);
  else if constexpr (N == 10)
    return tet10_shape_derivatives(xi);
  else if constexpr (N == 6)
    return wedge6_shape_derivatives(xi);
  else
    return wedge15_shape_derivatives(xi);
}

template <int N>
RuleTable<N> make_table(const std::vector<GaussPoint>& rule) {
  RuleTable<N> t;
  for (const GaussPoint& p : rule) {
    t.shape.push_back(shape_at<N>(p.xi));
    t.derivatives.push_back(derivatives_at<N>(p.xi));
    t.weights.push_back(p.weight);
    t.points.push_back(p.xi);
  }
  return t;
}

template <int N>
RuleTable<N> make_table(int points_per_direction) {
  return make_table<N>(hex_gauss_rule(points_per_direction));
}

template <int N>
const RuleTable<N>& table(int points_per_direction) {
  static const RuleTable<N> two = make_table<N>(2);
  static const RuleTable<N> three = make_table<N>(3);
  return points_per_direction == 2 ? two : three;
}

// Tetrahedra and wedges: the stiffness (mass = false) or mass table of integration_rule
// (simplex_elements.hpp); N identifies the type.
template <int N>
const RuleTable<N>& simplex_table(ElementType type, bool mass) {
  static const RuleTable<N> stiffness_table = make_table<N>(integration_rule(type, false));
  static const RuleTable<N> mass_table = make_table<N>(integration_rule(type, true));
  return mass ? mass_table : stiffness_table;
}

// Adds c_λ g_a g_bᵀ + c_μ g_b g_aᵀ + c_μ (g_a·g_b) I₃ to the upper node blocks (a ≤ b) of K,
// eq. (1) at one integration point with c_λ = λ w det J, c_μ = μ w det J.
template <int M>
void add_isotropic_upper(Eigen::Matrix<double, 3 * M, 3 * M>& k,
                         const Eigen::Matrix<double, 3, M>& g, double c_lambda, double c_mu) {
  for (int b = 0; b < M; ++b) {
    const Eigen::Vector3d gb = g.col(b);
    for (int a = 0; a <= b; ++a) {
      const Eigen::Vector3d ga = g.col(a);
      Eigen::Matrix3d block = c_lambda * ga * gb.transpose() + c_mu * gb * ga.transpose();
      block.diagonal().array() += c_mu * ga.dot(gb);
      k.template block<3, 3>(3 * a, 3 * b) += block;
    }
  }
}

// K_ba = K_abᵀ (eq. (1) is symmetric under a ↔ b with transposition): fill the lower triangle.
template <int S>
void mirror_upper(Eigen::Matrix<double, S, S>& k) {
  for (int j = 0; j < S; ++j)
    for (int i = j + 1; i < S; ++i) k(i, j) = k(j, i);
}

// J_kj = ∂x_j/∂ξ_k = Σ_a ∂N_a/∂ξ_k x_ja.
template <int N>
Eigen::Matrix3d jacobian(const Eigen::Matrix<double, 3, N>& dn,
                         const Eigen::Map<const Eigen::Matrix<double, 3, N>>& x) {
  return dn * x.transpose();
}

// Compatible elements (hex8, hex20, hex20_reduced): eq. (1) with the stiffness rule and eq. (2)
// with the mass rule. Returns the volume, or −1 when det J ≤ 0 somewhere.
template <int N>
double tabulated_kernel(const RuleTable<N>& ks, const RuleTable<N>& ms, const double* coordinates,
                        const detail::IsotropicConstants& c, double* stiffness, double* mass) {
  const Eigen::Map<const Eigen::Matrix<double, 3, N>> x(coordinates);
  Eigen::Map<Eigen::Matrix<double, 3 * N, 3 * N>> k_out(stiffness);
  Eigen::Map<Eigen::Matrix<double, 3 * N, 3 * N>> m_out(mass);

  Eigen::Matrix<double, 3 * N, 3 * N> k = Eigen::Matrix<double, 3 * N, 3 * N>::Zero();
  for (std::size_t q = 0; q < ks.weights.size(); ++q) {
    const Eigen::Matrix3d j = jacobian<N>(ks.derivatives[q], x);
    const double det = j.determinant();
    if (!(det > 0.0)) return -1.0;
    const Eigen::Matrix<double, 3, N> g = j.inverse() * ks.derivatives[q];  // column a = ∇N_a
    const double dv = ks.weights[q] * det;
    add_isotropic_upper<N>(k, g, c.lambda * dv, c.mu * dv);
  }
  mirror_upper<3 * N>(k);
  k_out = k;

  // Eq. (2): the scalar matrix m_ab = ρ Σ w det J N_a N_b, placed on the diagonal of each block.
  Eigen::Matrix<double, N, N> m = Eigen::Matrix<double, N, N>::Zero();
  double volume = 0.0;
  for (std::size_t q = 0; q < ms.weights.size(); ++q) {
    const double det = jacobian<N>(ms.derivatives[q], x).determinant();
    if (!(det > 0.0)) return -1.0;
    const double dv = ms.weights[q] * det;
    volume += dv;
    m.noalias() += (c.density * dv) * ms.shape[q] * ms.shape[q].transpose();
  }
  mirror_upper<N>(m);  // exact symmetry (the vectorised outer products may differ in the last bit)
  m_out.setZero();
  for (int b = 0; b < N; ++b)
    for (int a = 0; a < N; ++a)
      for (int d = 0; d < 3; ++d) m_out(3 * a + d, 3 * b + d) = m(a, b);
  return volume;
}

// Hexahedra: the tensor-product Gauss rules.
template <int N>
double compatible_kernel(int stiffness_points, int mass_points, const double* coordinates,
                         const detail::IsotropicConstants& c, double* stiffness, double* mass) {
  return tabulated_kernel<N>(table<N>(stiffness_points), table<N>(mass_points), coordinates, c,
                             stiffness, mass);
}

// Tetrahedra and wedges: the rules of integration_rule.
template <int N>
double simplex_kernel(ElementType type, const double* coordinates,
                      const detail::IsotropicConstants& c, double* stiffness, double* mass) {
  return tabulated_kernel<N>(simplex_table<N>(type, false), simplex_table<N>(type, true),
                             coordinates, c, stiffness, mass);
}

// hex8_incompatible: eqs. (1), (3), (4). The 8 nodal gradients and the 3 incompatible-mode
// gradients g_m of eq. (4) are treated alike by eq. (1) (each incompatible mode P_m carries one
// vector α_m ∈ ℝ³), giving a 33 × 33 matrix whose last 9 rows/columns are condensed.
double incompatible_kernel(const double* coordinates, const detail::IsotropicConstants& c,
                           double* stiffness, double* mass) {
  constexpr int kModes = 3;
  constexpr int kAll = 8 + kModes;
  const Eigen::Map<const Eigen::Matrix<double, 3, 8>> x(coordinates);
  const Eigen::Matrix3d j0 = jacobian<8>(hex8_shape_derivatives(Eigen::Vector3d::Zero()), x);
  const double det0 = j0.determinant();
  if (!(det0 > 0.0)) return -1.0;
  const Eigen::Matrix3d j0_inverse = j0.inverse();

  Eigen::Matrix<double, 3 * kAll, 3 * kAll> k = Eigen::Matrix<double, 3 * kAll, 3 * kAll>::Zero();
  const RuleTable<8>& ks = table<8>(2);
  for (std::size_t q = 0; q < ks.weights.size(); ++q) {
    const Eigen::Matrix3d j = jacobian<8>(ks.derivatives[q], x);
    const double det = j.determinant();
    if (!(det > 0.0)) return -1.0;
    Eigen::Matrix<double, 3, kAll> g;
    g.leftCols<8>() = j.inverse() * ks.derivatives[q];
    // ∂P_m/∂ξ for P = (1 − ξ², 1 − η², 1 − ζ²): column m = −2 ξ_m e_m.
    const Eigen::Matrix3d dp = (-2.0 * ks.points[q]).asDiagonal();
    g.rightCols<kModes>() = (det0 / det) * j0_inverse * dp;  // eq. (4)
    const double dv = ks.weights[q] * det;
    add_isotropic_upper<kAll>(k, g, c.lambda * dv, c.mu * dv);
  }
  mirror_upper<3 * kAll>(k);

  // Eq. (3): static condensation of the incompatible amplitudes α.
  const auto k_uu = k.topLeftCorner<24, 24>();
  const auto k_ua = k.topRightCorner<24, 3 * kModes>();
  const Eigen::Matrix<double, 3 * kModes, 3 * kModes> k_aa = k.bottomRightCorner<9, 9>();
  const Eigen::LLT<Eigen::Matrix<double, 9, 9>> llt(k_aa);
  Eigen::Map<Eigen::Matrix<double, 24, 24>> k_out(stiffness);
  k_out = k_uu - k_ua * llt.solve(k_ua.transpose());
  // Round-off symmetrisation so the assembled matrix is exactly symmetric.
  for (int jj = 0; jj < 24; ++jj)
    for (int i = jj + 1; i < 24; ++i) {
      const double s = 0.5 * (k_out(i, jj) + k_out(jj, i));
      k_out(i, jj) = s;
      k_out(jj, i) = s;
    }

  // Mass: the incompatible modes carry no mass (they are internal strain enhancements), eq. (2).
  std::array<double, 24 * 24> unused{};
  return compatible_kernel<8>(2, 2, coordinates, c, unused.data(), mass);
}

detail::IsotropicConstants constants_of(const Material& material) {
  if (const std::string message = material.validate(); !message.empty())
    throw std::invalid_argument(message);
  return {material.lame_lambda(), material.shear_modulus(), material.density};
}

void check_columns(ElementType type, const Eigen::Matrix3Xd& coordinates) {
  if (coordinates.cols() != node_count(type))
    throw std::invalid_argument(std::string(abaqus_name(type)) + ": coordinates have " +
                                std::to_string(coordinates.cols()) + " columns, must be " +
                                std::to_string(node_count(type)));
}

}  // namespace

namespace detail {

double element_kernel(ElementType type, const double* coordinates, const IsotropicConstants& c,
                      double* stiffness, double* mass) {
  switch (type) {
    case ElementType::hex8:
      return compatible_kernel<8>(2, 2, coordinates, c, stiffness, mass);
    case ElementType::hex8_incompatible:
      return incompatible_kernel(coordinates, c, stiffness, mass);
    case ElementType::hex20:
      return compatible_kernel<20>(3, 3, coordinates, c, stiffness, mass);
    case ElementType::hex20_reduced:
      return compatible_kernel<20>(2, 3, coordinates, c, stiffness, mass);
    case ElementType::tet4:
      return simplex_kernel<4>(type, coordinates, c, stiffness, mass);
    case ElementType::tet10:
      return simplex_kernel<10>(type, coordinates, c, stiffness, mass);
    case ElementType::wedge6:
      return simplex_kernel<6>(type, coordinates, c, stiffness, mass);
    case ElementType::wedge15:
      return simplex_kernel<15>(type, coordinates, c, stiffness, mass);
  }
  return -1.0;
}

}  // namespace detail

namespace {
void require_hexahedron(ElementType type, const char* who) {
  if (family(type) != ElementFamily::hexahedron)
    throw std::invalid_argument(std::string(who) + ": " + abaqus_name(type) +
                                " has no tensor-product Gauss rule (use integration_rule)");
}
}  // namespace

int stiffness_rule(ElementType type) {
  require_hexahedron(type, "stiffness_rule");
  return type == ElementType::hex20 ? 3 : 2;
}
int mass_rule(ElementType type) {
  require_hexahedron(type, "mass_rule");
  return node_count(type) == 20 ? 3 : 2;
}

ElementMatrices element_matrices(ElementType type, const Eigen::Matrix3Xd& coordinates,
                                 const Material& material) {
  check_columns(type, coordinates);
  const detail::IsotropicConstants c = constants_of(material);
  const Eigen::Index size = 3 * node_count(type);
  ElementMatrices e;
  e.stiffness.resize(size, size);
  e.mass.resize(size, size);
  e.volume = detail::element_kernel(type, coordinates.data(), c, e.stiffness.data(), e.mass.data());
  if (!(e.volume > 0.0))
    throw std::invalid_argument(std::string(abaqus_name(type)) +
                                ": det J <= 0 at an integration point or the centre (inverted "
                                "or degenerate element)");
  return e;
}

Eigen::MatrixXd element_stiffness(ElementType type, const Eigen::Matrix3Xd& coordinates,
                                  const Material& material) {
  return element_matrices(type, coordinates, material).stiffness;
}

Eigen::MatrixXd element_mass(ElementType type, const Eigen::Matrix3Xd& coordinates,
                             const Material& material) {
  return element_matrices(type, coordinates, material).mass;
}

Vector6d element_centre_strain(ElementType type, const Eigen::Matrix3Xd& coordinates,
                               const Eigen::VectorXd& displacements) {
  check_columns(type, coordinates);
  const Eigen::Index n = coordinates.cols();
  if (displacements.size() != 3 * n)
    throw std::invalid_argument("element_centre_strain: displacements must have 3n entries");
  const Eigen::Matrix3Xd dn = shape_derivatives(type, centre_natural_coordinates(type));
  const Eigen::Matrix3d j = dn * coordinates.transpose();
  if (!(j.determinant() > 0.0))
    throw std::invalid_argument("element_centre_strain: det J <= 0 at the centre");
  const Eigen::Matrix3Xd g = j.inverse() * dn;
  // Displacement gradient H_ij = ∂u_i/∂x_j = Σ_a u_ia g_ja.
  const Eigen::Map<const Eigen::Matrix3Xd> u(displacements.data(), 3, n);
  const Eigen::Matrix3d h = u * g.transpose();
  Vector6d e;
  e << h(0, 0), h(1, 1), h(2, 2), h(0, 1) + h(1, 0), h(1, 2) + h(2, 1), h(2, 0) + h(0, 2);
  return e;
}

Vector6d element_centre_stress(ElementType type, const Eigen::Matrix3Xd& coordinates,
                               const Material& material, const Eigen::VectorXd& displacements) {
  return elasticity_matrix(material) * element_centre_strain(type, coordinates, displacements);
}

}  // namespace jointhb::fe
