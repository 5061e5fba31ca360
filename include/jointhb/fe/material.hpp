#pragma once
// Isotropic linear-elastic material of a part (SI units) and its elasticity matrix.
//
// Voigt order used throughout the FE stage: (xx, yy, zz, xy, yz, zx), with engineering shear
// strains γ_xy = 2ε_xy etc., so that σ = D ε and the strain energy density is ½ εᵀ D ε.

#include <Eigen/Core>
#include <string>

namespace jointhb::fe {

struct Material {
  std::string name;             ///< for messages
  double youngs_modulus = 0.0;  ///< E [Pa], > 0
  double poissons_ratio = 0.0;  ///< ν [-], -1 < ν < 0.5
  double density = 0.0;         ///< ρ [kg/m³], > 0

  /// Empty when valid, else a message naming the field, its value and the violated constraint.
  [[nodiscard]] std::string validate() const;

  /// Lamé's first parameter λ = E ν / ((1 + ν)(1 − 2ν)) [Pa].
  [[nodiscard]] double lame_lambda() const;
  /// Shear modulus μ = G = E / (2 (1 + ν)) [Pa].
  [[nodiscard]] double shear_modulus() const;
};

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// The isotropic elasticity matrix D (σ = D ε, Voigt order above):
///   D = λ m mᵀ + μ diag(2, 2, 2, 1, 1, 1),  m = (1, 1, 1, 0, 0, 0)ᵀ
/// (e.g. Zienkiewicz, Taylor & Zhu, The Finite Element Method, 7th ed., vol. 1, eq. 6.14).
/// Throws std::invalid_argument when material.validate() is not empty.
[[nodiscard]] Matrix6d elasticity_matrix(const Material& material);

}  // namespace jointhb::fe
