// Exact 1D increments of the Gaul–Mayer and Jenkins laws (eq. 10): against an independent RK4
// integration of the evolution equation, composition, symmetry, bounds, limits, derivatives.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "jointhb/contact/closed_forms.hpp"
#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/jenkins_law.hpp"

namespace jc = jointhb::contact;

namespace {

// RK4 on dF/dg = k (1 - |F|/F_s)^n (loading, F ≥ 0) with m equal steps: an independent reference.
double rk4_loading(double f0, double slip, double n, double fs, double k, int m) {
  const auto rate = [&](double f) { return k * std::pow(std::max(1.0 - f / fs, 0.0), n); };
  double f = f0;
  const double h = slip / m;
  for (int i = 0; i < m; ++i) {
    const double a = rate(f), b = rate(f + 0.5 * h * a), c = rate(f + 0.5 * h * b),
                 d = rate(f + h * c);
    f = std::min(f + h / 6.0 * (a + 2 * b + 2 * c + d), fs);
  }
  return f;
}

}  // namespace

TEST(GaulMayerLaw, LoadingIncrementMatchesRungeKuttaOfEq10) {
  for (double n : {0.1, 1.0 / 3.0, 0.7}) {
    jc::GaulMayerLaw law(n);
    const jc::TangentialLimits lim{2.0, 50.0};  // g_max = 2/((1-n) 50)
    for (double frac : {0.01, 0.2, 0.6}) {
      const double f0 = 0.3;
      const double slip = frac * lim.slip_limit / ((1 - n) * lim.stiffness);
      const double exact = law.scalar_step(f0, slip, lim).force;
      const double ref = rk4_loading(f0, slip, n, lim.slip_limit, lim.stiffness, 20000);
      EXPECT_NEAR(exact, ref, 1e-12 * lim.slip_limit) << "n=" << n << " frac=" << frac;
    }
  }
}

TEST(GaulMayerLaw, VirginCurveIsEq8ForMindlinExponent) {
  jc::GaulMayerLaw law(1.0 / 3.0);
  const jc::TangentialLimits lim{3.0, 7.0};
  const double gmax = 1.5 * lim.slip_limit / lim.stiffness;  // eq. (8)
  for (double g : {0.0, 0.1 * gmax, 0.5 * gmax, 0.99 * gmax, gmax, 2 * gmax}) {
    const double printed = lim.slip_limit * (1.0 - std::pow(std::max(1.0 - g / gmax, 0.0), 1.5));
    EXPECT_NEAR(law.scalar_step(0.0, g, lim).force, printed, 1e-14 * lim.slip_limit);
    EXPECT_NEAR(law.virgin_force(g, lim), printed, 1e-14 * lim.slip_limit);
  }
}

TEST(GaulMayerLaw, OneIncrementEqualsManySubsteps) {
  // Exactness: splitting an increment (also one that unloads through zero) changes nothing.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double n : {0.05, 1.0 / 3.0, 0.95}) {
    jc::GaulMayerLaw law(n);
    const jc::TangentialLimits lim{1.0, 10.0};
    for (int trial = 0; trial < 200; ++trial) {
      const double f0 = 0.999 * u(rng);
      const double slip = 0.4 * u(rng);
      const auto whole = law.scalar_step(f0, slip, lim);
      double f = f0, dissipation = 0.0;
      for (int i = 0; i < 64; ++i) {
        const auto s = law.scalar_step(f, slip / 64, lim);
        f = s.force;
        dissipation += s.dissipation;
      }
      EXPECT_NEAR(whole.force, f, 1e-13) << "f0=" << f0 << " slip=" << slip << " n=" << n;
      EXPECT_NEAR(whole.dissipation, dissipation, 1e-12 * (1.0 + dissipation));
    }
  }
}

