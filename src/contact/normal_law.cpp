// The exponential pressure-gap law of Gaul & Mayer, eq. (6):
//   p_N(g_N) = p_N0 exp(-λ (g_N - g_N0)),   k_N = -dp_N/dg_N = λ p_N,
// with its cutoff variant (N-1) and the linear penalty law (N-2) of normal_law.hpp.
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

std::string NormalLaw::validate() const {
  if (!std::isfinite(reference_gap)) {
    return fmt::format("reference_gap = {} is invalid: must be finite", reference_gap);
  }
  if (kind == NormalLawKind::linear) {
    if (!(std::isfinite(penalty_stiffness) && penalty_stiffness > 0.0))
      return fmt::format("penalty_stiffness = {} is invalid: must be finite and > 0 (linear law)", penalty_stiffness);
    return {};
  }
  if (!(std::isfinite(reference_pressure) && reference_pressure > 0.0)) {
    return fmt::format("reference_pressure = {} is invalid: must be finite and > 0",
                       reference_pressure);
  }
  if (!(std::isfinite(decay) && decay > 0.0)) {
    return fmt::format("decay = {} is invalid: must be finite and > 0 (λ = 1/σ)", decay);
  }
  if (!(cutoff_gap > reference_gap) || std::isnan(cutoff_gap)) {
    return fmt::format("cutoff_gap = {} is invalid: must be > reference_gap = {} (or +inf: no cutoff)",
                       cutoff_gap, reference_gap);
  }
  return {};
}

namespace {

// p_N0 e^{-λ(g - g_N0)} with the exponent capped at kExponentCap and the result at a ceiling at
// which λ times it stays finite.
double exponential(double reference_pressure, double decay, double reference_gap, double gap) {
  const double exponent = std::min(-decay * (gap - reference_gap), kExponentCap);
  const double p = reference_pressure * std::exp(exponent);
  return std::min(p, kPressureCeiling / std::max(1.0, decay));
}

}  // namespace

double NormalLaw::pressure(double gap) const {
  if (kind == NormalLawKind::linear) return gap <= reference_gap ? penalty_stiffness * (reference_gap - gap) : 0.0;
  if (gap >= cutoff_gap) return 0.0;
  const double p = exponential(reference_pressure, decay, reference_gap, gap);  // eq. (6)
  if (std::isinf(cutoff_gap)) return p;
  return std::max(p - exponential(reference_pressure, decay, reference_gap, cutoff_gap), 0.0);  // (N-1)
}

double NormalLaw::pressure_change(double gap, double delta) const {
  const double moved = gap + delta;
  const double direct = pressure(moved) - pressure(gap);
  if (kind == NormalLawKind::linear) {
    return gap <= reference_gap && moved <= reference_gap ? -penalty_stiffness * delta : direct;
  }
  // Both pressures on the uncapped exponential (and, with a cutoff, both above zero): the cutoff
  // offset cancels exactly, p(g + δ) − p(g) = p_exp(g) (e^{−λδ} − 1).
  const bool capped = -decay * (gap - reference_gap) >= kExponentCap ||
                      -decay * (moved - reference_gap) >= kExponentCap;
  const double at_gap = exponential(reference_pressure, decay, reference_gap, gap);
  if (capped || at_gap >= kPressureCeiling / std::max(1.0, decay) || moved >= cutoff_gap ||
      gap >= cutoff_gap || (std::isfinite(cutoff_gap) && (pressure(moved) == 0.0 || pressure(gap) == 0.0))) {
    return direct;
  }
  return at_gap * std::expm1(-decay * delta);
}

double NormalLaw::stiffness(double gap) const {
  if (kind == NormalLawKind::linear) return gap <= reference_gap ? penalty_stiffness : 0.0;  // closed at g_N0
  if (gap >= cutoff_gap) return 0.0;
  // k_N = λ p_N0 e^{-λ(g - g_N0)}: λ p_N for eq. (6) (the paper's slope dp_N/dg_N = -λ p_N).
  return decay * exponential(reference_pressure, decay, reference_gap, gap);
}

double NormalLaw::stiffness_slope(double gap) const {
  return kind == NormalLawKind::linear ? 0.0 : -decay * stiffness(gap);
}

double NormalLaw::stiffness_scale() const {
  return kind == NormalLawKind::linear ? penalty_stiffness : decay * reference_pressure;
}

double NormalLaw::open_reference() const {
  return kind == NormalLawKind::linear ? 0.0 : reference_pressure;
}

double NormalLaw::gap_at_pressure(double p) const {
  if (!(std::isfinite(p) && p > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "NormalLaw::gap_at_pressure: pressure = {} must be finite and > 0", p));
  }
  if (kind == NormalLawKind::linear) return reference_gap - p / penalty_stiffness;
  // g_N = g_N0 + ln(p_N0/(p + p_c))/λ (p_c = 0 without a cutoff); the ratio is formed first (exact
  // near p_N0) unless it overflows.
  const double shifted = std::isinf(cutoff_gap) ? p : p + exponential(reference_pressure, decay, reference_gap, cutoff_gap);
  const double ratio = reference_pressure / shifted;
  const double log_ratio = (std::isfinite(ratio) && ratio > 0.0)
                               ? std::log(ratio)
                               : std::log(reference_pressure) - std::log(shifted);
  return reference_gap + log_ratio / decay;
}

}  // namespace jointhb::contact
