// Material (fe/material.hpp): validation messages and the isotropic elasticity matrix.
#include "jointhb/fe/material.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <stdexcept>

namespace jointhb::fe {
namespace {

Material steel_material() { return {"steel", 210e9, 0.3, 7850.0}; }

TEST(Material, ValidateNamesTheField) {
  EXPECT_EQ(steel_material().validate(), "");
  Material m = steel_material();
  m.youngs_modulus = 0.0;
  EXPECT_NE(m.validate().find("youngs_modulus"), std::string::npos);
  m = steel_material();
  m.poissons_ratio = 0.5;
  EXPECT_NE(m.validate().find("poissons_ratio"), std::string::npos);
  m.poissons_ratio = -1.0;
  EXPECT_NE(m.validate().find("poissons_ratio"), std::string::npos);
  m = steel_material();
  m.density = -1.0;
  EXPECT_NE(m.validate().find("density"), std::string::npos);
  EXPECT_THROW((void)elasticity_matrix(m), std::invalid_argument);
}

TEST(Material, ElasticityMatrixIsHookesLaw) {
  const Material m = steel_material();
  const Matrix6d d = elasticity_matrix(m);
  EXPECT_TRUE(d.isApprox(d.transpose(), 0.0));
  // Uniaxial stress σ_xx = E ε_xx with lateral strains −ν ε_xx (D⁻¹ = compliance).
  Vector6d sigma = Vector6d::Zero();
  sigma(0) = 1e6;
  const Vector6d eps = d.ldlt().solve(sigma);
  EXPECT_NEAR(eps(0), 1e6 / m.youngs_modulus, 1e-12 * eps(0));
  EXPECT_NEAR(eps(1), -m.poissons_ratio * eps(0), 1e-12 * eps(0));
  EXPECT_NEAR(eps(2), -m.poissons_ratio * eps(0), 1e-12 * eps(0));
  // Engineering shear: τ_xy = G γ_xy; the order is xy, yz, zx.
  const double g = m.youngs_modulus / (2.0 * (1.0 + m.poissons_ratio));
  for (int i = 3; i < 6; ++i) EXPECT_DOUBLE_EQ(d(i, i), g);
  EXPECT_NEAR(d(0, 1), m.lame_lambda(), 1e-6);
  EXPECT_NEAR(d(0, 0), m.lame_lambda() + 2.0 * g, 1e-3);
}

}  // namespace
}  // namespace jointhb::fe
