// EPMC of a preloaded FE joint in modal/interface form (interface_mode.hpp).
#include "jointhb/hb/interface_mode.hpp"

#include <Eigen/LU>

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

namespace jointhb::hb {

std::string InterfaceModeOptions::validate(const InterfaceModel& model) const {
  if (std::string msg = balance.validate(); !msg.empty()) return msg;
  const int elastic = model.num_modes() - model.rigid_modes;
  if (mode < 1 || mode > elastic)
    return fmt::format("mode: must be in [1, {}] (elastic kept modes), got {}", elastic, mode);
  return {};
}

InterfaceModeResidual::InterfaceModeResidual(InterfaceModel model, InterfaceModeOptions options)
    : balance_([&] {
        if (std::string msg = options.validate(model); !msg.empty()) throw std::invalid_argument(msg);
        return InterfaceBalance(std::move(model), options.balance);
      }()) {
  mode_ = balance_.model().rigid_modes + options.mode - 1;
}

double InterfaceModeResidual::linear_omega() const { return std::sqrt(balance_.model().omega2[mode_]); }

double InterfaceModeResidual::linear_damping_ratio() const {
  const InterfaceModel& m = balance_.model();
  return (m.rayleigh_mass + m.rayleigh_stiffness * m.omega2[mode_]) / (2.0 * linear_omega());
}

Eigen::VectorXd InterfaceModeResidual::linear_start() const {
  const InterfaceModel& m = balance_.model();
  const int a1 = balance_.basis().cosine_index(1);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(unknowns());
  y[balance_.modal_index(mode_, a1)] = 1.0;
  for (int p = 0; p < balance_.points(); ++p)
    for (int d = 0; d < 3; ++d) y[balance_.gap_index(p, d, a1)] = m.gap_shapes(3 * p + d, mode_);
  y[unknowns() - 2] = linear_omega();
  y[unknowns() - 1] = 2.0 * linear_damping_ratio() * linear_omega();
  return y;
}

void InterfaceModeResidual::evaluate(const Eigen::VectorXd& y_hat, double lambda, bool jacobian,
                                     Evaluation& out) const {
  const Eigen::Index U = balance_.unknowns();
  if (y_hat.size() != U + 2)
    throw std::invalid_argument(fmt::format("InterfaceModeResidual: {} unknowns, expected {}", y_hat.size(), U + 2));
  const double q = std::pow(10.0, lambda);
  const double omega = y_hat[U], xi = y_hat[U + 1];
  const Eigen::VectorXd y = q * y_hat.head(U);
  balance_.evaluate(y, omega, xi, Eigen::VectorXd(), jacobian, out.balance);
  out.ok = out.balance.ok;
  out.message = out.balance.message;
  const int a1 = balance_.basis().cosine_index(1);
  const Eigen::Index ia = balance_.modal_index(mode_, a1), ib = ia + 1;
  out.residual.resize(U + 2);
  out.residual.head(U) = out.balance.residual / q;
  out.residual[U] = y_hat[ia] - 1.0;
  out.residual[U + 1] = y_hat[ib];
  if (!jacobian) return;
  if (!balance_.options().dense_jacobian) {
    out.d_state.resize(0, 0);
    out.d_parameter = Eigen::VectorXd::Zero(U + 2);
    out.d_parameter.head(U) = std::numbers::ln10 * (balance_.apply_jacobian(out.balance, omega, xi, y_hat.head(U)) -
                                                     out.residual.head(U));
    return;
  }
  const Eigen::MatrixXd& J = out.balance.jacobian;
  out.d_state.setZero(U + 2, U + 2);
  out.d_state.topLeftCorner(U, U) = J;
  out.d_state.block(0, U, U, 1) = out.balance.d_omega / q;
  out.d_state.block(0, U + 1, U, 1) = out.balance.d_xi / q;
  out.d_state(U, ia) = 1.0;
  out.d_state(U + 1, ib) = 1.0;
  // d/dλ [R(qŷ)/q] = ln 10 · (J ŷ − R/q): only the nonlinear part contributes.
  out.d_parameter = Eigen::VectorXd::Zero(U + 2);
  out.d_parameter.head(U) = std::numbers::ln10 * (J * y_hat.head(U) - out.residual.head(U));
}

Eigen::VectorXd InterfaceModeResidual::apply_jacobian(const Evaluation& at, const Eigen::VectorXd& y_hat,
                                                      double lambda, const Eigen::VectorXd& v,
                                                      bool single_precision) const {
  const Eigen::Index U = balance_.unknowns();
  const double q = std::pow(10.0, lambda);
  const double omega = y_hat[U], xi = y_hat[U + 1];
  const int a1 = balance_.basis().cosine_index(1);
  const Eigen::Index ia = balance_.modal_index(mode_, a1), ib = ia + 1;
  Eigen::VectorXd out(U + 2);
  out.head(U) = balance_.apply_jacobian(at.balance, omega, xi, v.head(U), single_precision) +
                (at.balance.d_omega * v[U] + at.balance.d_xi * v[U + 1]) / q;
  out[U] = v[ia];
  out[U + 1] = v[ib];
  return out;
}

// M = [J̃ C; Eᵀ 0], C = [∂R/∂Ω, ∂R/∂ξ]/q, Eᵀ picks (η_f a₁, η_f b₁):
//   W = J̃⁻¹ C, S = Eᵀ W (2 × 2);  z₂ = S⁻¹ (Eᵀ J̃⁻¹ v₁ − v₂),  z₁ = J̃⁻¹ v₁ − W z₂.
std::function<Eigen::VectorXd(const Eigen::VectorXd&)> InterfaceModeResidual::preconditioner(
    const Evaluation& at, const Eigen::VectorXd& y_hat, double lambda, InterfacePreconditioner kind) const {
  const Eigen::Index U = balance_.unknowns();
  const double q = std::pow(10.0, lambda);
  const double omega = y_hat[U], xi = y_hat[U + 1];
  const int a1 = balance_.basis().cosine_index(1);
  const Eigen::Index ia = balance_.modal_index(mode_, a1), ib = ia + 1;
  // At the linear start (Ω = ω_f, ξ = c_f) the followed mode's fundamental block of the balance
  // Jacobian is singular (the free vibration solves it); the bordering below removes that
  // direction, but an approximate inverse that is exact there (one contact point, every mode kept:
  // J_loc or J̃ is then the Jacobian itself) divides by zero. Then the balance's block is taken at
  // ξ + 1e-6 ω_f instead: nonsingular, and still an approximate inverse.
  std::function<Eigen::VectorXd(const Eigen::VectorXd&)> pc = balance_.preconditioner(at.balance, omega, xi, kind);
  Eigen::MatrixXd w(U, 2);
  w.col(0) = pc(at.balance.d_omega / q);
  w.col(1) = pc(at.balance.d_xi / q);
  if (!w.allFinite()) {
    pc = balance_.preconditioner(at.balance, omega, xi + 1e-6 * linear_omega(), kind);
    w.col(0) = pc(at.balance.d_omega / q);
    w.col(1) = pc(at.balance.d_xi / q);
  }
  Eigen::Matrix2d s;
  s << w(ia, 0), w(ia, 1), w(ib, 0), w(ib, 1);
  const Eigen::Matrix2d s_inverse = s.inverse();
  return [pc, w, s_inverse, U, ia, ib](const Eigen::VectorXd& v) {
    Eigen::VectorXd z(U + 2);
    const Eigen::VectorXd w1 = pc(v.head(U));
    const Eigen::Vector2d z2 = s_inverse * Eigen::Vector2d(w1[ia] - v[U], w1[ib] - v[U + 1]);
    z.head(U) = w1 - w * z2;
    z.tail(2) = z2;
    return z;
  };
}

InterfaceModeState InterfaceModeResidual::state(const Eigen::VectorXd& y_hat, double lambda,
                                                const Evaluation* at_point) const {
  Evaluation local;
  if (at_point == nullptr) {
    evaluate(y_hat, lambda, false, local);
    at_point = &local;
  }
  const Eigen::Index U = balance_.unknowns();
  const double q = std::pow(10.0, lambda);
  InterfaceModeState s;
  s.amplitude = q;
  s.omega = y_hat[U];
  s.damping_ratio = y_hat[U + 1] / (2.0 * s.omega);
  s.dissipation = at_point->balance.dissipation;
  s.fourier_dissipation = at_point->balance.fourier_dissipation;
  s.open_points = at_point->balance.open_points;
  s.slipping_points = at_point->balance.slipping_points;
  s.states = at_point->balance.states;
  const InterfaceModel& m = balance_.model();
  const FourierBasis& basis = balance_.basis();
  for (int j = 0; j < balance_.modes(); ++j) {
    const double c = m.rayleigh_mass + m.rayleigh_stiffness * m.omega2[j];
    for (int k : basis.orders()) {
      const int ia = basis.cosine_index(k);
      const double a = q * y_hat[balance_.modal_index(j, ia)], b = q * y_hat[balance_.modal_index(j, ia + 1)];
      s.viscous_dissipation += std::numbers::pi * c * k * k * s.omega * (a * a + b * b);
      s.injected_energy += std::numbers::pi * y_hat[U + 1] * k * k * s.omega * (a * a + b * b);
    }
  }
  s.damping_ratio_energy = (s.dissipation + s.viscous_dissipation) / (2.0 * std::numbers::pi * s.omega * s.omega * q * q);
  return s;
}

}  // namespace jointhb::hb
