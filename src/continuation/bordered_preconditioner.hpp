#pragma once
// The block-elimination preconditioner of a bordered matrix (internal to the continuation layer;
// docs/continuation.md §2), shared by the continuation's matrix-free solves (pseudo_arclength.cpp)
// and the refinement of extrema (curve_refinement.cpp):
//   M = [ K   j ],  K⁻¹ ≈ k_inverse:   w₁ = K⁻¹ v_x,  w₂ = K⁻¹ j,
//       [ c_xᵀ c_λ ]                   z_λ = (v_λ − c_xᵀ w₁) / (c_λ − c_xᵀ w₂),  z_x = w₁ − w₂ z_λ,
// with z_λ = 0 where the Schur complement c_λ − c_xᵀ w₂ vanishes to round-off.

#include <Eigen/Core>
#include <cmath>
#include <utility>

#include "jointhb/continuation/pseudo_arclength.hpp"

namespace jointhb::continuation::detail {

class BorderedPreconditioner {
 public:
  /// `j` (n) the border column, `c` (n + 1) the border row.
  BorderedPreconditioner(LinearOperator k_inverse, const Eigen::VectorXd& j, const Eigen::VectorXd& c)
      : k_inverse_(std::move(k_inverse)), c_(c), n_(j.size()), w2_(k_inverse_(j)) {
    den_ = c[n_] - c.head(n_).dot(w2_);
    border_ = std::abs(den_) > 1e-14 * (std::abs(c[n_]) + c.head(n_).norm() * w2_.norm());
  }

  /// M⁻¹ v (n + 1).
  [[nodiscard]] Eigen::VectorXd operator()(const Eigen::VectorXd& v) const {
    Eigen::VectorXd z(n_ + 1);
    const Eigen::VectorXd w1 = k_inverse_(v.head(n_));
    const double zl = border_ ? (v[n_] - c_.head(n_).dot(w1)) / den_ : 0.0;
    z.head(n_) = w1 - w2_ * zl;
    z[n_] = zl;
    return z;
  }

 private:
  LinearOperator k_inverse_;
  const Eigen::VectorXd& c_;
  Eigen::Index n_;
  Eigen::VectorXd w2_;  // K⁻¹ j
  double den_ = 0.0;    // c_λ − c_xᵀ w₂
  bool border_ = false;
};

}  // namespace jointhb::continuation::detail
