#pragma once
// GMRES with right preconditioning, without restart (Saad & Schultz 1986; Saad, "Iterative
// Methods for Sparse Linear Systems", 2nd ed. 2003, Alg. 9.5): for A z = b, with x₀ = 0,
//   z_k = M⁻¹ V_k y_k,   y_k = argmin_y ‖ β e₁ − H̄_k y ‖₂,   β = ‖b‖₂,
// where V_k is the Arnoldi basis of the Krylov space K_k(A M⁻¹, b) (modified Gram–Schmidt, one
// re-orthogonalisation pass) and H̄_k the (k+1) × k Hessenberg matrix, reduced by Givens
// rotations so that |g_{k+1}| = ‖b − A z_k‖₂ in exact arithmetic. Right preconditioning minimises
// the true residual, not the preconditioned one. Serial and deterministic.

#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <vector>

namespace jointhb::support {

struct GmresOutcome {
  bool converged = false;  ///< the recursive residual fell below tolerance · ‖b‖₂
  int iterations = 0;      ///< Arnoldi steps (products with A)
  double residual = 0.0;   ///< last recursive residual estimate / ‖b‖₂
};

/// Solves A z = b; `apply` computes A v, `precondition` M⁻¹ v. z holds the iterate on return
/// (also when not converged). The caller should check the true residual: in floating point the
/// recursive estimate can drift below it.
inline GmresOutcome gmres(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& apply,
                          const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& precondition,
                          const Eigen::VectorXd& b, int max_iterations, double tolerance,
                          Eigen::VectorXd& z) {
  using Eigen::VectorXd;
  GmresOutcome out;
  const Eigen::Index n = b.size();
  z = VectorXd::Zero(n);
  const double beta = b.norm();
  if (!(beta > 0.0)) {
    out.converged = std::isfinite(beta);
    return out;
  }
  const int k_max = max_iterations;
  std::vector<VectorXd> v;
  v.reserve(static_cast<std::size_t>(k_max) + 1);
  v.push_back(b / beta);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(k_max + 1, k_max);
  VectorXd cs = VectorXd::Zero(k_max), sn = VectorXd::Zero(k_max), g = VectorXd::Zero(k_max + 1);
  g(0) = beta;
  int k = 0;
  out.residual = 1.0;
  for (; k < k_max; ++k) {
    VectorXd w = apply(precondition(v[static_cast<std::size_t>(k)]));
    for (int pass = 0; pass < 2; ++pass) {
      for (int i = 0; i <= k; ++i) {
        const double hik = w.dot(v[static_cast<std::size_t>(i)]);
        h(i, k) += hik;
        w -= hik * v[static_cast<std::size_t>(i)];
      }
    }
    h(k + 1, k) = w.norm();
    for (int i = 0; i < k; ++i) {  // previous rotations on the new column
      const double t = cs(i) * h(i, k) + sn(i) * h(i + 1, k);
      h(i + 1, k) = -sn(i) * h(i, k) + cs(i) * h(i + 1, k);
      h(i, k) = t;
    }
    const double r = std::hypot(h(k, k), h(k + 1, k));
    if (!(r > 0.0) || !std::isfinite(r)) break;  // A M⁻¹ singular on the Krylov space
    cs(k) = h(k, k) / r;
    sn(k) = h(k + 1, k) / r;
    const double hk1 = h(k + 1, k);
    h(k, k) = r;
    h(k + 1, k) = 0.0;
    g(k + 1) = -sn(k) * g(k);
    g(k) = cs(k) * g(k);
    out.residual = std::abs(g(k + 1)) / beta;
    const bool breakdown = !(hk1 > 0.0);  // lucky breakdown: the Krylov space is invariant
    if (!breakdown) v.push_back(w / hk1);
    if (out.residual <= tolerance || breakdown) {
      ++k;
      out.converged = true;
      break;
    }
  }
  out.iterations = k;
  if (k == 0) return out;
  // y = H_k⁻¹ g_k (upper triangular after the rotations), z = M⁻¹ V_k y.
  VectorXd y = h.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
  VectorXd vy = VectorXd::Zero(n);
  for (int i = 0; i < k; ++i) vy += y(i) * v[static_cast<std::size_t>(i)];
  z = precondition(vy);
  if (!z.allFinite()) out.converged = false;
  return out;
}

}  // namespace jointhb::support
