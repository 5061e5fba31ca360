#pragma once
// The residual-mode coefficients of harmonic k (docs/theory.md §11, eq. T-23), shared by the
// interface balance and its preconditioners (internal header).
#include <complex>

#include "jointhb/hb/interface_model.hpp"

namespace jointhb::hb::detail {

using cd = std::complex<double>;

// The residual-mode coefficients of harmonic k (eq. T-23): h ≈ c0/μ + c1/μ², with their
// derivatives in Ω and ξ.
struct ResidualCoefficients {
  cd c0, c1, c0_omega, c1_omega, c0_xi, c1_xi;
};

inline ResidualCoefficients residual_coefficients(const InterfaceModel& m, int k, double omega,
                                           double xi) {
  const double kw = k * omega;
  const double s = m.residual_shift, a = m.rayleigh_mass, b = m.rayleigh_stiffness;
  const cd i(0.0, 1.0);
  const cd beta = 1.0 + i * kw * b;
  const cd w = s * beta - kw * kw + i * kw * (a - xi);
  const cd beta_omega = i * double(k) * b;
  const cd w_omega = s * beta_omega - 2.0 * k * kw + i * double(k) * (a - xi);
  const cd w_xi = -i * kw;
  ResidualCoefficients r;
  r.c0 = 1.0 / beta;
  r.c1 = -w / (beta * beta);
  r.c0_omega = -beta_omega / (beta * beta);
  r.c1_omega = -w_omega / (beta * beta) + 2.0 * w * beta_omega / (beta * beta * beta);
  r.c0_xi = 0.0;
  r.c1_xi = -w_xi / (beta * beta);
  return r;
}

}  // namespace jointhb::hb::detail
