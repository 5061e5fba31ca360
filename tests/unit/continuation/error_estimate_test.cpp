// Error estimates of discrete damping-curve and FRF points (continuation/error_estimate.hpp,
// docs/theory.md §13) against the TRUE errors: the same point solved at the same λ or Ω with
// H = 63, N_t = 2048 (error_reference.hpp). The bounds asserted are the brackets measured by
// validation/hb/error_estimate.cpp (README_error_estimate.md) with margin.
#include "jointhb/continuation/error_estimate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "error_reference.hpp"
#include "jointhb/continuation/backbone.hpp"
#include "jointhb/continuation/frf.hpp"

namespace jointhb::continuation {
namespace {

// Measured brackets of estimate/true (README_error_estimate.md) with margin.
constexpr double kJenkinsFactor = 5.0;
constexpr double kGaulMayerFactor = 5.0;
constexpr double kTwoDofFactor = 5.0;
constexpr double kFrfFactor = 5.0;

// The 1-DOF systems (error_reference.hpp): Jenkins slips at |x| = 3.33e-5.
hb::DiscreteSystem estimate_one_dof(const std::string& law) { return error_reference::one_dof_system(law); }

// The 2-DOF system of tests/unit/hb/test_nonlinear_mode.cpp.
hb::DiscreteSystem estimate_two_dof(const std::string& law) {
  hb::DiscreteSystem s;
  Eigen::MatrixXd k(2, 2);
  k << 2.0, -1.0, -1.0, 2.0;
  s.mass = Eigen::MatrixXd::Identity(2, 2).sparseView();
  s.stiffness = k.sparseView();
  s.damping = (0.01 * k).sparseView();
  hb::ContactElement c;
  c.law = law;
  c.exponent = 0.4;
  c.dof_a = 0;
  c.dof_b = 1;
  c.stiffness = 1.0;
  c.friction_coefficient = 1.0;
  c.normal_force = 0.01;
  s.contacts.push_back(c);
  c.dof_a = 1;
  c.dof_b = -1;
  c.stiffness = 0.5;
  s.contacts.push_back(c);
  return s;
}

// The damping-curve point at exactly q (Newton from the linear mode at fixed λ) with its estimate.
BackbonePoint estimate_mode_point(const hb::DiscreteSystem& system, double q, int h, int samples,
                                  bool estimate = true) {
  BackboneOptions o = error_reference::single_point_options(q, h, samples);
  o.error_estimate = estimate;
  const BackboneCurve c = trace_backbone(system, o);
  EXPECT_EQ(c.points.size(), 1u) << c.message;
  return c.points.empty() ? BackbonePoint{} : c.points[0];
}

// |estimate / truth| within [1/factor, factor] and the same sign.
void expect_estimate_within(double estimate, double truth, double factor,
                            const std::string& where) {
  EXPECT_GT(estimate / truth, 1.0 / factor)
      << where << ": estimate " << estimate << ", true " << truth;
  EXPECT_LT(estimate / truth, factor) << where << ": estimate " << estimate << ", true " << truth;
}

// Over the amplitudes and H = 1, 3, 5, 7 at N_t = 256: where the true error of Ω or ζ is above
// 1e-8 and truncation dominates it, the truncation estimate is within `factor` of it.
void check_mode_truncation(const hb::DiscreteSystem& system, const std::vector<double>& amplitudes,
                           double factor, const std::string& name) {
  int compared = 0;
  for (const double q : amplitudes) {
    for (const int h : {1, 3, 5, 7}) {
      const BackbonePoint p = estimate_mode_point(system, q, h, 256);
      ASSERT_TRUE(p.error.known) << name << " q = " << q << " H = " << h;
      hb::NonlinearModeOptions o;
      o.harmonics = h;
      o.time_samples = 256;
      const error_reference::ModeTruth t =
          error_reference::mode_truth(system, o, p.unknowns, std::log10(q));
      ASSERT_TRUE(t.ok) << name << " q = " << q << " H = " << h << ": reference not solved";
      const std::string where = name + " q = " + std::to_string(q) + " H = " + std::to_string(h);
      const auto check = [&](const ErrorPair& e, const error_reference::TrueError& truth,
                             const char* what) {
        if (std::abs(truth.total) > 1e-8 &&
            std::abs(truth.aliasing) < 0.1 * std::abs(truth.truncation)) {
          expect_estimate_within(e.truncation, truth.truncation, factor, where + " " + what);
          ++compared;
        } else if (std::abs(truth.total) < 1e-10) {
          // Where the true error is at round-off/tolerance level, so is the estimate.
          EXPECT_LT(std::abs(e.truncation), 1e-8) << where << " " << what;
        }
      };
      check(p.error.omega, t.omega, "omega");
      check(p.error.damping, t.damping, "damping");
    }
  }
  EXPECT_GE(compared, 4) << name << ": too few points above round-off to compare";
}

TEST(ErrorEstimate, TruncationTracksTrueErrorOneDofJenkins) {
  // stuck (exactly linear: no truncation error), onset of slip, damping peak, gross slip
  check_mode_truncation(estimate_one_dof("jenkins"), {1e-5, 4e-5, 1.2e-4, 1e-3}, kJenkinsFactor,
                        "jenkins");
}

TEST(ErrorEstimate, TruncationTracksTrueErrorOneDofGaulMayer) {
  check_mode_truncation(estimate_one_dof("gaul-mayer"), {5e-6, 1.2e-4, 1e-3}, kGaulMayerFactor,
                        "gaul-mayer");
}

TEST(ErrorEstimate, TruncationTracksTrueErrorTwoDof) {
  check_mode_truncation(estimate_two_dof("gaul-mayer"), {3e-3, 3e-2, 1e-1}, kTwoDofFactor, "2dof");
}

TEST(ErrorEstimate, AliasingFlagsTooFewSamples) {
  // A slipping Jenkins contact at the smallest N_t = 2H + 2: the stick/slip switches fall between
  // few samples, the estimate must say so; at N_t = 1024 the sampling error is small and so is the
  // estimate.
  const hb::DiscreteSystem s = estimate_one_dof("jenkins");
  for (const int h : {1, 3, 5}) {
    const BackbonePoint coarse = estimate_mode_point(s, 1.2e-4, h, 2 * h + 2);
    ASSERT_TRUE(coarse.error.known);
    EXPECT_GT(
        std::max(std::abs(coarse.error.omega.aliasing), std::abs(coarse.error.damping.aliasing)),
        1e-3)
        << "H = " << h;
    const BackbonePoint fine = estimate_mode_point(s, 1.2e-4, h, 1024);
    ASSERT_TRUE(fine.error.known);
    // measured at N_t = 1024: ≤ 2e-6 (Ω), ≤ 1.1e-5 (ζ), against 4e-3 … 6e-2 at 2H + 2
    const double coarse_worst =
        std::max(std::abs(coarse.error.omega.aliasing), std::abs(coarse.error.damping.aliasing));
    for (const double v : {fine.error.omega.aliasing, fine.error.damping.aliasing}) {
      EXPECT_LT(std::abs(v), 1e-4) << "H = " << h;
      EXPECT_LT(std::abs(v), 1e-2 * coarse_worst) << "H = " << h;
    }
  }
}

TEST(ErrorEstimate, FrfAmplitudeTracksTrueError) {
  const hb::DiscreteSystem s = estimate_one_dof("jenkins");
  hb::Excitation e;
  e.forces.push_back({0, 0.5, 1});
  int compared = 0;
  for (const double omega : {190.0, 230.0}) {
    for (const int h : {1, 3, 5}) {
      FrfOptions o;
      o.omega_start = omega;
      o.omega_end = omega + 1.0;
      o.harmonics = h;
      o.time_samples = 256;
      o.stability = Stability::never;
      o.refine_extrema = false;
      o.continuation.max_points = 1;
      o.continuation.residual_tolerance = 1e-13;
      const FrfCurve c = trace_frf(s, e, o);
      ASSERT_EQ(c.points.size(), 1u) << c.message;
      const FrfPoint& p = c.points[0];
      ASSERT_TRUE(p.error.known);
      hb::HarmonicBalanceOptions bo;
      bo.harmonics = h;
      bo.time_samples = 256;
      const error_reference::FrfTruth t =
          error_reference::frf_truth(s, e, bo, p.coefficients, omega, 0, 0.5);
      ASSERT_TRUE(t.ok);
      const std::string where = "Ω = " + std::to_string(omega) + " H = " + std::to_string(h);
      if (std::abs(t.amplitude_h1.total) > 1e-8 &&
          std::abs(t.amplitude_h1.aliasing) < 0.1 * std::abs(t.amplitude_h1.truncation)) {
        expect_estimate_within(p.error.amplitude_h1.truncation, t.amplitude_h1.truncation,
                               kFrfFactor, where);
        ++compared;
      }
    }
  }
  EXPECT_GE(compared, 2);
}

TEST(ErrorEstimate, OffLeavesPointsUnknown) {
  const BackbonePoint p = estimate_mode_point(estimate_one_dof("jenkins"), 1.2e-4, 3, 64, false);
  EXPECT_FALSE(p.error.known);
  EXPECT_EQ(p.error.omega.truncation, 0.0);
  EXPECT_EQ(p.error.damping.aliasing, 0.0);
}

}  // namespace
}  // namespace jointhb::continuation
