#pragma once
// Closed forms of the Gaul–Mayer tangential law, in one place (docs/theory.md derives them).
//
// Notation: F_s = μ F_N (slip limit), k = k_T0, n the exponent of eq. (10), ĝ the slip span of the
// loading branch of a steady symmetric loop (from F_T = 0, reached by elastic unloading, to F̂_T).
// For a harmonic slip of amplitude a the span is ĝ = 2a - F̂/k (docs/theory.md §4.2).

namespace jointhb::contact::closed_form {

struct MicroslipParameters {
  double exponent = 1.0 / 3.0;  ///< n ∈ (0, 1)
  double slip_limit = 1.0;      ///< F_s = μ F_N > 0
  double stiffness = 1.0;       ///< k_T0 > 0
};

/// g_max = F_s/((1-n) k): slip of the virgin curve to full slip (general n).
double full_slip_span(const MicroslipParameters& p);
/// g_T^max = 3 F_s/(2 k) exactly as printed in eq. (8) (Mindlin, n = 1/3).
double full_slip_span_printed(const MicroslipParameters& p);

/// Virgin curve, eq. (8) generalised: |F| = F_s [1 - (1 - s/g_max)^(1/(1-n))] for 0 ≤ s ≤ g_max,
/// F_s beyond. Evaluated without cancellation for small s.
double virgin_force(double s, const MicroslipParameters& p);

/// J(y0, y1) = ∫_{y0}^{y1} v ((1-v)^{-n} - 1) dv, 0 ≤ y0 ≤ y1 ≤ 1: the dissipation of a loading
/// branch from |F| = y0 F_s to y1 F_s is (F_s²/k) J. Accurate to round-off relative to J(0, y1).
double loading_dissipation_integral(double y0, double y1, double n);

/// The same integral with each end point also given by its complement w = (1-y)^{1-n} (the variable
/// that falls linearly with the loading slip). For n near 1, y rounds to 1 long before the virgin
/// curve reaches full slip while w is still accurate; the integral is then taken from w.
double loading_dissipation_integral(double y0, double w0, double y1, double w1, double n);

/// W_D of eq. (11) (ĝ < g_T^max) or eq. (12) (ĝ ≥ g_T^max), literally as printed, with the printed
/// g_T^max = 3F_s/(2k) and the printed exponents. Exact for n = 1/3 only (docs/theory.md).
/// For x = ĝ/g_T^max ≤ 1/4 the same expression is summed as its Taylor series, so that the
/// printed formula is not blurred by the cancellation of its O(x) terms.
double dissipation_paper(double loading_span, const MicroslipParameters& p);

/// W_D derived from eq. (10) for any n ∈ (0,1), x = ĝ/g_max with g_max = F_s/((1-n)k):
///   x < 1: W_D = (2F_s²/k) { x/(1-n) + [(1-x)^{(2-n)/(1-n)} - 1]/(2-n) - ½[1-(1-x)^{1/(1-n)}]² }
///   x ≥ 1: W_D = (2F_s²/k) { n(3-n)/(2(2-3n+n²)) + (x-1)/(1-n) }
/// evaluated in a cancellation-free form (through loading_dissipation_integral).
double dissipation_general(double loading_span, const MicroslipParameters& p);

/// The steady symmetric loop under g_T = a cos ωt: F̂ solves F̂ = F_virgin(2a - F̂/k).
struct SymmetricLoop {
  double force_amplitude = 0.0;  ///< F̂
  double loading_span = 0.0;     ///< ĝ = 2a - F̂/k
  double dissipation = 0.0;      ///< W_D (general form)
  bool gross_slip = false;       ///< F̂ reached F_s
};
SymmetricLoop symmetric_loop(double amplitude, const MicroslipParameters& p);

/// Jenkins element under a = amplitude: W_D = 4 F_s (a - F_s/k) for a > F_s/k, else 0.
double dissipation_jenkins(double amplitude, double slip_limit, double stiffness);

}  // namespace jointhb::contact::closed_form
