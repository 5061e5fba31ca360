#include "jointhb/hb/jacobian_check.hpp"

#include <algorithm>
#include <cmath>

namespace jointhb::hb {
namespace {
// One-sided differences of a smooth R agree to O(h |R''|); beyond this (relative to max |J|) the
// column straddles a kink.
constexpr double kKinkTolerance = 1e-4;
}  // namespace

JacobianCheck check_jacobian(const HarmonicBalance& balance, const Eigen::VectorXd& x, double omega,
                             double relative_step) {
  HarmonicBalanceEvaluation analytic;
  balance.evaluate(x, omega, true, analytic);
  const Eigen::Index n = x.size();
  const double hx = relative_step * std::max(x.lpNorm<Eigen::Infinity>(), 1e-300);
  HarmonicBalanceEvaluation plus;
  HarmonicBalanceEvaluation minus;
  JacobianCheck c;
  const double jscale = std::max(analytic.d_coefficients.cwiseAbs().maxCoeff(), 1e-300);
  for (Eigen::Index j = 0; j < n; ++j) {
    Eigen::VectorXd xp = x;
    Eigen::VectorXd xm = x;
    xp[j] += hx;
    xm[j] -= hx;
    balance.evaluate(xp, omega, false, plus);
    balance.evaluate(xm, omega, false, minus);
    const Eigen::VectorXd column = (plus.residual - minus.residual) / (2.0 * hx);
    // One-sided differences that disagree reveal a kink of the friction law within ±h (a sample
    // switching between stick and slip): no derivative exists there to compare with.
    const Eigen::VectorXd forward = (plus.residual - analytic.residual) / hx;
    const Eigen::VectorXd backward = (analytic.residual - minus.residual) / hx;
    if ((forward - backward).cwiseAbs().maxCoeff() > kKinkTolerance * jscale) {
      ++c.kinked_columns;
      continue;
    }
    Eigen::Index row = 0;
    const double e = (column - analytic.d_coefficients.col(j)).cwiseAbs().maxCoeff(&row) / jscale;
    if (!(e <= c.max_error)) {  // also catches NaN
      c.max_error = e;
      c.worst_row = row;
      c.worst_column = j;
    }
  }
  const double ho = relative_step * omega;
  balance.evaluate(x, omega + ho, false, plus);
  balance.evaluate(x, omega - ho, false, minus);
  const Eigen::VectorXd d_omega = (plus.residual - minus.residual) / (2.0 * ho);
  const double oscale = std::max({analytic.d_omega.cwiseAbs().maxCoeff(),
                                  jscale * x.lpNorm<Eigen::Infinity>() / omega, 1e-300});
  c.max_error_omega = (d_omega - analytic.d_omega).cwiseAbs().maxCoeff() / oscale;
  return c;
}

}  // namespace jointhb::hb
