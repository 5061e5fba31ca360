#pragma once
// The 1-DOF friction oscillator of the continuation tests: m ẍ + c ẋ + k x + F_T = F cos Ωt with
// m = k = 1 and one Jenkins contact to ground (stiffness k_T0, slip force μF_N, μ = 1); shared by
// test_frf.cpp, frf_stability_test.cpp and phase_bridge_test.cpp.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/hb/harmonic_balance.hpp"

namespace jointhb::continuation::test {

/// m = k = 1, damping c, a Jenkins contact k_T0 = kt0, μF_N = slip_force (none when kt0 = 0).
inline hb::DiscreteSystem jenkins_oscillator(double kt0, double slip_force, double c) {
  hb::DiscreteSystem s;
  s.mass = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  s.stiffness = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  s.damping = Eigen::MatrixXd::Constant(1, 1, c).sparseView();
  if (kt0 > 0.0) {
    hb::ContactElement e;
    e.law = "jenkins";
    e.stiffness = kt0;
    e.friction_coefficient = 1.0;
    e.normal_force = slip_force;
    s.contacts.push_back(e);
  }
  return s;
}

/// F cos Ωt on DOF 0.
inline hb::Excitation force_at_dof0(double amplitude) {
  hb::Excitation e;
  e.forces.push_back({0, amplitude, 1});
  return e;
}

}  // namespace jointhb::continuation::test
