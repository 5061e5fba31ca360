// Error estimates of finite-element damping-curve and FRF points
// (continuation/interface_error_estimate.hpp).
#include "jointhb/continuation/interface_error_estimate.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <tuple>
#include <utility>

#include "../support/gmres.hpp"
#include "error_estimate_support.hpp"

namespace jointhb::continuation {
namespace {

using InterfaceOperator = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

// GMRES of an estimate's Newton step: cycles of kInterfaceEstimateKrylov iterations (each from the
// true residual of the last), at most kInterfaceEstimateCycles. An estimate needs two correct
// digits, the step is accepted at a true relative residual of kInterfaceEstimateAccuracy.
constexpr int kInterfaceEstimateKrylov = 100;
constexpr int kInterfaceEstimateCycles = 4;
constexpr double kInterfaceEstimateKrylovTolerance = 1e-8;
constexpr double kInterfaceEstimateAccuracy = 1e-4;
// Newton iterations of the H + 2 solution, converged when ‖R‖∞ ≤ kInterfaceEstimateTolerance (rows
// in units of the modal amplitude, as the curves' residual_tolerance 1e-10).
constexpr int kInterfaceEstimateIterations = 10;
constexpr double kInterfaceEstimateTolerance = 1e-10;
constexpr double kInterfaceEstimateDigits = 1e-3;

// δ with J δ = −r: LU of `dense` when it is formed, else GMRES on `apply` preconditioned by
// `precondition`; nullopt when the solve fails or δ is not finite.
std::optional<Eigen::VectorXd> interface_estimate_step(const Eigen::MatrixXd& dense, const InterfaceOperator& apply,
                                                       const InterfaceOperator& precondition, const Eigen::VectorXd& r) {
  if (dense.size() > 0) {
    if (dense.rows() != r.size() || dense.cols() != r.size()) return std::nullopt;
    Eigen::VectorXd step = -Eigen::PartialPivLU<Eigen::MatrixXd>(dense).solve(r);
    return step.allFinite() ? std::optional<Eigen::VectorXd>(std::move(step)) : std::nullopt;
  }
  const double norm = r.norm();
  if (!std::isfinite(norm)) return std::nullopt;
  Eigen::VectorXd step = Eigen::VectorXd::Zero(r.size());
  Eigen::VectorXd rest = -r;  // −r − J δ
  for (int cycle = 0; cycle < kInterfaceEstimateCycles && rest.norm() > kInterfaceEstimateAccuracy * norm; ++cycle) {
    Eigen::VectorXd dz;
    support::gmres(apply, precondition, rest, kInterfaceEstimateKrylov, kInterfaceEstimateKrylovTolerance, dz);
    if (!dz.allFinite()) return std::nullopt;
    step += dz;
    rest = -r - apply(step);
  }
  if (!(rest.norm() <= kInterfaceEstimateAccuracy * norm)) return std::nullopt;
  return step;
}

// The Newton step −J⁻¹ r of EPMC residual `mode` at the evaluation `at` (with the Jacobian) of (Ŷ, λ).
std::optional<Eigen::VectorXd> mode_estimate_step(const hb::InterfaceModeResidual& mode,
                                                  const hb::InterfaceModeResidual::Evaluation& at,
                                                  const Eigen::VectorXd& y_hat, double lambda, const Eigen::VectorXd& r) {
  if (mode.balance().options().dense_jacobian) return interface_estimate_step(at.d_state, {}, {}, r);
  const InterfaceOperator apply = [&](const Eigen::VectorXd& v) { return mode.apply_jacobian(at, y_hat, lambda, v); };
  return interface_estimate_step(Eigen::MatrixXd(), apply,
                                 mode.preconditioner(at, y_hat, lambda, hb::InterfacePreconditioner::point_local), r);
}

// The same for the forced balance `b` at the evaluation `at` of (y, Ω), ξ = 0.
std::optional<Eigen::VectorXd> balance_estimate_step(const hb::InterfaceBalance& b, const hb::InterfaceBalanceEvaluation& at,
                                                     double omega, const Eigen::VectorXd& r) {
  if (b.options().dense_jacobian) return interface_estimate_step(at.jacobian, {}, {}, r);
  const InterfaceOperator apply = [&](const Eigen::VectorXd& v) { return b.apply_jacobian(at, omega, 0.0, v); };
  return interface_estimate_step(Eigen::MatrixXd(), apply,
                                 b.preconditioner(at, omega, 0.0, hb::InterfacePreconditioner::point_local), r);
}

// DOFs of the DOF-major coefficient layout of a balance: n_s modal coordinates and 3P gaps.
int interface_estimate_dofs(const hb::InterfaceBalance& b) { return b.modes() + 3 * b.points(); }

// Newton's method at a fixed parameter from y to ‖R‖∞ ≤ tolerance, or until a full step changes y
// by at most kInterfaceEstimateDigits of its change from `origin` (the transferred point): the
// estimate is then converged to three digits, which is all it needs (the residual of a joint can
// stall near 1e-9 where the periodic states' tolerance limits it), and that last step is taken
// without evaluating after it (Newton's next step would be smaller still). Other steps are halved
// (down to 1/16) until the residual norm falls. `evaluate(y, at)` evaluates with the Jacobian,
// `step(at, y)` is −J⁻¹R or nullopt. On success `at` holds the last evaluation: at the returned y,
// or one step before it (*stepped = true).
template <class Evaluation, class Evaluate, class Step>
bool converge_finer(Eigen::VectorXd& y, const Eigen::VectorXd& origin, double tolerance, const Evaluate& evaluate,
                    const Step& step, Evaluation& at, bool* stepped) {
  *stepped = false;
  evaluate(y, at);
  if (!at.ok || !at.residual.allFinite()) return false;
  double norm = at.residual.template lpNorm<Eigen::Infinity>();
  for (int it = 0; it < kInterfaceEstimateIterations && norm > tolerance; ++it) {
    const std::optional<Eigen::VectorXd> d = step(at, y);
    if (!d) return false;
    const double scale = y.template lpNorm<Eigen::Infinity>();
    if (d->template lpNorm<Eigen::Infinity>() <=
        kInterfaceEstimateDigits * (y + *d - origin).template lpNorm<Eigen::Infinity>() + 1e-14 * scale) {
      y += *d;
      *stepped = true;
      return true;
    }
    bool moved = false;
    for (double alpha = 1.0; alpha >= 1.0 / 16.0 && !moved; alpha *= 0.5) {
      Evaluation trial;
      const Eigen::VectorXd y_trial = y + alpha * *d;
      evaluate(y_trial, trial);
      const double trial_norm =
          trial.ok && trial.residual.allFinite() ? trial.residual.template lpNorm<Eigen::Infinity>() : norm;
      if (trial_norm < norm) {
        y = y_trial;
        at = std::move(trial);
        norm = trial_norm;
        moved = true;
      }
    }
    if (!moved) return false;
  }
  return norm <= tolerance;
}

// |fundamental| and max_t |u(t)| of output `output` of balance b at y, from an evaluation `at` of y.
std::pair<double, double> interface_frf_outputs(const hb::InterfaceBalance& b, int output, const Eigen::VectorXd& y,
                                                double omega, const Eigen::VectorXd& load,
                                                const hb::InterfaceBalanceEvaluation& at) {
  const Eigen::VectorXd u = b.output_coefficients(output, y, omega, 0.0, load, at.contact_force);
  const int a1 = b.basis().cosine_index(1);
  return {std::hypot(u[a1], u[a1 + 1]), b.basis().peak_magnitude(u)};
}

// The outputs at y + δ (one more evaluation, without the Jacobian); nullopt when it fails.
std::optional<std::pair<double, double>> interface_frf_outputs_at(const hb::InterfaceBalance& b, int output,
                                                                  const Eigen::VectorXd& y, double omega,
                                                                  const Eigen::VectorXd& load) {
  hb::InterfaceBalanceEvaluation at;
  b.evaluate(y, omega, 0.0, load, false, at);
  if (!at.ok) return std::nullopt;
  return interface_frf_outputs(b, output, y, omega, load, at);
}

}  // namespace

InterfaceBackboneErrorEstimator::InterfaceBackboneErrorEstimator(const hb::InterfaceModel& model,
                                                                 const hb::InterfaceModeOptions& options)
    : finer_(model, [&] {
        hb::InterfaceModeOptions o = options;
        o.balance = estimate_detail::finer_options(o.balance, true);
        return o;
      }()),
      sampled_(model, [&] {
        hb::InterfaceModeOptions o = options;
        o.balance = estimate_detail::finer_options(o.balance, false);
        return o;
      }()) {}

BackboneError InterfaceBackboneErrorEstimator::estimate(const hb::InterfaceModeResidual& base,
                                                        const Eigen::VectorXd& y_hat, double lambda,
                                                        const hb::InterfaceModeResidual::Evaluation* at_point,
                                                        bool truncation) {
  BackboneError e;
  e.truncation_known = truncation;
  const hb::InterfaceBalance& coarse = base.balance();
  const hb::InterfaceBalance& fine = finer_.balance();
  const int dofs = interface_estimate_dofs(coarse);
  const Eigen::Index nb = coarse.unknowns(), nf = fine.unknowns();
  // (T-41b): Ŷ at H transferred to H + 2 (the new harmonics zero), Newton's method at fixed λ to
  // the H + 2 solution. One step is not enough on a joint: the loops of its points change shape
  // when harmonics are admitted, and the first step missed the converged change by 4× or in sign
  // in microslip (docs/theory.md §13).
  Eigen::VectorXd yf(finer_.unknowns());
  yf.head(nf) = hb::transfer_coefficients(coarse.basis(), fine.basis(), y_hat.head(nb), dofs);
  yf.tail(2) = y_hat.tail(2);
  const Eigen::VectorXd transferred = yf;
  const auto solve = [&](Eigen::VectorXd start) -> std::optional<Eigen::VectorXd> {
    hb::InterfaceModeResidual::Evaluation at_fine;
    bool stepped = false;  // Ω, ξ are unknowns: no evaluation needed after the last step
    const bool ok = converge_finer(
        start, transferred, kInterfaceEstimateTolerance,
        [&](const Eigen::VectorXd& at_y, hb::InterfaceModeResidual::Evaluation& out) { finer_.evaluate(at_y, lambda, true, out); },
        [&](const hb::InterfaceModeResidual::Evaluation& at, const Eigen::VectorXd& at_y) {
          return mode_estimate_step(finer_, at, at_y, lambda, at.residual);
        },
        at_fine, &stepped);
    return ok ? std::optional<Eigen::VectorXd>(std::move(start)) : std::nullopt;
  };
  if (truncation) {
    std::optional<Eigen::VectorXd> solved;
    if (carried_.size() == transferred.size()) solved = solve(transferred + carried_);
    if (!solved) solved = solve(transferred);  // from the point alone
    carried_ = solved ? Eigen::VectorXd(*solved - transferred) : Eigen::VectorXd();
    if (!solved) return e;
    yf = *solved;
  }
  // (T-42): the residual with 2 N_t samples, the step with the N_t Jacobian.
  hb::InterfaceModeResidual::Evaluation sampled, evaluated;
  sampled_.evaluate(y_hat, lambda, false, sampled);
  const bool has_jacobian = at_point && at_point->ok &&
                            (base.balance().options().dense_jacobian ? at_point->d_state.size() > 0
                                                                     : !at_point->balance.point_blocks.empty());
  if (!has_jacobian) base.evaluate(y_hat, lambda, true, evaluated);
  const hb::InterfaceModeResidual::Evaluation& at = has_jacobian ? *at_point : evaluated;
  if (!sampled.ok || !at.ok) return e;
  const std::optional<Eigen::VectorXd> aliasing = mode_estimate_step(base, at, y_hat, lambda, sampled.residual);
  if (!aliasing) return e;
  if (truncation)
    std::tie(e.omega.truncation, e.damping.truncation) = estimate_detail::mode_changes(
        y_hat.tail(2), yf.tail(2) - y_hat.tail(2));  // (Ω, ξ) of the H + 2 solution against the point's
  std::tie(e.omega.aliasing, e.damping.aliasing) = estimate_detail::mode_changes(y_hat, *aliasing);
  e.known = std::isfinite(e.omega.worst()) && std::isfinite(e.damping.worst());
  if (!e.known) e = BackboneError{};
  return e;
}

InterfaceFrfErrorEstimator::InterfaceFrfErrorEstimator(const hb::InterfaceModel& model,
                                                       const hb::InterfaceBalanceOptions& options,
                                                       double load_amplitude, int output)
    : finer_(model, estimate_detail::finer_options(options, true)),
      sampled_(model, estimate_detail::finer_options(options, false)),
      load_amplitude_(load_amplitude),
      output_(output),
      // |F| max|φᵀf| / ω_ref²: the static modal response (trace_interface_frf's residual_scale)
      residual_scale_(std::abs(load_amplitude) * std::max(model.load_modal.lpNorm<Eigen::Infinity>(), 1e-300) /
                      (finer_.reference_omega() * finer_.reference_omega())) {}

FrfError InterfaceFrfErrorEstimator::estimate(const hb::InterfaceBalance& base, const Eigen::VectorXd& y,
                                              double omega, const hb::InterfaceBalanceEvaluation* given,
                                              bool truncation) {
  FrfError e;
  e.truncation_known = truncation;
  const Eigen::VectorXd load = base.cosine_load(load_amplitude_);
  const Eigen::VectorXd load_fine = finer_.cosine_load(load_amplitude_);
  const bool has_jacobian =
      given && given->ok && (base.options().dense_jacobian ? given->jacobian.size() > 0 : !given->point_blocks.empty());
  hb::InterfaceBalanceEvaluation evaluated;
  if (!has_jacobian) base.evaluate(y, omega, 0.0, load, true, evaluated);
  const hb::InterfaceBalanceEvaluation& at_point = has_jacobian ? *given : evaluated;
  if (!at_point.ok) return e;
  const auto [h1, peak] = interface_frf_outputs(base, output_, y, omega, load, at_point);
  // (T-41b) at fixed Ω: Newton's method at H + 2 from the transferred coefficients, converged to
  // the curve's tolerance in units of the static modal response (as trace_interface_frf scales it).
  const int dofs = interface_estimate_dofs(base);
  const Eigen::VectorXd transferred = hb::transfer_coefficients(base.basis(), finer_.basis(), y, dofs);
  bool stepped = false;
  const auto solve = [&](Eigen::VectorXd start, hb::InterfaceBalanceEvaluation& at_fine) -> std::optional<Eigen::VectorXd> {
    const bool ok = converge_finer(
        start, transferred, kInterfaceEstimateTolerance * residual_scale_,
        [&](const Eigen::VectorXd& at_y, hb::InterfaceBalanceEvaluation& out) {
          finer_.evaluate(at_y, omega, 0.0, load_fine, true, out);
        },
        [&](const hb::InterfaceBalanceEvaluation& at, const Eigen::VectorXd&) {
          return balance_estimate_step(finer_, at, omega, at.residual);
        },
        at_fine, &stepped);
    return ok ? std::optional<Eigen::VectorXd>(std::move(start)) : std::nullopt;
  };
  // The outputs at H + 2 (the point's own where the truncation part is not asked for).
  double h1_finer = h1, peak_finer = peak;
  if (truncation) {
    hb::InterfaceBalanceEvaluation at_fine;
    std::optional<Eigen::VectorXd> solved;
    if (carried_.size() == transferred.size()) solved = solve(transferred + carried_, at_fine);
    if (!solved) solved = solve(transferred, at_fine);  // from the point alone
    carried_ = solved ? Eigen::VectorXd(*solved - transferred) : Eigen::VectorXd();
    if (!solved) return e;
    const Eigen::VectorXd& yf = *solved;
    // The outputs need the contact forces at yf: one evaluation without the Jacobian after a last
    // step that was not evaluated.
    if (stepped) {
      const std::optional<std::pair<double, double>> truncated =
          interface_frf_outputs_at(finer_, output_, yf, omega, load_fine);
      if (!truncated) return e;
      std::tie(h1_finer, peak_finer) = *truncated;
    } else {
      std::tie(h1_finer, peak_finer) = interface_frf_outputs(finer_, output_, yf, omega, load_fine, at_fine);
    }
  }
  // (T-42) at fixed Ω.
  hb::InterfaceBalanceEvaluation sampled;
  sampled_.evaluate(y, omega, 0.0, load, false, sampled);
  if (!sampled.ok) return e;
  const std::optional<Eigen::VectorXd> aliasing = balance_estimate_step(base, at_point, omega, sampled.residual);
  if (!aliasing) return e;
  const auto aliased = interface_frf_outputs_at(base, output_, y + *aliasing, omega, load);
  if (!aliased) return e;
  e.amplitude_h1 = {estimate_detail::relative_change(h1_finer, h1), estimate_detail::relative_change(aliased->first, h1)};
  e.amplitude_max = {estimate_detail::relative_change(peak_finer, peak),
                     estimate_detail::relative_change(aliased->second, peak)};
  e.known = std::isfinite(e.amplitude_h1.worst()) && std::isfinite(e.amplitude_max.worst());
  if (!e.known) e = FrfError{};
  return e;
}

}  // namespace jointhb::continuation
