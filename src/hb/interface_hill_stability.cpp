// Hill's method for a finite-element joint's harmonic-balance solution
// (hb/interface_hill_stability.hpp, eq. T-36a).
#include "jointhb/hb/interface_hill_stability.hpp"

#include <stdexcept>

#include "../support/lapack_lu.hpp"
#include "floquet_input.hpp"
#include "hill_companion.hpp"

namespace jointhb::hb {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// ∂residual/∂y at the evaluation `at` (scaled rows): its dense matrix, or column by column from
// apply_jacobian when the balance assembles only the point blocks.
MatrixXd dense_jacobian(const InterfaceBalance& balance, const InterfaceBalanceEvaluation& at,
                        double omega) {
  const Eigen::Index u = balance.unknowns();
  if (at.jacobian.rows() == u && at.jacobian.cols() == u) return at.jacobian;
  MatrixXd j(u, u);
  VectorXd unit = VectorXd::Zero(u);
  for (Eigen::Index c = 0; c < u; ++c) {
    unit[c] = 1.0;
    j.col(c) = balance.apply_jacobian(at, omega, 0.0, unit);
    unit[c] = 0.0;
  }
  return j;
}

// S of eq. T-36a in unscaled modal rows, over the elastic kept modes (j ≥ rigid_modes):
// ω_ref² (J_ηη − J_ηg J_gg⁻¹ J_gη) of the scaled Jacobian (the gap rows' scale cancels in
// J_gg⁻¹ J_gη). A rigid-body mode does not move the interface (Gφ_j = 0): nothing couples it, and
// its exponents 0 and −a are left out. Empty when J_gg is singular.
MatrixXd condensed_stiffness(const InterfaceBalance& balance, const MatrixXd& j) {
  const Eigen::Index m = balance.basis().size();
  const Eigen::Index first = static_cast<Eigen::Index>(balance.model().rigid_modes) * m;
  const Eigen::Index modal = static_cast<Eigen::Index>(balance.modes()) * m;
  const Eigen::Index elastic = modal - first;
  const Eigen::Index gaps = j.rows() - modal;
  const support::LapackLu gap_block(j.bottomRightCorner(gaps, gaps));
  if (!(gap_block.rcond() > 0.0)) return {};
  MatrixXd s = j.block(first, first, elastic, elastic);
  s.noalias() -= j.block(first, modal, elastic, gaps) *
                 gap_block.solve_columns(j.block(modal, first, gaps, elastic));
  s *= balance.reference_omega() * balance.reference_omega();
  return s;
}

// The companion matrix of (S + λΔ₁ + λ² I) P_η = 0 over the elastic kept modes:  [0, I; −S, −Δ₁],
// Δ₁ = diag(c_j) ⊗ I + 2 I ⊗ D_Ω with c_j = a + b ω_j² (Rayleigh damping of mode j).
MatrixXd companion_matrix(const InterfaceBalance& balance, const MatrixXd& s, double omega) {
  const InterfaceModel& model = balance.model();
  const int m = balance.basis().size();
  const Eigen::Index size = s.rows();
  const MatrixXd d = detail::time_derivative(balance.basis(), omega);
  MatrixXd a = MatrixXd::Zero(2 * size, 2 * size);
  a.topRightCorner(size, size).setIdentity();
  a.bottomLeftCorner(size, size) = -s;
  for (int j = model.rigid_modes; j < balance.modes(); ++j) {
    const Eigen::Index o = static_cast<Eigen::Index>(j - model.rigid_modes) * m;
    const double damping = model.rayleigh_mass + model.rayleigh_stiffness * model.omega2[j];
    auto block = a.block(size + o, size + o, m, m);
    block = -2.0 * d;
    block.diagonal().array() -= damping;
  }
  return a;
}

}  // namespace

FloquetResult interface_hill_floquet(const InterfaceBalance& balance, const VectorXd& y,
                                     double omega, const HillOptions& options) {
  if (auto msg = options.validate(); !msg.empty()) throw std::invalid_argument(msg);
  FloquetResult out;
  out.message = detail::floquet_input_problem("interface_hill_floquet", "unknowns", y, balance.unknowns(), omega);
  if (!out.message.empty()) return out;
  InterfaceBalanceEvaluation at;
  balance.evaluate(y, omega, 0.0, VectorXd(), true, at);
  if (!at.ok) {
    out.message = "the Jacobian could not be evaluated: " + at.message;
    return out;
  }
  const MatrixXd s = condensed_stiffness(balance, dense_jacobian(balance, at, omega));
  if (s.size() == 0) {
    out.message = "the gap rows' block J_gg of the Jacobian is singular";
    return out;
  }
  return detail::floquet_from_companion(companion_matrix(balance, s, omega), balance.basis(),
                                        balance.modes() - balance.model().rigid_modes, omega, options);
}

}  // namespace jointhb::hb
