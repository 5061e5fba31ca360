#pragma once
// The 10-DOF chain of the light-damping corpus (validation/hb/light_damping.cpp, `ten_dof_system`),
// shared by the unit tests that reproduce its former known stops: unit masses and springs, x_0 tied
// to ground, Jenkins contacts k_T0 = 2, μF_N = 1 at (1, ground), (3, 2), (5, ground), (7, 6),
// (9, ground); modal damping ratio ζ on every mode of the stuck system (none for ζ = 0).

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "jointhb/hb/discrete_system.hpp"

namespace jointhb::hb::test {

inline DiscreteSystem corpus_chain(double zeta) {
  const int n = 10;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    k(i, i) += 1.0;
    if (i > 0) {
      k(i - 1, i - 1) += 1.0;
      k(i, i - 1) -= 1.0;
      k(i - 1, i) -= 1.0;
    }
  }
  DiscreteSystem s;
  s.mass = Eigen::MatrixXd::Identity(n, n).sparseView();
  s.stiffness = k.sparseView();
  for (const auto& [a, b] : std::vector<std::pair<int, int>>{{1, -1}, {3, 2}, {5, -1}, {7, 6}, {9, -1}}) {
    ContactElement c;
    c.law = "jenkins";
    c.dof_a = a;
    c.dof_b = b;
    c.stiffness = 2.0;
    c.friction_coefficient = 1.0;
    c.normal_force = 1.0;
    s.contacts.push_back(c);
  }
  s.damping = zeta > 0.0 ? modal_damping_matrix(s.mass, stuck_stiffness(s), std::vector<double>(n, zeta))
                         : SparseMatrix(Eigen::MatrixXd::Zero(n, n).sparseView());
  return s;
}

}  // namespace jointhb::hb::test
