#pragma once
// A discrete harmonic balance (hb/harmonic_balance.hpp) seen by the continuation layer: its
// residual as a ResidualFunction of (X, Ω), and the delay of its coefficients by a phase of the
// fundamental (the predictor of the crossing at fixed phase, phase_bridge.hpp).

#include <cmath>
#include <utility>

#include "jointhb/hb/harmonic_balance.hpp"
#include "phase_bridge.hpp"

namespace jointhb::continuation::detail {

/// R(X, Ω) of `b` with its dense Jacobian (b must outlive the function).
inline ResidualFunction residual_of(const hb::HarmonicBalance& b) {
  return [&b](const Eigen::VectorXd& x, double omega, bool jacobian) {
    hb::HarmonicBalanceEvaluation ev;
    b.evaluate(x, omega, jacobian, ev);
    Evaluation e;
    e.ok = ev.ok;
    e.message = ev.message;
    e.residual = std::move(ev.residual);
    e.d_state = std::move(ev.d_coefficients);
    e.d_parameter = std::move(ev.d_omega);
    return e;
  };
}

/// X delayed by φ/Ω: harmonic h of each of the `dofs` signals turned by hφ,
/// (a, b) ↦ (a cos hφ − b sin hφ, a sin hφ + b cos hφ) (b must outlive the function).
inline PhaseRotation harmonic_rotation(const hb::HarmonicBalance& b, int dofs) {
  return [&b, dofs](const Eigen::VectorXd& x, double phi) {
    Eigen::VectorXd out = x;
    for (int dof = 0; dof < dofs; ++dof) {
      for (const int h : b.basis().orders()) {
        const Eigen::Index i = b.index(dof, b.basis().cosine_index(h));
        const double cs = std::cos(h * phi), sn = std::sin(h * phi);
        out[i] = x[i] * cs - x[i + 1] * sn;
        out[i + 1] = x[i] * sn + x[i + 1] * cs;
      }
    }
    return out;
  };
}

}  // namespace jointhb::continuation::detail
