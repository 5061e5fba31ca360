#pragma once
// A-posteriori error estimates of one converged point of a finite-element damping curve or FRF
// (continuation/interface_response.hpp), the estimates of continuation/error_estimate.hpp on the
// modal/interface balance (docs/theory.md §13, eq. T-41, T-42):
//   truncation (T-41b): the converged coefficients transferred to H + 2 harmonics (N_t' samples)
//     and Newton's method there at the fixed parameter to the H + 2 solution (not the single step
//     of the discrete estimate: on a joint the first step can miss the change by 4× or in sign);
//   aliasing: the residual with 2 N_t samples at the same H and coefficients, one Newton step with
//     the N_t Jacobian.
// The Newton steps are solved as the curve's own: by LU of the dense Jacobian where the balance
// assembles it, otherwise by GMRES on the matrix-free Jacobian with the point-local preconditioner
// (eq. T-34). Outputs: Ω and ζ of a damping-curve point, amplitude_h1 and amplitude_max of the
// output of an FRF point; signed relative changes as in error_estimate.hpp.

#include <Eigen/Core>

#include "jointhb/continuation/error_estimate.hpp"
#include "jointhb/hb/interface_balance.hpp"
#include "jointhb/hb/interface_mode.hpp"

namespace jointhb::continuation {

/// The two finer EPMC residuals of a finite-element damping curve's estimates (built once per curve).
class InterfaceBackboneErrorEstimator {
 public:
  /// Throws std::invalid_argument as hb::InterfaceModeResidual does.
  InterfaceBackboneErrorEstimator(const hb::InterfaceModel& model, const hb::InterfaceModeOptions& options);
  /// The estimates at the converged point (Ŷ, λ) of `base` (the curve's own residual); known =
  /// false where a periodic state or a linear solve fails. Along a curve, the H + 2 Newton starts
  /// from the point's coefficients plus what the previous point's H + 2 solution added to its own
  /// (the new harmonics carried over): 1–2 iterations instead of 3–6.
  /// `at_point`: an evaluation of `base` at exactly (Ŷ, λ) with its Jacobian (the corrector's
  /// last), which saves one; nullptr: evaluated here. `truncation` = false: the aliasing parts only
  /// (truncation_known = false; the H + 2 start carried over is kept for the next point).
  [[nodiscard]] BackboneError estimate(const hb::InterfaceModeResidual& base, const Eigen::VectorXd& y_hat,
                                       double lambda, const hb::InterfaceModeResidual::Evaluation* at_point = nullptr,
                                       bool truncation = true);

 private:
  hb::InterfaceModeResidual finer_;    // H + 2, N_t'
  hb::InterfaceModeResidual sampled_;  // H, 2 N_t
  Eigen::VectorXd carried_;            // previous H + 2 solution − its transferred point (empty: none)
};

/// The two finer balances of a finite-element FRF's estimates (built once per curve).
class InterfaceFrfErrorEstimator {
 public:
  /// `load_amplitude`: F(t) = amplitude · cos Ωt times the model's load shape; `output`: index
  /// into model.outputs. Throws std::invalid_argument as hb::InterfaceBalance does.
  InterfaceFrfErrorEstimator(const hb::InterfaceModel& model, const hb::InterfaceBalanceOptions& options,
                             double load_amplitude, int output);
  /// The estimates at the converged point (y, Ω) of `base` (the curve's own balance); the H + 2
  /// start carried over from the previous point as for damping curves.
  /// `at_point` and `truncation` as for damping curves.
  [[nodiscard]] FrfError estimate(const hb::InterfaceBalance& base, const Eigen::VectorXd& y, double omega,
                                  const hb::InterfaceBalanceEvaluation* at_point = nullptr, bool truncation = true);

 private:
  hb::InterfaceBalance finer_;
  hb::InterfaceBalance sampled_;
  Eigen::VectorXd carried_;
  double load_amplitude_ = 1.0;
  int output_ = 0;
  double residual_scale_ = 1.0;  // of the H + 2 Newton's convergence test
};

}  // namespace jointhb::continuation
