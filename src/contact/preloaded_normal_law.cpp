// The exponential normal contact about its preload (contact/preloaded_normal_law.hpp, N-3).
#include "jointhb/contact/preloaded_normal_law.hpp"

#include <cmath>

namespace jointhb::contact {

double PreloadedNormalLaw::force(double gap, double preload, double stiffness) {
  return -preload * std::expm1(-stiffness / preload * gap);  // F_N0 (1 − e^{−λg}), exact near 0
}

double PreloadedNormalLaw::tangent(double gap, double preload, double stiffness) {
  return stiffness * std::exp(-stiffness / preload * gap);
}

ScalarStep PreloadedNormalLaw::evaluate(double f0, double slip, const TangentialLimits& limits,
                                        bool /*dissipation*/) const {
  // (N-3'): F_N0 − F_1 = (F_N0 − F_0) e^{−λΔg}, λ = k_N/F_N0.
  const double fn = limits.slip_limit;
  const double k = limits.stiffness;
  ScalarStep r;
  if (fn <= 0.0) return r;
  const double lambda = k / fn;
  const double e = std::exp(-lambda * slip);
  const double remaining = (fn - f0) * e;  // F_N(g_1), the contact force left
  r.force = fn - remaining;
  r.d_force = e;
  r.d_slip = lambda * remaining;
  r.d_limit = 1.0 - e - remaining * k * slip / (fn * fn);
  r.d_stiffness = remaining * slip / fn;
  return r;
}

}  // namespace jointhb::contact
