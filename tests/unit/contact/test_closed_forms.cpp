// Closed forms of the Gaul–Mayer law: eq. (11)/(12) as printed vs the general-n formula derived
// in docs/theory.md, and both vs an independent quadrature of the steady loop.
#include <gtest/gtest.h>

#include <cmath>

#include "jointhb/contact/closed_forms.hpp"

namespace cf = jointhb::contact::closed_form;

namespace {

// W_D of the symmetric loop by composite Simpson quadrature of ∮ F dg over the analytic branches:
// elastic unloading from F̂ to 0, then the virgin curve over the span ĝ (both half cycles).
double loop_quadrature(double span, const cf::MicroslipParameters& p, int m) {
  const double fhat = cf::virgin_force(span, p);
  double loading = 0.0;  // ∫_0^ĝ F_virgin(s) ds
  const double h = span / m;
  for (int i = 0; i <= m; ++i) {
    const double w = (i == 0 || i == m) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    loading += w * cf::virgin_force(i * h, p);
  }
  loading *= h / 3.0;
  return 2.0 * (loading - fhat * fhat / (2.0 * p.stiffness));
}

}  // namespace

TEST(ClosedForms, PaperEq11And12EqualTheGeneralFormulaForMindlinExponent) {
  const cf::MicroslipParameters p{1.0 / 3.0, 2.0, 5.0};
  const double gmax = cf::full_slip_span(p);
  EXPECT_DOUBLE_EQ(gmax, cf::full_slip_span_printed(p));
  for (double x : {0.05, 0.3, 0.7, 0.999, 1.0, 1.5, 10.0}) {
    const double general = cf::dissipation_general(x * gmax, p);
    EXPECT_NEAR(cf::dissipation_paper(x * gmax, p), general, 1e-12 * general) << "x=" << x;
  }
}

TEST(ClosedForms, GeneralFormulaMatchesQuadratureOfTheLoopForAnyExponent) {
  for (double n : {0.05, 0.2, 0.5, 0.9}) {
    const cf::MicroslipParameters p{n, 1.0, 1.0};
    for (double x : {0.2, 0.6, 0.9}) {
      const double span = x * cf::full_slip_span(p);
      const double general = cf::dissipation_general(span, p);
      EXPECT_NEAR(loop_quadrature(span, p, 20000), general, 1e-7 * general) << n << " " << x;
    }
  }
}

TEST(ClosedForms, PrintedFormulasFailAwayFromMindlinExponent) {
  for (double n : {0.05, 0.2, 0.5, 0.9}) {
    const cf::MicroslipParameters p{n, 1.0, 1.0};
    const double span = 0.5 * cf::full_slip_span(p);
    const double ratio = cf::dissipation_paper(span, p) / cf::dissipation_general(span, p);
    EXPECT_GT(std::abs(ratio - 1.0), 0.01) << "n=" << n;
  }
  // For n < 1/3 the printed eq. (11) turns negative at small spans (docs/theory.md §4.3): its O(x²)
  // term is (3/(4(1-n)) - 9/8) x², which vanishes only at n = 1/3.
  const cf::MicroslipParameters small{0.05, 1.0, 1.0};
  for (double x : {0.001, 0.1, 0.3}) {
    EXPECT_LT(cf::dissipation_paper(x * cf::full_slip_span_printed(small), small), 0.0) << x;
  }
}

TEST(ClosedForms, GrossSlipConstantIsTheLoadingIntegralToFullSlip) {
  for (double n : {0.05, 1.0 / 3.0, 0.9}) {
    EXPECT_NEAR(cf::loading_dissipation_integral(0.0, 1.0, n),
                n * (3 - n) / (2 * (2 - 3 * n + n * n)), 1e-13 / (1 - n));
  }
}

TEST(ClosedForms, SmallAmplitudeExpansionWithoutCancellation) {
  // I(y) = n y³/3 + n(n+1) y⁴/8 + O(y⁵): the stable evaluation keeps full relative accuracy.
  for (double n : {0.05, 1.0 / 3.0, 0.9}) {
    for (double y : {1e-8, 1e-5}) {
      const double series = n * y * y * y / 3 + n * (n + 1) * std::pow(y, 4) / 8 +
                            n * (n + 1) * (n + 2) / 6 * std::pow(y, 5) / 5;
      EXPECT_NEAR(cf::loading_dissipation_integral(0.0, y, n), series, 1e-14 * series);
    }
  }
}

TEST(ClosedForms, SymmetricLoopSolvesItsEquationAndMeetsJenkinsLimit) {
  const cf::MicroslipParameters p{0.4, 3.0, 100.0};
  for (double a : {1e-9, 1e-4, 0.03, 0.2}) {
    const auto loop = cf::symmetric_loop(a, p);
    EXPECT_NEAR(loop.loading_span, 2 * a - loop.force_amplitude / p.stiffness, 1e-15 * a);
    EXPECT_NEAR(loop.force_amplitude, cf::virgin_force(loop.loading_span, p),
                1e-14 * loop.force_amplitude + 1e-300);
  }
  EXPECT_EQ(cf::dissipation_jenkins(0.01, 1.0, 10.0), 0.0);
  EXPECT_DOUBLE_EQ(cf::dissipation_jenkins(0.3, 1.0, 10.0), 4.0 * (0.3 - 0.1));
}

