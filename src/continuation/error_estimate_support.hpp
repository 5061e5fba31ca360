#pragma once
// What the error estimates of discrete and finite-element curves share (error_estimate.cpp,
// interface_error_estimate.cpp; docs/theory.md §13): the rows a coarser basis keeps, relative
// changes, the outputs of an EPMC point and the options of the two finer balances.

#include <Eigen/Core>
#include <cmath>
#include <utility>

#include "jointhb/continuation/error_estimate.hpp"
#include "jointhb/hb/fourier.hpp"

namespace jointhb::continuation::estimate_detail {

/// 1 on the rows of `to` (DOF-major coefficients of `dofs` DOFs) whose harmonic `from` keeps, 0
/// on the new ones: the transfer of ones.
inline Eigen::VectorXd kept_rows(const hb::FourierBasis& from, const hb::FourierBasis& to, int dofs) {
  return hb::transfer_coefficients(from, to,
                                   Eigen::VectorXd::Ones(static_cast<Eigen::Index>(dofs) * from.size()),
                                   dofs);
}

/// (after − before)/|before|, or after − before where before = 0.
inline double relative_change(double after, double before) {
  const double change = after - before;
  return before != 0.0 ? change / std::abs(before) : change;
}

/// The relative changes of Ω and ζ = ξ/(2Ω) from EPMC unknowns y (…, Ω, ξ) to y + δ.
inline std::pair<double, double> mode_changes(const Eigen::VectorXd& y, const Eigen::VectorXd& step) {
  const Eigen::Index n = y.size();
  const double omega = y[n - 2], xi = y[n - 1];
  const double omega1 = omega + step[n - 2], xi1 = xi + step[n - 1];
  return {relative_change(omega1, omega), relative_change(xi1 / (2.0 * omega1), xi / (2.0 * omega))};
}

/// The options of the finer balance: H + 2 harmonics with N_t' samples (T-41) when `finer`, else
/// 2 N_t samples at the same H (T-42). One template for every options struct that names both
/// fields `harmonics` and `time_samples`.
template <class BalanceOptions>
BalanceOptions finer_options(BalanceOptions o, bool finer) {
  if (finer) {
    o.time_samples = truncation_time_samples(o.harmonics, o.time_samples);
    o.harmonics += 2;
  } else {
    o.time_samples *= 2;
  }
  return o;
}

}  // namespace jointhb::continuation::estimate_detail
