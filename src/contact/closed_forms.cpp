// Closed forms of the Gaul–Mayer law (closed_forms.hpp, docs/theory.md §2).
#include "jointhb/contact/closed_forms.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jointhb::contact::closed_form {
namespace {

// I(y) = ∫_0^y v ((1-v)^{-n} - 1) dv, with w = (1-y)^{1-n}.
// For y ≤ 1/2 the binomial series (1-v)^{-n} = Σ_j (n)_j/j! v^j gives
//   I(y) = Σ_{j≥1} (n)_j/j! · y^{j+2}/(j+2),
// all terms positive, so I is accurate to round-off relative to itself (the closed form below
// cancels to O(y³) from O(1) terms). For y > 1/2 the closed form in u = 1 - y = w^{1/(1-n)}
//   I(y) = A(1) - A(w),  A(w) = w/(1-n) - u w/(2-n) - u + u²/2,
// loses at most a factor 1/I(1/2) ≈ 24/n in relative accuracy; it is taken from w, not y, because
// for n near 1 the singular tail ∫ (1-v)^{-n} dv ≈ w/(1-n) is still finite when y has rounded to 1.
double loading_integral(double y, double w, double n) {
  if (y <= 0.0) return 0.0;
  if (y <= 0.5) {
    double coefficient = n;  // (n)_j / j! for j = 1
    double power = y * y * y;
    double sum = 0.0;
    for (int j = 1; j < 400; ++j) {
      const double term = coefficient * power / (j + 2);
      sum += term;
      if (term <= sum * 1.0e-17) break;
      coefficient *= (n + j) / (j + 1.0);
      power *= y;
    }
    return sum;
  }
  const auto antiderivative = [n](double w_) {
    const double u = w_ > 0.0 ? std::pow(w_, 1.0 / (1.0 - n)) : 0.0;
    return w_ / (1.0 - n) - u * w_ / (2.0 - n) - u + 0.5 * u * u;
  };
  return antiderivative(1.0) - antiderivative(std::max(w, 0.0));
}

double complement(double y, double n) {  // w = (1-y)^{1-n}
  return y >= 1.0 ? 0.0 : std::exp((1.0 - n) * std::log1p(-y));
}

}  // namespace

double full_slip_span(const MicroslipParameters& p) {
  return p.slip_limit / ((1.0 - p.exponent) * p.stiffness);
}

double full_slip_span_printed(const MicroslipParameters& p) {
  return 1.5 * p.slip_limit / p.stiffness;  // eq. (8): g_T^max = 3 μF_N / (2 k_T0)
}

double virgin_force(double s, const MicroslipParameters& p) {
  const double x = std::max(s, 0.0) / full_slip_span(p);
  if (x >= 1.0) return p.slip_limit;
  // 1 - (1-x)^{1/(1-n)} without cancellation for small x
  return -p.slip_limit * std::expm1(std::log1p(-x) / (1.0 - p.exponent));
}

double loading_dissipation_integral(double y0, double y1, double n) {
  return loading_integral(y1, complement(y1, n), n) - loading_integral(y0, complement(y0, n), n);
}

double loading_dissipation_integral(double y0, double w0, double y1, double w1, double n) {
  return loading_integral(y1, w1, n) - loading_integral(y0, w0, n);
}

namespace {

// 2F_s²/k as 2F_s·(F_s/k): F_s² alone overflows for F_s above ~1e154 although the product with
// 1/k may not, and an overflowed scale times a vanishing integral would be ∞·0 = NaN.
double energy_scale(const MicroslipParameters& p) {
  return 2.0 * p.slip_limit * (p.slip_limit / p.stiffness);
}

// eq. (12)'s constant n(3-n)/(2(2-3n+n²)) with 2-3n+n² = (1-n)(2-n) factored: the expanded form
// cancels to relative error eps/(1-n) as n → 1.
double full_slip_constant(double n) { return n * (3.0 - n) / (2.0 * (1.0 - n) * (2.0 - n)); }

}  // namespace

