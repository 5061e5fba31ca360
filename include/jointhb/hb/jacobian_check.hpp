#pragma once
// Finite-difference check of the analytic harmonic-balance Jacobian (Ceres' check_gradients):
// central differences of R(X, Ω) along every unknown and along Ω, compared with ∂R/∂X and ∂R/∂Ω.
// A debugging aid and a user-visible safeguard (`check_jacobian: true` in a case file), never the
// production path: it costs 2(n·m + 1) residual evaluations.

#include <Eigen/Core>

#include "jointhb/hb/harmonic_balance.hpp"

namespace jointhb::hb {

struct JacobianCheck {
  double max_error = 0.0;  ///< max |J_fd − J| over all entries of ∂R/∂X, relative to max |J|
  double max_error_omega = 0.0;  ///< max |∂R/∂Ω_fd − ∂R/∂Ω| relative to max(|∂R/∂Ω|, max |J| |X|/Ω)
  Eigen::Index worst_row = -1;  ///< entry of the largest ∂R/∂X discrepancy
  Eigen::Index worst_column = -1;
  /// Columns skipped because the one-sided differences disagree (a kink of a friction law within
  /// ±h: a sample switching between stick and slip), where no derivative exists to compare.
  int kinked_columns = 0;
};

/// `relative_step` scales the difference step: h = relative_step · max(|X|_∞, tiny) for X and
/// relative_step · Ω for Ω. Kinks of the friction laws inside ±h show up as O(1) errors in the
/// affected entries: such columns are detected (one-sided differences disagree) and skipped.
JacobianCheck check_jacobian(const HarmonicBalance& balance, const Eigen::VectorXd& coefficients,
                             double omega, double relative_step = 1e-6);

}  // namespace jointhb::hb
