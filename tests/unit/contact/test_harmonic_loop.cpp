// The loop driver (harmonic_loop.hpp): W_D of the steady loop against the closed forms, the
// loading-span reading of eq. (11), Jenkins, and extreme amplitudes.
#include <gtest/gtest.h>

#include <cmath>

#include "jointhb/contact/closed_forms.hpp"
#include "jointhb/contact/harmonic_loop.hpp"

namespace jc = jointhb::contact;

TEST(HarmonicLoop, DissipationMatchesGeneralFormulaToRoundOff) {
  for (double n : {0.05, 0.2, 1.0 / 3.0, 0.5, 0.9}) {
    for (double ratio : {1e-3, 0.1, 0.5, 0.9, 2.0, 10.0}) {
      jc::LoopOptions o;
      o.exponent = n;
      o.amplitude = ratio * o.friction_coefficient * o.normal_force / ((1 - n) * o.stiffness);
      const auto r = jc::run_loop(o);
      ASSERT_EQ(r.state.termination, jointhb::Termination::converged);
      EXPECT_NEAR(r.dissipation_general, r.dissipation, 1e-12 * r.dissipation)
          << "n=" << n << " a/gmax=" << ratio;
    }
  }
}

TEST(HarmonicLoop, LoadingSpanNotAmplitudeIsTheRightReadingOfEq11) {
  // At small amplitude the span 2a - F̂/k tends to a, so the readings differ only as slip grows;
  // at a = 2 g_max (gross slip) they are far apart.
  jc::LoopOptions o;  // n = 1/3
  o.amplitude = 2.0 * o.friction_coefficient * o.normal_force * 1.5 / o.stiffness;
  const auto r = jc::run_loop(o);
  EXPECT_NEAR(r.loading_span, 2 * o.amplitude - r.force_amplitude / o.stiffness, 1e-15);
  EXPECT_NEAR(r.dissipation_paper, r.dissipation, 1e-12 * r.dissipation);
  EXPECT_GT(std::abs(r.dissipation_paper_amplitude_reading / r.dissipation - 1.0), 0.3);
}

TEST(HarmonicLoop, JenkinsMatchesItsClosedForm) {
  jc::LoopOptions o;
  o.law = "jenkins";
  for (double a : {1e-5, 3e-5, 1e-4, 1e-3}) {  // F_s/k = 3e-5
    o.amplitude = a;
    const auto r = jc::run_loop(o);
    const double scale = 4.0 * o.friction_coefficient * o.normal_force * a;  // W_D of full sliding
    EXPECT_NEAR(r.dissipation, r.dissipation_jenkins, 1e-12 * scale) << a;
  }
}

TEST(HarmonicLoop, ExtremeAmplitudesNormalMotionAndHarmonicsStayFinite) {
  for (bool normal_motion : {false, true}) {
    for (double a : {0.0, 1e-30, 1e-15, 1.0, 1e6}) {
      jc::LoopOptions o;
      o.amplitude = a;
      o.harmonics = {{3, 0.3 * a, 0.2}};
      if (normal_motion) {
        o.normal_amplitude = 2e-6;
        o.normal_decay = 1e6;
        o.stiffness_follows_normal = true;
      }
      const auto r = jc::run_loop(o);
      EXPECT_TRUE(std::isfinite(r.dissipation) && std::isfinite(r.force_amplitude)) << a;
      EXPECT_GE(r.dissipation, 0.0);
      for (std::size_t i = 0; i < r.force.size(); ++i) {
        EXPECT_LE(std::abs(r.force[i]), o.friction_coefficient * r.normal_force[i] * (1 + 1e-15));
      }
      // With a stiffness modulated in phase with a vanishing slip (a = 1e-30), ∮ k dg ≠ 0 pumps
      // the mean force towards the limit over ~1e26 periods: that steady state is out of Newton's
      // reach (1 - M ≈ 1e-26) and is reported as not converged, with a message, never as NaN.
      if (normal_motion && a == 1e-30) {
        if (r.state.termination != jointhb::Termination::converged) {
          EXPECT_NE(r.state.message.find("not converged"), std::string::npos);
        }
      } else {
        EXPECT_EQ(r.state.termination, jointhb::Termination::converged) << a << " " << normal_motion;
      }
    }
  }
}

TEST(HarmonicLoop, InvalidOptionsAreRejected) {
  jc::LoopOptions o;
  o.exponent = 1.5;
  EXPECT_THROW(jc::run_loop(o), std::invalid_argument);
  o = {};
  o.friction_coefficient = 0.0;
  EXPECT_THROW(jc::run_loop(o), std::invalid_argument);
  o = {};
  o.amplitude = std::nan("");
  EXPECT_THROW(jc::run_loop(o), std::invalid_argument);
  o = {};
  o.law = "coulomb";
  EXPECT_THROW(jc::run_loop(o), std::invalid_argument);
}

// The slip over the stick range, r = a k_T0/(μ F_N), is accepted in [1e-100, 1e100] (its cube,
// in W_D, stays a double); at the edges W_D still equals the closed form, beyond them the loop is
// refused naming the amplitude instead of answered with W_D = 0 (issue 20, item 3: before the
// check a = 1e160 m gave W_D 0 and "microslip").
TEST(HarmonicLoop, SlipRangeEdgesAreRightAndBeyondThemRefused) {
  const auto at_ratio = [](double ratio, double normal_force) {
    jc::LoopOptions o;
    o.normal_force = normal_force;
    o.amplitude = ratio * o.friction_coefficient * o.normal_force / o.stiffness;
    return o;
  };
  for (const auto& [ratio, force] : {std::pair{3e-99, 1e95}, std::pair{3e99, 100.0}}) {
    const auto r = jc::run_loop(at_ratio(ratio, force));
    ASSERT_EQ(r.state.termination, jointhb::Termination::converged) << ratio;
    ASSERT_GT(r.dissipation, 0.0) << ratio;
    EXPECT_NEAR(r.dissipation_general, r.dissipation, 1e-9 * r.dissipation) << ratio;
  }
  for (double ratio : {1e-101, 1e101}) {
    try {
      (void)jc::run_loop(at_ratio(ratio, 100.0));
      ADD_FAILURE() << "ratio " << ratio << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind("amplitude: ", 0), 0u) << e.what();
    }
  }
}
