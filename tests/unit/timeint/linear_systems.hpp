#pragma once
// Linear discrete systems shared by the time-integration tests.

#include <Eigen/Dense>
#include <numbers>

#include "jointhb/hb/discrete_system.hpp"

namespace jointhb::test_systems {

/// A DiscreteSystem from dense M, C, K (no contacts).
inline hb::DiscreteSystem linear_system(const Eigen::MatrixXd& m, const Eigen::MatrixXd& c,
                                        const Eigen::MatrixXd& k) {
  hb::DiscreteSystem s;
  s.mass = m.sparseView();
  s.damping = c.sparseView();
  s.stiffness = k.sparseView();
  return s;
}

/// One DOF: m = 1, ω_n = 2π, damping ratio ζ.
inline hb::DiscreteSystem one_dof(double zeta) {
  constexpr double pi = std::numbers::pi;
  return linear_system(Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Constant(1, 1, 2.0 * zeta * 2.0 * pi),
                       Eigen::MatrixXd::Constant(1, 1, 4.0 * pi * pi));
}

}  // namespace jointhb::test_systems
