// Hexahedron shape functions and Gauss rules (fe/hexahedron.hpp).
#include "jointhb/fe/hexahedron.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace jointhb::fe {
namespace {

Eigen::Vector3d random_point(std::mt19937& gen) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return {u(gen), u(gen), u(gen)};
}

class HexShape : public ::testing::TestWithParam<ElementType> {};

TEST_P(HexShape, KroneckerPropertyAtTheNodes) {
  const ElementType type = GetParam();
  const int n = node_count(type);
  for (int b = 0; b < n; ++b) {
    const Eigen::VectorXd shape = shape_functions(type, hex_node_natural_coordinates(b));
    for (int a = 0; a < n; ++a) EXPECT_NEAR(shape(a), a == b ? 1.0 : 0.0, 1e-15) << a << " " << b;
  }
}

TEST_P(HexShape, PartitionOfUnityAndLinearCompleteness) {
  const ElementType type = GetParam();
  const int n = node_count(type);
  std::mt19937 gen(7);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d xi = random_point(gen);
    const Eigen::VectorXd shape = shape_functions(type, xi);
    const Eigen::Matrix3Xd dn = shape_derivatives(type, xi);
    EXPECT_NEAR(shape.sum(), 1.0, 1e-14);
    EXPECT_LT(dn.rowwise().sum().norm(), 1e-14);
    // Σ N_a ξ_a = ξ and Σ ∂N_a/∂ξ_k ξ_a = e_k (isoparametric mapping of the reference cube).
    Eigen::Matrix3Xd nodes(3, n);
    for (int a = 0; a < n; ++a) nodes.col(a) = hex_node_natural_coordinates(a);
    EXPECT_LT((nodes * shape - xi).norm(), 1e-14);
    EXPECT_LT((dn * nodes.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  }
}

TEST_P(HexShape, DerivativesMatchFiniteDifferences) {
  const ElementType type = GetParam();
  std::mt19937 gen(11);
  const double h = 1e-6;
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector3d xi = random_point(gen);
    const Eigen::Matrix3Xd dn = shape_derivatives(type, xi);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(k);
      const Eigen::VectorXd fd =
          (shape_functions(type, xi + step) - shape_functions(type, xi - step)) / (2.0 * h);
      EXPECT_LT((fd - dn.row(k).transpose()).cwiseAbs().maxCoeff(), 1e-9);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Types, HexShape, ::testing::Values(ElementType::hex8, ElementType::hex20),
                         [](const auto& p) { return std::string(abaqus_name(p.param)); });

TEST(HexGaussRule, WeightsAndPolynomialExactness) {
  for (int n = 1; n <= 3; ++n) {
    const auto& rule = hex_gauss_rule(n);
    ASSERT_EQ(rule.size(), static_cast<std::size_t>(n * n * n));
    double sum = 0.0, moment = 0.0;
    for (const GaussPoint& p : rule) {
      sum += p.weight;
      // ∫ ξ^(2n−2) η² ζ^0 over the cube = 2/(2n − 1) · 2/3 · 2 (η² needs n ≥ 2).
      moment += p.weight * std::pow(p.xi(0), 2 * n - 2) * (n >= 2 ? p.xi(1) * p.xi(1) : 1.0);
    }
    EXPECT_NEAR(sum, 8.0, 1e-14);
    const double exact = 2.0 / (2 * n - 1) * (n >= 2 ? 2.0 / 3.0 : 2.0) * 2.0;
    EXPECT_NEAR(moment, exact, 1e-14) << n;
  }
  EXPECT_THROW((void)hex_gauss_rule(4), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::fe
