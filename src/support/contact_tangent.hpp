#pragma once
// The symmetric, positive semi-definite part of a contact point's consistent tangent (internal):
//   C̃ = [sym(C_TT)₊  0; 0  max(C_NN, 0)],  sym(A)₊ = the eigen-decomposition of ½(A + Aᵀ) with
// negative eigenvalues set to zero.
// The normal–tangential coupling (∂t_T/∂g_N through μ p_N and k_T(p_N)) makes C non-symmetric and
// a slipping point's tangential tangent can be indefinite; CHOLMOD's LLᵀ needs a symmetric
// positive (semi-)definite contribution. Used as a quasi-Newton matrix by the preload solver
// (preload_solver.cpp) and the FE time integrator (fe_newmark.cpp); their residuals stay exact.

#include <Eigen/Dense>
#include <algorithm>

namespace jointhb::support {

inline Eigen::Matrix3d symmetric_psd_part(const Eigen::Matrix3d& t) {
  const Eigen::Matrix2d tt = 0.5 * (t.topLeftCorner<2, 2>() + t.topLeftCorner<2, 2>().transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(tt);
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  c.topLeftCorner<2, 2>() = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
                            eig.eigenvectors().transpose();
  c(2, 2) = std::max(t(2, 2), 0.0);
  return c;
}

}  // namespace jointhb::support
