// Gaul–Mayer microslip law, eq. (10), integrated exactly over an increment (gaul_mayer_law.hpp).
//
// With y = |F|/F_s and the complement c(y) = 1 - (1-y)^{1-n}, a loading increment of slip m gives
//   c_1 = c_0 + (1-n) k m / F_s          (exact solution of eq. 10 at constant F_s, k)
// and full slip once c_1 ≥ 1. Working with c (through log1p/expm1) keeps tiny forces accurate to
// round-off; (1-y)^{1-n} itself would lose all digits of y below ~1e-16.
#include "jointhb/contact/gaul_mayer_law.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "jointhb/contact/closed_forms.hpp"

namespace jointhb::contact {
namespace {

// Loading in direction s from |F| = y0 F_s over the slip m ≥ 0 (eq. 10).
// The dissipation integral (T-6) is evaluated only when `dissipation` is set.
ScalarStep load(double y0, double m, double s, double n, double fs, double k, bool dissipation) {
  ScalarStep r;
  r.loading_slip = m;
  if (y0 >= 1.0) {  // already sliding: Coulomb
    r.force = s * fs;
    r.d_limit = s;
    r.dissipation = fs * m;
    return r;
  }
  const double log_u0 = std::log1p(-y0);
  const double c0 = -std::expm1((1.0 - n) * log_u0);
  const double c1 = c0 + (1.0 - n) * k * m / fs;
  if (c1 >= 1.0) {  // full slip reached inside the increment, then Coulomb sliding
    const double reach = (1.0 - c0) * fs / ((1.0 - n) * k);
    r.force = s * fs;
    r.d_limit = s;
    r.dissipation = fs * (m - reach);
    if (dissipation) {
      r.dissipation +=
          fs * fs / k * closed_form::loading_dissipation_integral(y0, 1.0 - c0, 1.0, 0.0, n);
    }
    return r;
  }
  const double log_u1 = std::log1p(-c1) / (1.0 - n);
  const double y1 = -std::expm1(log_u1);
  const double psi1 = std::exp(n * log_u1);  // (1 - y1)^n: loading factor at the end
  const double psi0 = std::exp(n * log_u0);
  r.force = s * fs * y1;
  r.d_force = psi1 / psi0;  // ≤ 1: bounded even as y0 → 1
  r.d_slip = k * psi1;
  r.d_stiffness = s * psi1 * m;
  r.d_limit = s * (y1 - psi1 * (y0 / psi0 + k * m / fs));
  if (dissipation) {
    r.dissipation =
        fs * fs / k * closed_form::loading_dissipation_integral(y0, 1.0 - c0, y1, 1.0 - c1, n);
  }
  return r;
}

}  // namespace

GaulMayerLaw::GaulMayerLaw(double exponent) : n_(exponent) {
  if (!(exponent > 0.0 && exponent < 1.0)) {
    throw std::invalid_argument("gaul-mayer law: exponent n must lie in (0, 1), got " +
                                std::to_string(exponent));
  }
}

double GaulMayerLaw::virgin_force(double s, const TangentialLimits& limits) const {
  return closed_form::virgin_force(s, {n_, limits.slip_limit, limits.stiffness});
}

ScalarStep GaulMayerLaw::evaluate(double f0, double slip, const TangentialLimits& limits,
                                  bool dissipation) const {
  const double fs = limits.slip_limit;
  const double k = limits.stiffness;
  ScalarStep r;
  if (fs <= 0.0) return r;  // open contact: no tangential force
  if (f0 > fs) f0 = fs;     // tolerate round-off above the limit
  if (f0 < -fs) f0 = -fs;
  if (slip == 0.0) {
    r.force = f0;
    r.d_force = 1.0;
    r.d_slip = k;  // the elastic (reversal) tangent
    return r;
  }
  const double s = slip > 0.0 ? 1.0 : -1.0;
  const double m = std::abs(slip);
  if (f0 * s >= 0.0) return load(std::abs(f0) / fs, m, s, n_, fs, k, dissipation);

  // Elastic unloading while |F| decreases.
  const double to_zero = std::abs(f0) / k;
  if (m <= to_zero) {
    r.force = f0 + k * slip;
    r.d_force = 1.0;
    r.d_slip = k;
    r.d_stiffness = slip;
    return r;
  }
  // Unloading passes through F = 0: split there, load from zero over the rest.
  const double rest = m - to_zero;
  ScalarStep v = load(0.0, rest, s, n_, fs, k, dissipation);
  const double dv = s * v.d_slip;  // dF/d(rest) along s, = s k ψ_1
  // rest = s·slip + s·f0/k  ⇒  ∂rest/∂f0 = s/k, ∂rest/∂slip = s, ∂rest/∂k = |f0|/k²
  r.force = v.force;
  r.d_force = dv * s / k;
  r.d_slip = dv * s;
  r.d_limit = v.d_limit;
  r.d_stiffness = v.d_stiffness + dv * std::abs(f0) / (k * k);
  r.dissipation = v.dissipation;
  r.loading_slip = rest;
  return r;
}

}  // namespace jointhb::contact