TEST(GaulMayerLaw, OddSymmetryBoundsAndNonNegativeDissipation) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double n : {1e-6, 0.2, 0.5, 1.0 - 1e-6}) {
    jc::GaulMayerLaw law(n);
    const jc::TangentialLimits lim{0.7, 3.0};
    double f = 0.0;
    for (int i = 0; i < 5000; ++i) {
      const double slip = u(rng) * (i % 7 == 0 ? 2.0 : 0.05);
      const auto s = law.scalar_step(f, slip, lim);
      const auto mirrored = law.scalar_step(-f, -slip, lim);
      ASSERT_TRUE(std::isfinite(s.force) && std::isfinite(s.d_force) && std::isfinite(s.d_slip) &&
                  std::isfinite(s.d_limit) && std::isfinite(s.d_stiffness));
      EXPECT_EQ(s.force, -mirrored.force);
      EXPECT_LE(std::abs(s.force), lim.slip_limit);
      EXPECT_GE(s.dissipation, 0.0);
      EXPECT_GE(s.d_force, 0.0);
      EXPECT_LE(s.d_force, 1.0 + 1e-15);
      f = s.force;
    }
  }
}

TEST(GaulMayerLaw, ElasticUnloadingAndSlidingBranches) {
  jc::GaulMayerLaw law(0.4);
  const jc::TangentialLimits lim{1.0, 10.0};
  const auto unload = law.scalar_step(0.8, -0.05, lim);  // |F| decreases: k_T0 exactly
  EXPECT_DOUBLE_EQ(unload.force, 0.8 - 0.5);
  EXPECT_EQ(unload.dissipation, 0.0);
  EXPECT_EQ(unload.loading_slip, 0.0);
  const auto slide = law.scalar_step(1.0, 0.3, lim);  // on the limit: Coulomb sliding
  EXPECT_EQ(slide.force, 1.0);
  EXPECT_DOUBLE_EQ(slide.dissipation, 0.3);
  EXPECT_THROW(jc::GaulMayerLaw(0.0), std::invalid_argument);
  EXPECT_THROW(jc::GaulMayerLaw(1.0), std::invalid_argument);
  EXPECT_THROW(jc::GaulMayerLaw(std::nan("")), std::invalid_argument);
}

TEST(GaulMayerLaw, LimitsOfTheExponent) {
  const jc::TangentialLimits lim{1.0, 1.0};
  // n → 0: elastic until the limit, i.e. the Jenkins element.
  jc::GaulMayerLaw almost_jenkins(1e-9);
  jc::JenkinsLaw jenkins;
  for (double g : {0.3, 0.9, 1.5}) {
    EXPECT_NEAR(almost_jenkins.scalar_step(0.0, g, lim).force,
                jenkins.scalar_step(0.0, g, lim).force, 1e-8);
  }
  // n → 1: the virgin curve tends to F_s (1 - exp(-k g / F_s)).
  jc::GaulMayerLaw almost_linear(1.0 - 1e-9);
  for (double g : {0.1, 1.0, 5.0}) {
    EXPECT_NEAR(almost_linear.scalar_step(0.0, g, lim).force, 1.0 - std::exp(-g), 1e-7);
  }
}

TEST(GaulMayerLaw, VanishingLimitAndExtremeIncrementsStayFinite) {
  jc::GaulMayerLaw law(1.0 / 3.0);
  for (double fs : {0.0, 1e-300, 1e-200, 1e-20}) {
    const jc::TangentialLimits lim{fs, 1e9};
    for (double slip : {1e-300, 1e-12, 1.0, 1e30}) {
      const auto s = law.scalar_step(0.5 * fs, slip, lim);
      EXPECT_TRUE(std::isfinite(s.force) && std::isfinite(s.d_slip) && std::isfinite(s.d_limit) &&
                  std::isfinite(s.dissipation));
      EXPECT_LE(std::abs(s.force), fs);
    }
  }
}

