#pragma once
// Floquet multipliers of linear systems in closed form, shared by the tests of
// hb/hill_stability.hpp, hb/orbit_monodromy.hpp and timeint/shooting.hpp: for a linear system the
// exponents are the eigenvalues λ of the first-order system [0 I; −M⁻¹K −M⁻¹C] and the
// multipliers e^{λT}, whatever the forcing and Ω.
#include <Eigen/Dense>
#include <complex>
#include <limits>
#include <vector>

#include "jointhb/hb/discrete_system.hpp"

namespace jointhb::hb::testing {

/// M = diag(1, 2), K = [3 −1; −1 1.5], C = [0.05 −0.01; −0.01 0.03].
inline DiscreteSystem two_dof_linear() {
  DiscreteSystem s;
  Eigen::MatrixXd m(2, 2), k(2, 2), c(2, 2);
  m << 1.0, 0.0, 0.0, 2.0;
  k << 3.0, -1.0, -1.0, 1.5;
  c << 0.05, -0.01, -0.01, 0.03;
  s.mass = m.sparseView();
  s.stiffness = k.sparseView();
  s.damping = c.sparseView();
  return s;
}

/// Eigenvalues λ of ẏ = [0 I; −M⁻¹K −M⁻¹C] y, K = the given stiffness.
inline Eigen::VectorXcd first_order_eigenvalues(const DiscreteSystem& s, const Eigen::MatrixXd& k) {
  const Eigen::Index n = s.dofs();
  const Eigen::MatrixXd m(s.mass), c(s.damping);
  const Eigen::MatrixXd minv = m.inverse();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -minv * k;
  a.bottomRightCorner(n, n) = -minv * c;
  return Eigen::EigenSolver<Eigen::MatrixXd>(a, false).eigenvalues();
}

/// e^{λT} for each λ.
inline std::vector<std::complex<double>> exact_multipliers(const Eigen::VectorXcd& lambda,
                                                           double period) {
  std::vector<std::complex<double>> r;
  for (const std::complex<double>& l : lambda) r.push_back(std::exp(l * period));
  return r;
}

/// max_j |ρ_j − expected_j| over a nearest-neighbour matching (each computed value used once).
inline double matched_error(const Eigen::VectorXcd& rho,
                            const std::vector<std::complex<double>>& expected) {
  std::vector<bool> used(static_cast<std::size_t>(rho.size()), false);
  double worst = 0.0;
  for (const std::complex<double>& e : expected) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t at = 0;
    for (Eigen::Index i = 0; i < rho.size(); ++i) {
      if (!used[static_cast<std::size_t>(i)] && std::abs(rho[i] - e) < best) {
        best = std::abs(rho[i] - e);
        at = static_cast<std::size_t>(i);
      }
    }
    used[at] = true;
    worst = std::max(worst, best);
  }
  return worst;
}

}  // namespace jointhb::hb::testing
