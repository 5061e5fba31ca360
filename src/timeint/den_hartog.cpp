// Den Hartog's non-stop steady state of the Coulomb oscillator (den_hartog.hpp).
//
// Derivation (docs/time-integration.md): in the half period σ = ωt - φ ∈ [0, π] the mass moves
// down (ẋ < 0), friction acts as +F_f, and with τ-derivatives (ω² d²/dσ² ≡ d²/dt²)
//   x/x_st = A cos(σ/β) + B sin(σ/β) + V cos(σ + φ) + r.
// Periodicity with two stops: x(0) = X0, x'(0) = 0, x(π) = -X0, x'(π) = 0. Writing
// c = cos(π/β), s = sin(π/β), ξ = X0/x_st, p = V cos φ, q = V sin φ:
//   x'(0) = 0   → B = β q,                       x(0) = ξ → A = ξ - p - r,
//   x'(π) = 0   → A s = β q (1 + c)   → q = A U,  U = s/(β(1 + c)) = tan(π/2β)/β,
//   x(π) = -ξ   → (ξ - p)(1 + c) + r(1 - c) + β q s = 0,
// and with (1 - c)/(1 + c) = β²U², s/(1 + c) = βU the last one reads (ξ - p)(1 + β²U²) = 0:
//   ξ = p = V cos φ,  q = V sin φ = -rU,  ξ² = V² - r²U²,  A = -r,  B = -βrU.
// Hence x/x_st = r(1 - cos(σ/β)) - βrU sin(σ/β) + ξ cos σ + rU sin σ (V cos(σ+φ) expanded).
#include "jointhb/timeint/den_hartog.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace jointhb::timeint {
namespace {

constexpr double kPi = std::numbers::pi;

// sin(z)/z without cancellation near 0.
double sinc(double z) {
  if (std::abs(z) < 1e-4) return 1.0 - z * z / 6.0;
  return std::sin(z) / z;
}

// ∫_0^π cos(μσ + ψ) dσ = π cos(μπ/2 + ψ) sinc(μπ/2): regular at μ = 0.
double cos_integral(double mu, double psi) {
  return kPi * std::cos(0.5 * mu * kPi + psi) * sinc(0.5 * mu * kPi);
}

// The half-period motion h(σ) = x/x_st and its σ-derivatives, σ ∈ [0, π].
struct HalfPeriod {
  double beta, r, u, xi;
  [[nodiscard]] double value(double s) const {
    return r * (1.0 - std::cos(s / beta)) - beta * r * u * std::sin(s / beta) + xi * std::cos(s) +
           r * u * std::sin(s);
  }
  [[nodiscard]] double slope(double s) const {
    return r / beta * std::sin(s / beta) - r * u * std::cos(s / beta) - xi * std::sin(s) +
           r * u * std::cos(s);
  }
  // The terms of h as amplitude · cos(νσ + ψ).
  [[nodiscard]] std::array<std::array<double, 3>, 5> terms() const {
    return {{{r, 0.0, 0.0},
             {-r, 1.0 / beta, 0.0},
             {-beta * r * u, 1.0 / beta, -0.5 * kPi},
             {xi, 1.0, 0.0},
             {r * u, 1.0, -0.5 * kPi}}};
  }
};

HalfPeriod half_period(const DenHartogResult& d) {
  return {d.frequency_ratio, d.friction_ratio, d.friction_function,
          d.static_deflection > 0.0 ? d.amplitude / d.static_deflection : 0.0};
}

// max over σ ∈ (0, π) of h'(σ)/sin σ: negative iff the velocity keeps its sign in the half
// period (the ends tend to h''(0) = r/β² - ξ < 0 and -h''(π) = -(r/β² + ξ) < 0). Dense sampling,
// then golden-section refinement around the largest sample.
double largest_scaled_slope(const HalfPeriod& h) {
  const auto g = [&](double s) { return h.slope(s) / std::sin(s); };
  constexpr int samples = 2048;
  double best = -std::numeric_limits<double>::infinity();
  int best_j = 1;
  for (int j = 1; j < samples; ++j) {
    const double v = g(kPi * j / samples);
    if (v > best) {
      best = v;
      best_j = j;
    }
  }
  double a = kPi * (best_j - 1) / samples + 1e-12, b = kPi * (best_j + 1) / samples - 1e-12;
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - ratio * (b - a), e = a + ratio * (b - a);
  double gc = g(c), ge = g(e);
  for (int it = 0; it < 60; ++it) {
    if (gc > ge) {
      b = e;
      e = c;
      ge = gc;
      c = b - ratio * (b - a);
      gc = g(c);
    } else {
      a = c;
      c = e;
      gc = ge;
      e = a + ratio * (b - a);
      ge = g(e);
    }
  }
  return std::max({best, gc, ge});
}

}  // namespace