TEST(ClosedForms, PrintedFormulaSeriesJoinsTheLiteralExpression) {
  // The series branch (x ≤ 1/4) and the literal expression agree where both are accurate, and at
  // n = 1/3 the printed formula equals the general one down to tiny spans.
  for (double n : {0.05, 1.0 / 3.0, 0.7}) {
    const cf::MicroslipParameters p{n, 1.0, 1.0};
    const double g = cf::full_slip_span_printed(p);
    const double x = 0.25, xl = 0.25 * (1 + 1e-12);
    const double literal =
        2.0 * (1.5 * xl + 1.5 * (1 - n) / (2 - n) * (std::pow(1 - xl, (2 - n) / (1 - n)) - 1) -
               0.5 * std::pow(1 - std::pow(1 - xl, 1.5), 2));
    EXPECT_NEAR(cf::dissipation_paper(x * g, p), literal, 1e-11 * std::abs(literal)) << n;
  }
  const cf::MicroslipParameters mindlin{1.0 / 3.0, 1.0, 1.0};
  for (double x : {1e-6, 1e-3, 0.2}) {
    const double span = x * cf::full_slip_span(mindlin);
    const double general = cf::dissipation_general(span, mindlin);
    EXPECT_NEAR(cf::dissipation_paper(span, mindlin), general, 1e-13 * general) << x;
  }
}

TEST(ClosedForms, PrintedFormulaStaysAccurateAsTheExponentApproachesOne) {
  // Issue 20, item 4: at n = 0.9999999 the series branch summed C(p, j) x^j with p = (2-n)/(1-n)
  // = 1e7, which overflowed to NaN. Reference: eq. (11) literally, in 60-digit arithmetic (mpmath),
  // F_s = k = 1, x = ĝ/g_T^max.
  struct Case {
    double n, x, wd;
  };
  const Case cases[] = {
      {0.05, 1e-9, -6.7105263048164827838e-19},  {0.05, 0.25, -0.024613990111562860354},
      {1.0 / 3.0, 1e-4, 7.5000000009313346209e-13}, {1.0 / 3.0, 0.2, 0.0060035882878007992761},
      {0.7, 0.01, 0.00027224953652998394468},    {0.7, 0.6, 0.56271520804673666774},
      {0.9, 1e-9, 1.2749999956125005009e-17},    {0.9, 0.01, 0.0012320129962119957673},
      {0.9, 0.2, 0.26978332721441092022},        {0.9999999, 1e-9, 1.495012251322162374e-11},
      {0.9999999, 1e-4, 0.00029967750115516260583}, {0.9999999, 0.01, 0.029775825471137668893},
      {0.9999999, 0.25, 0.62716280567668812805}, {0.9999999, 0.6, 1.2419641256269708159},
      {0.9999999999999999, 1e-9, 2.9999996646830928004e-9},
      {0.9999999999999999, 0.2, 0.51908350559986509747},
  };
  for (const Case& c : cases) {
    const cf::MicroslipParameters p{c.n, 1.0, 1.0};
    const double wd = cf::dissipation_paper(c.x * cf::full_slip_span_printed(p), p);
    EXPECT_NEAR(wd, c.wd, 1e-9 * std::abs(c.wd)) << "n=" << c.n << " x=" << c.x;
  }
  // Full slip (eq. 12) and the general formula stay finite as well.
  for (double n : {0.9999999, 0.9999999999999999}) {
    const cf::MicroslipParameters p{n, 1.0, 1.0};
    EXPECT_TRUE(std::isfinite(cf::dissipation_paper(2.0 * cf::full_slip_span_printed(p), p))) << n;
    for (double x : {1e-9, 0.3, 0.99, 2.0})
      EXPECT_TRUE(std::isfinite(cf::dissipation_general(x * cf::full_slip_span(p), p))) << n << " " << x;
  }
}

TEST(ClosedForms, EnergyScaleDoesNotOverflowBeforeTheResultDoes) {
  // 2F_s²/k with F_s = 1e160 and k = 1e20 is 2e300: F_s² alone (1e320) overflows, and ∞ times a
  // vanishing integral gave NaN (issue 20, item 4).
  const cf::MicroslipParameters big{1.0 / 3.0, 1e160, 1e20};
  const cf::MicroslipParameters unit{1.0 / 3.0, 1.0, 1.0};
  for (double x : {0.0, 1e-3, 0.5, 3.0}) {
    const double scaled = cf::dissipation_general(x * cf::full_slip_span(big), big);
    const double reference = cf::dissipation_general(x * cf::full_slip_span(unit), unit) * 1e300;
    EXPECT_NEAR(scaled, reference, 1e-12 * reference) << x;
    EXPECT_TRUE(std::isfinite(cf::dissipation_paper(x * cf::full_slip_span_printed(big), big))) << x;
  }
}
