#include "jointhb/fe/material.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace jointhb::fe {

std::string Material::validate() const {
  const std::string who = name.empty() ? std::string("material") : "material '" + name + "'";
  if (!(std::isfinite(youngs_modulus) && youngs_modulus > 0.0))
    return fmt::format("{}: youngs_modulus = {} must be > 0 (Pa)", who, youngs_modulus);
  if (!(std::isfinite(poissons_ratio) && poissons_ratio > -1.0 && poissons_ratio < 0.5))
    return fmt::format("{}: poissons_ratio = {} must satisfy -1 < nu < 0.5", who, poissons_ratio);
  if (!(std::isfinite(density) && density > 0.0))
    return fmt::format("{}: density = {} must be > 0 (kg/m^3)", who, density);
  return {};
}

double Material::lame_lambda() const {
  return youngs_modulus * poissons_ratio / ((1.0 + poissons_ratio) * (1.0 - 2.0 * poissons_ratio));
}

double Material::shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poissons_ratio)); }

Matrix6d elasticity_matrix(const Material& material) {
  if (const std::string message = material.validate(); !message.empty())
    throw std::invalid_argument(message);
  const double lambda = material.lame_lambda();
  const double mu = material.shear_modulus();
  Matrix6d d = Matrix6d::Zero();
  d.topLeftCorner<3, 3>().setConstant(lambda);
  for (int i = 0; i < 3; ++i) d(i, i) += 2.0 * mu;
  for (int i = 3; i < 6; ++i) d(i, i) = mu;
  return d;
}

}  // namespace jointhb::fe