double dissipation_paper(double loading_span, const MicroslipParameters& p) {
  const double n = p.exponent;
  const double scale = energy_scale(p);
  const double x = loading_span / full_slip_span_printed(p);
  const double pexp = (2.0 - n) / (1.0 - n);
  // The series' terms are C(p,j) x^j ~ (p x)^j / j!: with p = (2-n)/(1-n) → ∞ as n → 1 they
  // overflow long before they fall, so the series serves only while p x ≤ 1.
  if (x <= 0.25 && pexp * x <= 1.0) {
    // eq. (11) as printed, by its Taylor series in x: the literal expression cancels O(x) terms
    // down to an O(x²) (n ≠ 1/3) or O(x³) (n = 1/3) result. With p = (2-n)/(1-n), c = 3/(2p):
    //   f = 3x/2 + c[(1-x)^p - 1] - ½[1 - (1-x)^{3/2}]² = Σ_{j≥2} f_j x^j,
    //   f_1 = 3/2 - c p = 0,  f_2 = 3/(4(1-n)) - 9/8 (exactly, not by cancellation),
    //   f_j = c α_j - ½ Σ_{i=1}^{j-1} β_i β_{j-i},  α_j = C(p,j)(-1)^j,  β_j = -C(3/2,j)(-1)^j.
    const double c = 1.5 * (1.0 - n) / (2.0 - n);
    constexpr int kTerms = 60;  // the terms fall like 1/j! (p x ≤ 1) and 4^{-j} (x ≤ 1/4)
    // a_j = α_j x^j and b_j = β_j x^j by their recurrences: α_j alone reaches p^j/j!, which
    // overflows for p near 1e16 (n one rounding error below 1) although α_j x^j stays below 1.
    double a[kTerms + 1], b[kTerms + 1];
    a[1] = -pexp * x;
    b[1] = 1.5 * x;
    for (int j = 1; j < kTerms; ++j) {
      a[j + 1] = -a[j] * (pexp - j) / (j + 1) * x;
      b[j + 1] = -b[j] * (1.5 - j) / (j + 1) * x;
    }
    double sum = 1.125 * (n - 1.0 / 3.0) / (1.0 - n) * x * x;  // f_2 x² = (3/(4(1-n)) - 9/8) x²
    for (int j = 3; j <= kTerms; ++j) {
      double gamma = 0.0;
      for (int i = 1; i < j; ++i) gamma += b[i] * b[j - i];
      sum += c * a[j] - 0.5 * gamma;
    }
    return scale * sum;
  }
  if (x < 1.0) {
    // eq. (11), with 3x/2 = c p x folded into c[(1-x)^p - 1 + p x] (exact algebra): that bracket
    // is taken by expm1/log1p, so neither (1-x)^p nor the O(x) terms cancel (p x > 1 here or x > 1/4).
    const double c = 1.5 * (1.0 - n) / (2.0 - n);
    const double log_rest = std::log1p(-x);
    const double bracket = std::expm1(pexp * log_rest) + pexp * x;
    const double open = -std::expm1(1.5 * log_rest);  // 1 - (1-x)^{3/2}
    return scale * (c * bracket - 0.5 * open * open);
  }
  // eq. (12)
  return scale * (full_slip_constant(n) + 1.5 * (x - 1.0));
}

double dissipation_general(double loading_span, const MicroslipParameters& p) {
  const double n = p.exponent;
  const double scale = energy_scale(p);
  const double x = loading_span / full_slip_span(p);
  if (x < 1.0) {
    // W_D = (2F_s²/k) I(ŷ), ŷ = F̂/F_s on the virgin curve (docs/theory.md eq. T-11)
    return scale * loading_integral(virgin_force(loading_span, p) / p.slip_limit, 1.0 - x, n);
  }
  // I(1) = n(3-n)/(2(2-3n+n²)) (eq. 12's constant) plus Coulomb sliding 2F_s(ĝ - g_max)
  return scale * (full_slip_constant(n) + (x - 1.0) / (1.0 - n));
}

SymmetricLoop symmetric_loop(double amplitude, const MicroslipParameters& p) {
  SymmetricLoop loop;
  const double k = p.stiffness;
  const double fs = p.slip_limit;
  if (amplitude <= 0.0) return loop;
  // Gross slip when the loading span with F̂ = F_s reaches g_max.
  if (2.0 * amplitude - fs / k >= full_slip_span(p)) {
    loop.force_amplitude = fs;
    loop.gross_slip = true;
  } else {
    // h(F) = F - F_virgin(2a - F/k) is increasing, h(0) < 0 ≤ h(min(ka, F_s)).
    double lo = 0.0;
    double hi = std::min(k * amplitude, fs);
    double f = hi;
    for (int it = 0; it < 200; ++it) {
      const double span = 2.0 * amplitude - f / k;
      const double h = f - virgin_force(span, p);
      if (h > 0.0)
        hi = f;
      else
        lo = f;
      const double x = span / full_slip_span(p);
      const double slope = 1.0 + std::pow(std::max(1.0 - x, 0.0), p.exponent / (1.0 - p.exponent));
      double next = f - h / slope;  // Newton, safeguarded by the bracket
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (std::abs(next - f) <= 4.0 * std::numeric_limits<double>::epsilon() * f) {
        f = next;
        break;
      }
      f = next;
    }
    loop.force_amplitude = f;
  }
  loop.loading_span = 2.0 * amplitude - loop.force_amplitude / k;
  loop.dissipation = dissipation_general(loop.loading_span, p);
  return loop;
}

double dissipation_jenkins(double amplitude, double slip_limit, double stiffness) {
  const double sticking = slip_limit / stiffness;
  return amplitude > sticking ? 4.0 * slip_limit * (amplitude - sticking) : 0.0;
}

}  // namespace jointhb::contact::closed_form
