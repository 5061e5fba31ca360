// Error estimates of discrete damping-curve and FRF points (continuation/error_estimate.hpp).
#include "jointhb/continuation/error_estimate.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>
#include <utility>

#include "error_estimate_support.hpp"

namespace jointhb::continuation {
namespace {

using estimate_detail::finer_options;
using estimate_detail::kept_rows;
using estimate_detail::mode_changes;
using estimate_detail::relative_change;

// δ = −J⁻¹ R (dense LU with partial pivoting), nullopt when J is singular or δ not finite.
std::optional<Eigen::VectorXd> estimate_newton_step(const Eigen::MatrixXd& j,
                                                    const Eigen::VectorXd& r) {
  if (j.rows() != r.size() || j.cols() != r.size()) return std::nullopt;
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(j);
  Eigen::VectorXd step = -lu.solve(r);
  if (!step.allFinite()) return std::nullopt;
  return step;
}

// |fundamental| and max_t |x(t)| of DOF `dof` of coefficients x of balance b.
std::pair<double, double> estimate_frf_outputs(const hb::HarmonicBalance& b,
                                               const Eigen::VectorXd& x, int dof) {
  const hb::FourierBasis& basis = b.basis();
  return {b.fundamental_amplitude(x, dof),
          basis.peak_magnitude(x.segment(b.index(dof, 0), basis.size()))};
}

}  // namespace

double ErrorPair::worst() const { return std::max(std::abs(truncation), std::abs(aliasing)); }

int truncation_time_samples(int harmonics, int time_samples) {
  return std::max(time_samples, 2 * (harmonics + 2) + 2);
}

BackboneErrorEstimator::BackboneErrorEstimator(const hb::DiscreteSystem& system,
                                               const hb::NonlinearModeOptions& options)
    : finer_(system, finer_options(options, true)),
      sampled_(system, finer_options(options, false)) {}

BackboneError BackboneErrorEstimator::estimate(const hb::NonlinearModeResidual& base,
                                               const Eigen::VectorXd& y, double lambda) const {
  BackboneError e;
  const Eigen::Index nb = base.balance().unknowns();
  const int dofs = base.balance().system().dofs();
  // (T-41): Y at H transferred to H + 2 (the new harmonics zero), one Newton step at fixed λ.
  Eigen::VectorXd yf(finer_.unknowns());
  yf.head(finer_.balance().unknowns()) =
      hb::transfer_coefficients(base.balance().basis(), finer_.balance().basis(), y.head(nb), dofs);
  yf.tail(2) = y.tail(2);
  hb::NonlinearModeResidual::Evaluation ev;
  finer_.evaluate(yf, lambda, true, ev);
  if (!ev.ok) return e;
  // The rows of the new harmonics alone (T-41): the others hold the tolerance and, where N_t' >
  // N_t, the sampling change that (T-42) estimates; the amplitude and phase rows involve harmonic 1
  // only.
  const Eigen::Index nf = finer_.balance().unknowns();
  Eigen::VectorXd r_new = Eigen::VectorXd::Zero(ev.residual.size());
  r_new.head(nf) = ev.residual.head(nf).cwiseProduct(
      Eigen::VectorXd::Ones(nf) -
      kept_rows(base.balance().basis(), finer_.balance().basis(), dofs));
  const std::optional<Eigen::VectorXd> truncation = estimate_newton_step(ev.d_state, r_new);
  if (!truncation) return e;
  // (T-42): the residual with 2 N_t samples, the step with the N_t Jacobian.
  hb::NonlinearModeResidual::Evaluation fine, jac;
  sampled_.evaluate(y, lambda, false, fine);
  base.evaluate(y, lambda, true, jac);
  if (!fine.ok || !jac.ok) return e;
  const std::optional<Eigen::VectorXd> aliasing = estimate_newton_step(jac.d_state, fine.residual);
  if (!aliasing) return e;
  std::tie(e.omega.truncation, e.damping.truncation) = mode_changes(yf, *truncation);
  std::tie(e.omega.aliasing, e.damping.aliasing) = mode_changes(y, *aliasing);
  e.known = std::isfinite(e.omega.worst()) && std::isfinite(e.damping.worst());
  if (!e.known) e = BackboneError{};
  return e;
}

FrfErrorEstimator::FrfErrorEstimator(const hb::DiscreteSystem& system,
                                     const hb::Excitation& excitation,
                                     const hb::HarmonicBalanceOptions& options)
    : finer_(system, excitation, finer_options(options, true)),
      sampled_(system, excitation, finer_options(options, false)) {}

FrfError FrfErrorEstimator::estimate(const hb::HarmonicBalance& base, const Eigen::VectorXd& x,
                                     double omega, int dof) const {
  FrfError e;
  const auto [h1, peak] = estimate_frf_outputs(base, x, dof);
  // (T-41) at fixed Ω.
  const Eigen::VectorXd xf =
      hb::transfer_coefficients(base.basis(), finer_.basis(), x, base.system().dofs());
  hb::HarmonicBalanceEvaluation ev;
  finer_.evaluate(xf, omega, true, ev);
  if (!ev.ok) return e;
  // The rows of the new harmonics alone, as for the damping curve.
  const Eigen::VectorXd r_new = ev.residual.cwiseProduct(
      Eigen::VectorXd::Ones(ev.residual.size()) -
      kept_rows(base.basis(), finer_.basis(), base.system().dofs()));
  const std::optional<Eigen::VectorXd> truncation = estimate_newton_step(ev.d_coefficients, r_new);
  if (!truncation) return e;
  const auto [h1_t, peak_t] = estimate_frf_outputs(finer_, xf + *truncation, dof);
  // (T-42) at fixed Ω.
  hb::HarmonicBalanceEvaluation fine, jac;
  sampled_.evaluate(x, omega, false, fine);
  base.evaluate(x, omega, true, jac);
  if (!fine.ok || !jac.ok) return e;
  const std::optional<Eigen::VectorXd> aliasing =
      estimate_newton_step(jac.d_coefficients, fine.residual);
  if (!aliasing) return e;
  const auto [h1_a, peak_a] = estimate_frf_outputs(base, x + *aliasing, dof);
  e.amplitude_h1 = {relative_change(h1_t, h1), relative_change(h1_a, h1)};
  e.amplitude_max = {relative_change(peak_t, peak), relative_change(peak_a, peak)};
  e.known = std::isfinite(e.amplitude_h1.worst()) && std::isfinite(e.amplitude_max.worst());
  if (!e.known) e = FrfError{};
  return e;
}

namespace {

// Newton at fixed parameter with step halving: `evaluate(y, jacobian)` returns {R, J, ok};
// converged when the scaled residual norm ‖R‖∞/scale ≤ tolerance.
template <class Evaluate>
std::optional<Eigen::VectorXd> estimate_newton_solve(const Evaluate& evaluate, Eigen::VectorXd y,
                                                     double tolerance, double scale,
                                                     int iterations) {
  auto [r, j, ok] = evaluate(y, true);
  if (!ok) return std::nullopt;
  for (int it = 0; it < iterations; ++it) {
    const double norm = r.template lpNorm<Eigen::Infinity>();
    const std::optional<Eigen::VectorXd> step = estimate_newton_step(j, r);
    if (norm <= tolerance * scale) {
      // One more full step polishes the rows of small scale (Newton converges quadratically).
      if (step) {
        auto [rt, jt, okt] = evaluate(y + *step, false);
        if (okt && rt.template lpNorm<Eigen::Infinity>() <= 2.0 * norm) y += *step;
      }
      return y;
    }
    if (!step) return std::nullopt;
    bool moved = false;
    for (double alpha = 1.0; alpha >= 1.0 / 1024.0; alpha *= 0.5) {
      const Eigen::VectorXd trial = y + alpha * *step;
      auto [rt, jt, okt] = evaluate(trial, true);
      if (okt && rt.template lpNorm<Eigen::Infinity>() < norm) {
        y = trial;
        r = std::move(rt);
        j = std::move(jt);
        moved = true;
        break;
      }
    }
    if (!moved) return std::nullopt;
  }
  return r.template lpNorm<Eigen::Infinity>() <= tolerance * scale
             ? std::optional<Eigen::VectorXd>(y)
             : std::nullopt;
}

}  // namespace

std::optional<Eigen::VectorXd> solve_mode_at(const hb::NonlinearModeResidual& r, Eigen::VectorXd y,
                                             double lambda, double tolerance, int iterations) {
  const auto evaluate = [&](const Eigen::VectorXd& at, bool jacobian) {
    hb::NonlinearModeResidual::Evaluation ev;
    r.evaluate(at, lambda, jacobian, ev);
    return std::tuple<Eigen::VectorXd, Eigen::MatrixXd, bool>{std::move(ev.residual),
                                                              std::move(ev.d_state), ev.ok};
  };
  // R̂'s scale is the stiffness seen by the mode, ω² (as in trace_backbone); the amplitude and
  // phase rows are O(1) and polished by the last step.
  const double scale = std::max(1.0, r.linear_omega() * r.linear_omega());
  return estimate_newton_solve(evaluate, std::move(y), tolerance, scale, iterations);
}

std::optional<Eigen::VectorXd> solve_balance_at(const hb::HarmonicBalance& b, Eigen::VectorXd x,
                                                double omega, double tolerance, double scale,
                                                int iterations) {
  const auto evaluate = [&](const Eigen::VectorXd& at, bool jacobian) {
    hb::HarmonicBalanceEvaluation ev;
    b.evaluate(at, omega, jacobian, ev);
    return std::tuple<Eigen::VectorXd, Eigen::MatrixXd, bool>{std::move(ev.residual),
                                                              std::move(ev.d_coefficients), ev.ok};
  };
  return estimate_newton_solve(evaluate, std::move(x), tolerance, scale, iterations);
}

}  // namespace jointhb::continuation