DenHartogResult den_hartog(double mass, double stiffness, double friction_force,
                           double force_amplitude, double omega) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(mass) || !positive(stiffness) || !positive(force_amplitude) || !positive(omega) ||
      !std::isfinite(friction_force) || friction_force < 0.0) {
    throw std::invalid_argument(fmt::format(
        "den_hartog: mass, stiffness, force_amplitude, omega must be finite and > 0 and "
        "friction_force finite and >= 0, got {}, {}, {}, {}, {}",
        mass, stiffness, force_amplitude, omega, friction_force));
  }
  DenHartogResult d;
  d.natural_frequency = std::sqrt(stiffness / mass);
  d.omega = omega;
  const double beta = omega / d.natural_frequency;
  const double r = friction_force / force_amplitude;
  d.frequency_ratio = beta;
  d.static_deflection = force_amplitude / stiffness;
  d.friction_ratio = r;

  const double one_minus = (1.0 - beta) * (1.0 + beta);
  const double cos_pb = std::cos(kPi / beta);
  if (one_minus == 0.0 || (r > 0.0 && 1.0 + cos_pb == 0.0)) {
    d.regime = DenHartogRegime::singular_frequency;
    d.message = fmt::format("beta = {:.6g}: resonance of the friction-free or friction term", beta);
    return d;
  }
  const double v = 1.0 / one_minus;
  d.magnification = v;
  // U = tan(π/2β)/β, the form that stays accurate where 1 + cos(π/β) is small.
  const double u = r > 0.0 ? std::tan(0.5 * kPi / beta) / beta : 0.0;
  if (!std::isfinite(u)) {
    d.regime = DenHartogRegime::singular_frequency;
    d.message = fmt::format("beta = {:.6g}: 1 + cos(pi/beta) = 0", beta);
    return d;
  }
  d.friction_function = u;
  d.boundary_friction_ratio = std::abs(v) / std::sqrt(u * u + 1.0 / std::pow(beta, 4));
  const double discriminant = v * v - (r * u) * (r * u);
  if (!(discriminant > 0.0)) {
    d.regime = DenHartogRegime::no_real_amplitude;
    d.message =
        fmt::format("no non-stop motion: V^2 - (rU)^2 = {:.3g} <= 0 (beta = {:.6g}, r = {:.6g})",
                    discriminant, beta, r);
    return d;
  }
  const double xi = std::sqrt(discriminant);
  d.formula_amplitude = xi * d.static_deflection;
  if (!(xi > r / (beta * beta))) {
    d.regime = DenHartogRegime::sticks_at_stops;
    d.message = fmt::format(
        "the mass sticks at its stops: X0/x_st = {:.6g} <= r/beta^2 = {:.6g} (r above the boundary "
        "{:.6g})",
        xi, r / (beta * beta), d.boundary_friction_ratio);
    return d;
  }
  const HalfPeriod h{beta, r, u, xi};
  if (const double g = largest_scaled_slope(h); !(g < 0.0)) {
    d.regime = DenHartogRegime::extra_stops;
    d.message = fmt::format(
        "the velocity of the non-stop form changes sign inside a half period (max x'/sin = {:.3g})",
        g);
    return d;
  }
  d.regime = DenHartogRegime::non_stop;
  d.non_stop = true;
  d.amplitude = d.formula_amplitude;
  d.phase = std::atan2(-r * u / v, xi / v);  // cos φ = ξ/V, sin φ = -rU/V
  d.dissipation_per_cycle = 4.0 * friction_force * d.amplitude;
  const Eigen::VectorXd c = d.coefficients(1);
  d.first_harmonic_amplitude = std::hypot(c[1], c[2]);
  return d;
}

double DenHartogResult::displacement(double time) const {
  if (!non_stop) return 0.0;
  const double s = std::fmod(omega * time - phase, 2.0 * kPi);
  double sigma = s < 0.0 ? s + 2.0 * kPi : s;
  const HalfPeriod h = half_period(*this);
  if (sigma >= kPi) return -static_deflection * h.value(sigma - kPi);
  return static_deflection * h.value(sigma);
}

double DenHartogResult::velocity(double time) const {
  if (!non_stop) return 0.0;
  const double s = std::fmod(omega * time - phase, 2.0 * kPi);
  double sigma = s < 0.0 ? s + 2.0 * kPi : s;
  const HalfPeriod h = half_period(*this);
  if (sigma >= kPi) return -static_deflection * omega * h.slope(sigma - kPi);
  return static_deflection * omega * h.slope(sigma);
}

Eigen::VectorXd DenHartogResult::coefficients(int harmonics) const {
  if (harmonics < 1) {
    throw std::invalid_argument(
        fmt::format("den_hartog coefficients: harmonics must be >= 1, got {}", harmonics));
  }
  Eigen::VectorXd c = Eigen::VectorXd::Zero(2 * harmonics + 1);
  if (!non_stop) return c;
  // x(σ + π) = -x(σ): only odd k, a_k = (2/π) ∫_0^π h cos kσ dσ, b_k likewise with sin kσ, using
  //   ∫_0^π cos(νσ+ψ) cos kσ = ½[I(ν+k, ψ) + I(ν-k, ψ)],
  //   ∫_0^π cos(νσ+ψ) sin kσ = ½[I(ν+k, ψ-π/2) - I(ν-k, ψ-π/2)],   I(μ, ψ) = ∫_0^π cos(μσ+ψ).
  const HalfPeriod h = half_period(*this);
  for (int k = 1; k <= harmonics; k += 2) {
    double a = 0.0, b = 0.0;
    for (const auto& [amp, nu, psi] : h.terms()) {
      a += amp * 0.5 * (cos_integral(nu + k, psi) + cos_integral(nu - k, psi));
      b += amp * 0.5 *
           (cos_integral(nu + k, psi - 0.5 * kPi) - cos_integral(nu - k, psi - 0.5 * kPi));
    }
    a *= 2.0 / kPi * static_deflection;
    b *= 2.0 / kPi * static_deflection;
    // x(t) = x_st h(ωt - φ): rotate to the phase of the force.
    const double ck = std::cos(k * phase), sk = std::sin(k * phase);
    c[2 * k - 1] = a * ck - b * sk;
    c[2 * k] = a * sk + b * ck;
  }
  return c;
}

}  // namespace jointhb::timeint