namespace {

struct Partials {
  double f0, slip, limit, stiffness;
};

Partials central_differences(const jc::TangentialLaw& law, double f0, double slip,
                             jc::TangentialLimits lim) {
  const auto f = [&](double a, double b, double c, double d) {
    return law.scalar_step(a, b, {c, d}).force;
  };
  const double h = 1e-6;
  const double L = lim.slip_limit, k = lim.stiffness;
  const double hf = h * L, hs = h * L / k, hl = h * L, hk = h * k;
  return {(f(f0 + hf, slip, L, k) - f(f0 - hf, slip, L, k)) / (2 * hf),
          (f(f0, slip + hs, L, k) - f(f0, slip - hs, L, k)) / (2 * hs),
          (f(f0, slip, L + hl, k) - f(f0, slip, L - hl, k)) / (2 * hl),
          (f(f0, slip, L, k + hk) - f(f0, slip, L, k - hk)) / (2 * hk)};
}

}  // namespace

TEST(GaulMayerLaw, AnalyticDerivativesMatchFiniteDifferences) {
  jc::GaulMayerLaw law(0.3);
  const jc::TangentialLimits lim{2.0, 40.0};
  struct Case {
    double f0, slip;
    const char* what;
  };
  const Case cases[] = {{0.5, 0.01, "loading"},
                        {0.5, -0.005, "unloading"},
                        {1.2, -0.06, "unload through zero"},
                        {-1.9, 0.09, "through zero, far"},
                        {0.0, 0.02, "virgin"},
                        {1.99, 0.001, "near the limit"}};
  for (const auto& c : cases) {
    const auto s = law.scalar_step(c.f0, c.slip, lim);
    const auto fd = central_differences(law, c.f0, c.slip, lim);
    EXPECT_NEAR(s.d_force, fd.f0, 1e-6 * (1 + std::abs(fd.f0))) << c.what;
    EXPECT_NEAR(s.d_slip, fd.slip, 1e-6 * (1 + std::abs(fd.slip))) << c.what;
    EXPECT_NEAR(s.d_limit, fd.limit, 1e-6 * (1 + std::abs(fd.limit))) << c.what;
    EXPECT_NEAR(s.d_stiffness, fd.stiffness, 1e-6 * (1 + std::abs(fd.stiffness))) << c.what;
  }
}

TEST(JenkinsLaw, ElasticPerfectlyPlasticAndDerivatives) {
  jc::JenkinsLaw law;
  const jc::TangentialLimits lim{1.0, 10.0};
  EXPECT_DOUBLE_EQ(law.scalar_step(0.2, 0.05, lim).force, 0.7);
  const auto slide = law.scalar_step(0.2, 0.2, lim);
  EXPECT_EQ(slide.force, 1.0);
  EXPECT_NEAR(slide.dissipation, 1.0 * (2.2 - 1.0) / 10.0, 1e-15);
  for (const auto& c : {std::pair{0.2, 0.05}, std::pair{0.2, 0.2}, std::pair{-0.5, -0.1}}) {
    const auto s = law.scalar_step(c.first, c.second, lim);
    const auto fd = central_differences(law, c.first, c.second, lim);
    EXPECT_NEAR(s.d_force, fd.f0, 1e-7);
    EXPECT_NEAR(s.d_slip, fd.slip, 1e-6);
    EXPECT_NEAR(s.d_limit, fd.limit, 1e-7);
    EXPECT_NEAR(s.d_stiffness, fd.stiffness, 1e-7);
  }
}

TEST(GaulMayerLaw, SkippingTheDissipationChangesNothingElse) {
  // Newton sweeps call the law without the energy; forces and derivatives must be identical.
  jc::GaulMayerLaw law(0.3);
  const jc::TangentialLimits lim{2.0, 40.0};
  for (const auto& [f0, slip] :
       {std::pair{0.5, 0.01}, std::pair{1.2, -0.06}, std::pair{1.99, 0.2}}) {
    const auto with = law.scalar_step(f0, slip, lim);
    const auto without = law.scalar_step(f0, slip, lim, false);
    EXPECT_EQ(with.force, without.force);
    EXPECT_EQ(with.d_force, without.d_force);
    EXPECT_EQ(with.d_slip, without.d_slip);
    EXPECT_EQ(with.d_limit, without.d_limit);
    EXPECT_EQ(with.d_stiffness, without.d_stiffness);
    EXPECT_GT(with.dissipation, without.dissipation);
  }
}
