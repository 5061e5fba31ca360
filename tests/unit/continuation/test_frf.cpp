// Nonlinear FRF tracing (continuation/frf.hpp): the linear limit against the receptance, a
// friction oscillator's curve against its own harmonic-balance residual and physical bounds.
#include "jointhb/continuation/frf.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>

namespace jointhb::continuation {
namespace {

hb::DiscreteSystem oscillator(double kt0, double mu_fn, double zeta) {
  hb::DiscreteSystem s;
  s.mass = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  s.stiffness = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  s.damping = Eigen::MatrixXd::Constant(1, 1, 2.0 * zeta * std::sqrt(1.0 + kt0)).sparseView();
  if (kt0 > 0.0) {
    hb::ContactElement c;
    c.law = "jenkins";
    c.stiffness = kt0;
    c.friction_coefficient = 1.0;
    c.normal_force = mu_fn;
    s.contacts.push_back(c);
  }
  return s;
}

hb::Excitation force(double amplitude) {
  hb::Excitation e;
  e.forces.push_back({0, amplitude, 1});
  return e;
}

double receptance(double k, double c, double omega, double f) {
  return f / std::abs(std::complex<double>(k - omega * omega, omega * c));
}

TEST(FrfContinuation, LinearOscillatorFollowsTheReceptance) {
  const hb::DiscreteSystem s = oscillator(0.0, 0.0, 0.02);
  FrfOptions o;
  o.omega_start = 0.5;
  o.omega_end = 2.0;
  o.harmonics = 3;
  o.time_samples = 16;
  const FrfCurve curve = trace_frf(s, force(0.1), o);
  ASSERT_TRUE(curve.completed()) << curve.message;
  EXPECT_EQ(curve.points.back().omega, 2.0);
  EXPECT_GT(curve.points.size(), 10u);
  for (const auto& p : curve.points) {
    const double ref = receptance(1.0, 0.04, p.omega, 0.1);
    EXPECT_NEAR(p.amplitude_h1, ref, 1e-9 * ref) << p.omega;
    EXPECT_NEAR(p.amplitude_max, ref, 1e-9 * ref) << p.omega;
  }
}

TEST(FrfContinuation, StuckJenkinsIsTheStuckLinearSystem) {
  const hb::DiscreteSystem s = oscillator(3.0, 10.0, 0.02);  // μF_N far above the response
  FrfOptions o;
  o.omega_start = 1.0;
  o.omega_end = 3.0;
  o.harmonics = 5;
  o.time_samples = 32;
  const FrfCurve curve = trace_frf(s, force(0.01), o);
  ASSERT_TRUE(curve.completed()) << curve.message;
  for (const auto& p : curve.points) {
    const double ref = receptance(4.0, 2.0 * 0.02 * 2.0, p.omega, 0.01);
    EXPECT_NEAR(p.amplitude_h1, ref, 1e-9 * ref);
    EXPECT_EQ(p.dissipation, 0.0);
  }
}

TEST(FrfContinuation, SlippingJenkinsPointsSolveHarmonicBalanceAndPeakBetweenTheLimits) {
  const hb::DiscreteSystem s = oscillator(3.0, 0.05, 0.01);
  FrfOptions o;
  o.omega_start = 0.6;
  o.omega_end = 2.6;
  o.harmonics = 7;
  o.time_samples = 64;
  int seen = 0;
  const FrfCurve curve = trace_frf(s, force(0.1), o, [&](const FrfPoint&) {
    ++seen;
    return true;
  });
  ASSERT_TRUE(curve.completed()) << curve.message;
  EXPECT_EQ(seen, static_cast<int>(curve.points.size()));
  hb::HarmonicBalanceOptions ho;
  ho.harmonics = 7;
  ho.time_samples = 64;
  const hb::HarmonicBalance balance(s, force(0.1), ho);
  const FrfPoint* peak = &curve.points.front();
  hb::HarmonicBalanceEvaluation ev;
  for (const auto& p : curve.points) {
    balance.evaluate(p.coefficients, p.omega, false, ev);
    EXPECT_LT(ev.residual.lpNorm<Eigen::Infinity>(), 1e-8 * 0.1);
    if (p.amplitude_h1 > peak->amplitude_h1) peak = &p;
  }
  // The resonance lies between the free (√1) and the stuck (√4) natural frequencies, and the
  // contact slips there.
  EXPECT_GT(peak->omega, 1.0);
  EXPECT_LT(peak->omega, 2.0);
  EXPECT_GT(peak->dissipation, 0.0);
  EXPECT_GT(curve.newton_iterations, 0);
  EXPECT_GE(curve.timings.total, curve.timings.aft);
}

TEST(FrfContinuation, JacobianCheckAlongAGaulMayerCurve) {
  hb::DiscreteSystem s = oscillator(3.0, 0.05, 0.01);
  s.contacts[0].law = "gaul-mayer";
  s.contacts[0].exponent = 0.4;
  FrfOptions o;
  o.omega_start = 1.0;
  o.omega_end = 2.2;
  o.harmonics = 3;
  o.time_samples = 32;
  o.check_jacobian = true;
  const FrfCurve curve = trace_frf(s, force(0.05), o);
  ASSERT_TRUE(curve.completed()) << curve.message;
  EXPECT_GT(curve.jacobian_check_error, 0.0);  // it ran
  EXPECT_LT(curve.jacobian_check_error, 1e-6) << "at omega " << curve.jacobian_check_omega;
}

TEST(FrfContinuation, StopByCallbackKeepsThePoints) {
  FrfOptions o;
  o.harmonics = 3;
  o.time_samples = 16;
  int n = 0;
  const FrfCurve curve = trace_frf(oscillator(3.0, 0.05, 0.01), force(0.1), o,
                                   [&](const FrfPoint&) { return ++n < 4; });
  EXPECT_EQ(curve.reason, StopReason::stopped_by_user);
  EXPECT_EQ(curve.points.size(), 4u);
}

TEST(FrfContinuation, RejectsInvalidOptions) {
  FrfOptions o;
  o.omega_start = -1.0;
  EXPECT_NE(o.validate(1).find("omega_start"), std::string::npos);
  o.omega_start = 1.0;
  o.omega_end = 1.0;
  EXPECT_NE(o.validate(1).find("omega_end"), std::string::npos);
  o.omega_end = 2.0;
  o.output_dof = 1;
  EXPECT_NE(o.validate(1).find("output_dof"), std::string::npos);
  o.output_dof = 0;
  o.time_samples = 8;
  EXPECT_NE(o.validate(1).find("time_samples"), std::string::npos);
  EXPECT_THROW(trace_frf(oscillator(1.0, 1.0, 0.01), force(1.0), o), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::continuation
