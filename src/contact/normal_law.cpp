// The exponential pressure-gap law of Gaul & Mayer, eq. (6):
//   p_N(g_N) = p_N0 exp(-λ (g_N - g_N0)),   k_N = -dp_N/dg_N = λ p_N.
// The law is evaluated for arbitrary closures (a Newton iterate may overshoot far into the
// surface), so the exponent and the pressure are capped to keep p_N and k_N finite.

#include "jointhb/contact/normal_law.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace jointhb::contact {

namespace {

// exp(700) ≈ 1.0e304 is finite in double precision; the product p_N0 exp(x) may still overflow
// for large p_N0, so the pressure is also clamped to a ceiling at which k_N = λ p_N stays finite.
// Both caps lie some 300 orders of magnitude beyond any physical contact pressure.
constexpr double kExponentCap = 700.0;
constexpr double kPressureCeiling = 1.0e300;

}  // namespace

std::string ExponentialNormalLaw::validate() const {
  if (!(std::isfinite(reference_pressure) && reference_pressure > 0.0)) {
    return fmt::format("reference_pressure = {} is invalid: must be finite and > 0",
                       reference_pressure);
  }
  if (!(std::isfinite(decay) && decay > 0.0)) {
    return fmt::format("decay = {} is invalid: must be finite and > 0 (λ = 1/σ)", decay);
  }
  if (!std::isfinite(reference_gap)) {
    return fmt::format("reference_gap = {} is invalid: must be finite", reference_gap);
  }
  return {};
}

double ExponentialNormalLaw::pressure(double gap) const {
  // eq. (6), with the exponent -λ(g_N - g_N0) capped at kExponentCap.
  const double exponent = std::min(-decay * (gap - reference_gap), kExponentCap);
  const double p = reference_pressure * std::exp(exponent);
  if (p > kPressureCeiling / std::max(1.0, decay)) {
    return kPressureCeiling / std::max(1.0, decay);
  }
  return p;
}

double ExponentialNormalLaw::stiffness(double gap) const {
  // k_N = λ p_N (eq. 6: the paper's slope dp_N/dg_N = -λ p_N).
  return decay * pressure(gap);
}

double ExponentialNormalLaw::gap_at_pressure(double p) const {
  if (!(std::isfinite(p) && p > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "ExponentialNormalLaw::gap_at_pressure: pressure = {} must be finite and > 0", p));
  }
  // g_N = g_N0 + ln(p_N0/p)/λ; the ratio is formed first (exact near p_N0) unless it overflows.
  const double ratio = reference_pressure / p;
  const double log_ratio = (std::isfinite(ratio) && ratio > 0.0)
                               ? std::log(ratio)
                               : std::log(reference_pressure) - std::log(p);
  return reference_gap + log_ratio / decay;
}

}  // namespace jointhb::contact
