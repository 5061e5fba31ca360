#pragma once
// A-posteriori error estimates of one converged point of a discrete damping curve
// (continuation/backbone.hpp) or FRF (continuation/frf.hpp), docs/theory.md §13:
//   truncation (T-41): the converged coefficients transferred to H + 2 harmonics (same selection,
//     N_t' = max(N_t, 2(H + 2) + 2)), one Newton step there with the continuation parameter fixed,
//     δ = −J'⁻¹ R'_new (R' on the rows of the new harmonics, zero on the others: those hold only
//     the tolerance and, where N_t' > N_t, a sampling change that the aliasing estimate covers);
//     the change of the outputs under δ;
//   aliasing (T-42): the residual with 2 N_t samples at the same H and coefficients, one Newton
//   step
//     with the N_t Jacobian; the change of the outputs under it.
// The outputs: Ω and ζ = ξ/(2Ω) of a damping-curve point (λ = log10 q fixed), amplitude_h1 and
// amplitude_max of an FRF point (Ω fixed). Each estimate is a signed relative change,
// (refined − point)/|point|: its magnitude estimates the error, its sign the direction.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/hb/harmonic_balance.hpp"
#include "jointhb/hb/nonlinear_mode.hpp"

namespace jointhb::continuation {

/// The two estimates of one output's relative error (signed, see above).
struct ErrorPair {
  double truncation = 0.0;  ///< from the H + 2 Newton step (T-41)
  double aliasing = 0.0;    ///< from the 2 N_t Newton step (T-42)
  /// max(|truncation|, |aliasing|)
  [[nodiscard]] double worst() const;
};

/// The estimates of a damping-curve point; known = false: not computed (error_estimate off) or
/// failed at the point (a contact's periodic state or the solve failed; the values are then 0).
struct BackboneError {
  bool known = false;
  /// false: the truncation parts were not computed at this point (they are 0; the aliasing parts
  /// are): with `accuracy`, at the largest H it allows, where no raise is possible, finite-element
  /// curves compute them at every third point only (accuracy.hpp).
  bool truncation_known = true;
  ErrorPair omega;    ///< δΩ/Ω
  ErrorPair damping;  ///< δζ/|ζ| (δζ itself where ζ = 0)
};

/// The estimates of an FRF point (known as in BackboneError).
struct FrfError {
  bool known = false;
  bool truncation_known = true;  ///< as in BackboneError
  ErrorPair amplitude_h1;   ///< δ|fundamental|/|fundamental| of the output DOF
  ErrorPair amplitude_max;  ///< δ max_t |x_out(t)| / max_t |x_out(t)|
};

/// N_t' of the H + 2 basis of (T-41): max(N_t, 2(H + 2) + 2).
[[nodiscard]] int truncation_time_samples(int harmonics, int time_samples);

/// The two finer EPMC residuals of a damping curve's estimates (built once per curve).
class BackboneErrorEstimator {
 public:
  /// Throws std::invalid_argument as hb::NonlinearModeResidual does (e.g. a basis too large).
  BackboneErrorEstimator(const hb::DiscreteSystem& system, const hb::NonlinearModeOptions& options);
  /// The estimates at the converged point (y, λ) of `base` (the curve's own residual).
  [[nodiscard]] BackboneError estimate(const hb::NonlinearModeResidual& base,
                                       const Eigen::VectorXd& y, double lambda) const;

 private:
  hb::NonlinearModeResidual finer_;    // H + 2, N_t'
  hb::NonlinearModeResidual sampled_;  // H, 2 N_t
};

/// The two finer harmonic balances of an FRF's estimates (built once per curve).
class FrfErrorEstimator {
 public:
  /// Throws std::invalid_argument as hb::HarmonicBalance does.
  FrfErrorEstimator(const hb::DiscreteSystem& system, const hb::Excitation& excitation,
                    const hb::HarmonicBalanceOptions& options);
  /// The estimates at the converged point (x, Ω) of `base`, for the output DOF `dof`.
  [[nodiscard]] FrfError estimate(const hb::HarmonicBalance& base, const Eigen::VectorXd& x,
                                  double omega, int dof) const;

 private:
  hb::HarmonicBalance finer_;
  hb::HarmonicBalance sampled_;
};

/// Newton's method at a fixed parameter (λ or Ω) from y, with step halving on the residual norm:
/// the converged references of the tests and of validation/hb/error_estimate.cpp. nullopt unless
/// ‖R‖∞ ≤ tolerance · scale within `iterations` (scale = max(1, ω²) for the EPMC), then one
/// more full step.
[[nodiscard]] std::optional<Eigen::VectorXd> solve_mode_at(const hb::NonlinearModeResidual& r,
                                                           Eigen::VectorXd y, double lambda,
                                                           double tolerance, int iterations = 60);
[[nodiscard]] std::optional<Eigen::VectorXd> solve_balance_at(const hb::HarmonicBalance& b,
                                                              Eigen::VectorXd x, double omega,
                                                              double tolerance, double scale,
                                                              int iterations = 60);

}  // namespace jointhb::continuation
