// Nonlinear FRF tracing (continuation/frf.hpp): the linear limit against the receptance, a
// friction oscillator's curve against its own harmonic-balance residual and physical bounds.
#include "jointhb/continuation/frf.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <algorithm>
#include <complex>
#include <limits>
#include <string>
#include <numbers>
#include <utility>
#include <vector>

#include "../hb/corpus_chain.hpp"
#include "jenkins_oscillator.hpp"

namespace jointhb::continuation {
namespace {

// The 1-DOF Jenkins oscillator (jenkins_oscillator.hpp) with ζ the damping ratio of the stuck system.
hb::DiscreteSystem oscillator(double kt0, double mu_fn, double zeta) {
  return test::jenkins_oscillator(kt0, mu_fn, 2.0 * zeta * std::sqrt(1.0 + kt0));
}

hb::Excitation force(double amplitude) { return test::force_at_dof0(amplitude); }

// The light-damping corpus's FRF (validation/hb/light_damping.cpp): Ω ∈ [0.5, 1.5 ω_stuck], H = 7,
// N_t = 256; the reach of the curve and its peak only (no multipliers or error estimates).
FrfOptions light_damping_options(double kt0) {
  FrfOptions o;
  o.omega_start = 0.5;
  o.omega_end = 1.5 * std::sqrt(1.0 + kt0);
  o.harmonics = 7;
  o.time_samples = 256;
  o.stability = Stability::never;
  o.error_estimate = false;
  return o;
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

// Issue 23's lightly damped oscillator (m = k = 1, k_T0 = 10, μF_N = 0.1, c = 0.004 or 0): below
// the stuck resonance √11 the stuck response reaches the slip amplitude X_s = μF_N/k_T0 = 0.01, and
// beyond it only slip bounds the response (the curves used to stop there, at 3.24 and 3.16 rad/s).
// Energy bound (closed form): per period the force puts in π F X₁ ≤ 4 F X (X₁ ≤ 4X/π for a
// signal of peak X), a Jenkins element dissipates 4 μF_N (X − X_s) on a path with one maximum and
// one minimum, so X ≤ X_s / (1 − F/μF_N); the curve must reach X_s and stay below that.
TEST(FrfContinuation, LightlyDampedStuckResonanceIsCrossedAtTheSlipLimit) {
  for (const double zeta : {0.002 / std::sqrt(11.0), 0.0}) {
    for (const double f : {0.005, 0.01}) {
      FrfOptions o;
      o.omega_start = 0.5;
      o.omega_end = 4.5;
      o.harmonics = 7;
      o.time_samples = 256;
      // The reach and the bounds of the curve only: no multipliers or error estimates at its
      // points (their own tests are in frf_stability_test.cpp and error_estimate_test.cpp).
      o.stability = Stability::never;
      o.error_estimate = false;
      const FrfCurve curve = trace_frf(oscillator(10.0, 0.1, zeta), force(f), o);
      ASSERT_TRUE(curve.completed()) << "zeta " << zeta << " F " << f << ": " << curve.message;
      double peak = 0.0;
      for (const auto& p : curve.points) peak = std::max(peak, p.amplitude_max);
      EXPECT_GT(peak, 0.01 * (1.0 - 1e-9)) << zeta << " " << f;
      EXPECT_LT(peak, 0.01 / (1.0 - f / 0.1)) << zeta << " " << f;
      EXPECT_NEAR(curve.points.back().omega, 4.5, 1e-12);
    }
  }
}

// Undamped, forced far below the friction limit (F = 1e-3 μF_N, k_T0/k = 1 and 100): the stuck
// response climbs to the slip amplitude X_s = μF_N/k_T0 just below ω_stuck, where the branch turns
// by ~90° — the amplitude is held at X_s by slip while the phase turns by π over a band of Ω
// from √(k_s − F/X_s) to √(k_s + F/X_s) — and comes down the far stuck leg. Every arclength
// hyperplane normal to the rising leg cuts that cap far from its predictor or not at all: the
// curves stopped at min_step ("the
// corrector moved … more than 10 times the step", light-damping known stops). The step along the
// tangent beyond the corner crosses it (docs/continuation.md, "Crossing a corner").
// Bounds (closed form, as above): X_s ≤ peak ≤ X_s / (1 − F/μF_N); at Ω_end the response is the
// stuck linear one, F / (Ω² − k − k_T0).
TEST(FrfContinuation, UndampedStuckResonanceCornerIsCrossed) {
  const double f = 1e-3;
  for (const double kt0 : {1.0, 100.0}) {
    const FrfCurve curve = trace_frf(oscillator(kt0, 1.0, 0.0), force(f), light_damping_options(kt0));
    ASSERT_TRUE(curve.completed()) << "k_T0 " << kt0 << ": " << curve.message;
    double peak = 0.0;
    for (const auto& p : curve.points) peak = std::max(peak, p.amplitude_max);
    const double x_s = 1.0 / kt0;
    EXPECT_GT(peak, x_s * (1.0 - 1e-9)) << kt0;
    EXPECT_LT(peak, x_s / (1.0 - f)) << kt0;
    const FrfPoint& end = curve.points.back();
    EXPECT_NEAR(end.amplitude_h1, f / (end.omega * end.omega - 1.0 - kt0),
                1e-9 * f / (end.omega * end.omega - 1.0 - kt0))
        << kt0;
  }
}

// The undamped Jenkins oscillators at F = 10⁻⁶ μF_N of the light-damping corpus (four known stops
// until stop 52): the stuck leg meets X_s = μF_N/k_T0 within 10⁻⁷ of ω_stuck and the branch turns
// onto the friction cap, where the phase turns by π at nearly fixed Ω. The curve now crosses it
// (docs/continuation.md, "Crossing a resonance at fixed phase": a rescaled arclength for k_T0/k =
// 10⁻² and 1, the crossing at fixed phase for 10² and 10⁶) and reaches Ω_end. Off the cap every
// point is the stuck linear response F/|k + k_T0 − Ω²| (phase 0 below, π above); the peak is X_s
// up to the cap's excess, which the N_t = 256 balance resolves to ~10⁻⁴ X_s (its slip lasts less
// than a sample: a staircase of solutions), and the far leg is reached within 0.8 X_s of it. Where
// the cap is crossed at fixed phase (10², 10⁶) its top follows T-46 (docs/theory.md §8).
TEST(FrfContinuation, UndampedJenkinsCapIsCrossedAtFixedPhase) {
  const double f = 1e-6;
  for (const double kt0 : {1e-2, 1.0, 1e2, 1e6}) {
    const FrfCurve curve = trace_frf(oscillator(kt0, 1.0, 0.0), force(f), light_damping_options(kt0));
    ASSERT_TRUE(curve.completed()) << "k_T0 " << kt0 << ": " << curve.message;
    const double x_s = 1.0 / kt0, k_s = 1.0 + kt0;
    double peak = 0.0, far_leg = 0.0;
    for (const auto& p : curve.points) {
      peak = std::max(peak, p.amplitude_h1);
      if (p.amplitude_h1 >= x_s * (1.0 - 1e-9)) continue;  // on the cap
      const double ref = f / std::abs(k_s - p.omega * p.omega);
      EXPECT_NEAR(p.amplitude_h1, ref, 1e-6 * ref) << kt0 << " at " << p.omega;
      if (p.omega > std::sqrt(k_s)) far_leg = std::max(far_leg, p.amplitude_h1);
    }
    EXPECT_GT(peak, x_s * (1.0 - 1e-9)) << kt0;
    EXPECT_LT(peak, x_s * (1.0 + 1e-3)) << kt0;
    EXPECT_GT(far_leg, 0.2 * x_s) << kt0;
    if (kt0 < 100.0) continue;
    // Crossed at fixed phase: the located peak is the top of the cap, T-46 at sin θ = 1.
    const double epsilon = std::numbers::pi * f / 4.0;
    ASSERT_TRUE(curve.peak.has_value()) << kt0;
    EXPECT_NEAR((curve.peak->amplitude_h1 / x_s - 1.0) / (epsilon / (1.0 - epsilon)), 1.0, 0.02) << kt0;
  }
}

// An undamped 10-DOF chain (unit masses and springs, x_0 tied to ground, Jenkins contacts k_T0 = 2,
// μF_N = 1 at (1, ground), (3, 2), (5, ground), (7, 6), (9, ground); F = 0.1 at DOF 9) over
// Ω ∈ [0.1, 2.5]. Its contact-free mode at exactly 1 rad/s is a point of the 65-frequency sweep
// that sizes the arclength scale: the sampled response came out 5e14 times the median, and with
// that scale every step after the first point met a singular bordered matrix (reciprocal
// condition 1.9e-16, at every force and H: a light-damping known stop). Such samples are skipped
// now; the curve completes and its first point is the stuck linear response (all contacts stuck at
// Ω = 0.1: (K + K_T − Ω² M) X = F, closed form by a dense solve).
TEST(FrfContinuation, UndampedChainWithAResonanceOnTheScaleSweepCompletes) {
  const hb::DiscreteSystem s = hb::test::corpus_chain(0.0);
  const Eigen::Index n = s.dofs();
  const Eigen::MatrixXd stuck = Eigen::MatrixXd(hb::stuck_stiffness(s));
  hb::Excitation e;
  e.forces.push_back({9, 0.1, 1});
  FrfOptions o;
  o.omega_start = 0.1;
  o.omega_end = 2.5;
  o.harmonics = 3;
  o.time_samples = 256;  // at 64 the curve stops at Ω = 0.7087 (stick–slip near stuck mode 2)
  o.output_dof = 9;
  o.stability = Stability::never;
  o.error_estimate = false;
  const FrfCurve curve = trace_frf(s, e, o);
  ASSERT_TRUE(curve.completed()) << curve.message;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
  f(9) = 0.1;
  const Eigen::VectorXd x = (stuck - 0.01 * Eigen::MatrixXd::Identity(n, n)).lu().solve(f);
  EXPECT_NEAR(curve.points.front().amplitude_h1, std::abs(x(9)), 1e-10 * std::abs(x(9)));
}

// Started exactly at the undamped stuck resonance √11, where the stuck response is infinite (it
// used to end with "x0 entry 0 must be finite, got inf" and no point): the first point is the
// slip-limited response, between X_s and the energy bound, and the curve reaches its end.
TEST(FrfContinuation, StartsAtAnUndampedStuckResonance) {
  FrfOptions o;
  o.omega_start = std::sqrt(11.0);
  o.omega_end = 4.5;
  o.harmonics = 7;
  o.time_samples = 256;
  const FrfCurve curve = trace_frf(oscillator(10.0, 0.1, 0.0), force(0.005), o);
  ASSERT_TRUE(curve.completed()) << curve.message;
  EXPECT_GT(curve.points.front().amplitude_max, 0.01);
  EXPECT_LT(curve.points.front().amplitude_max, 0.01 / (1.0 - 0.005 / 0.1));
}

// A lightly damped peak far below the slip limit (ζ = 1e-4 of the stuck system, k_T0/k = 1e-2,
// F = 1e-6 μF_N: the stuck peak 5e-3 against the slip amplitude 100): the curve is the stuck linear
// one, with a peak 2·10⁻⁴ rad/s wide. A step over it landed on the flat branch beyond with the phase
// turned by π: the one-harmonic probe that sets the arclength scale found 1e-5 instead of 5e-3, and
// the curve then crawled at 1e-6 per point to max_points at Ω = 1.0045 (a light-damping known stop).
// Options::max_state_turn rejects such steps; the peak is now located to the closed form.
TEST(FrfContinuation, LightlyDampedLinearPeakIsResolvedNotSteppedOver) {
  const double zeta = 1e-4, kt0 = 0.01, f = 1e-6;
  const FrfCurve curve = trace_frf(oscillator(kt0, 1.0, zeta), force(f), light_damping_options(kt0));
  ASSERT_TRUE(curve.completed()) << curve.message;
  EXPECT_LT(curve.points.size(), 200u);
  // |X| peak of m ẍ + c ẋ + k_s x = f cos Ωt: f / (2 ζ k_s √(1 − ζ²)), with ζ of the stuck system.
  const double k_s = 1.0 + kt0;
  const double peak = f / (2.0 * zeta * k_s * std::sqrt(1.0 - zeta * zeta));
  ASSERT_TRUE(curve.peak.has_value());
  EXPECT_NEAR(curve.peak->amplitude_h1, peak, 1e-6 * peak);
  EXPECT_NEAR(curve.peak->omega, std::sqrt(k_s) * std::sqrt(1.0 - 2.0 * zeta * zeta), 1e-7);
  for (const auto& p : curve.points) {
    const double ref = receptance(k_s, 2.0 * zeta * std::sqrt(k_s), p.omega, f);
    EXPECT_NEAR(p.amplitude_h1, ref, 1e-8 * ref) << p.omega;
  }
}

// A gross-slip peak of a lightly damped system (ζ = 1e-4 of the stuck system, k_T0/k = 100,
// F = 10 μF_N): the response follows the contact-free oscillator up to about 4300, while the
// stuck sweep and the contact-free sweep (65 frequencies, none within 4 % of ω = 1) give 114. The
// one-harmonic probes stopped on the way up; the scale of the contact-free sweep alone made the
// curve take 1163 points (max_points = 1000 reached). The highest point a stopped probe reached now
// bounds the scale from below. Energy per period at the peak (x ≈ X cos Ωt, phase 90°):
// π F X = π c Ω X² + 4 μF_N (X − X_s), X_s = μF_N/k_T0 (one harmonic).
TEST(FrfContinuation, LightlyDampedGrossSlipPeakFinishesInFewPoints) {
  const double zeta = 1e-4, kt0 = 100.0, f = 10.0;
  const FrfCurve curve = trace_frf(oscillator(kt0, 1.0, zeta), force(f), light_damping_options(kt0));
  ASSERT_TRUE(curve.completed()) << curve.message;
  EXPECT_LT(curve.points.size(), 200u);
  ASSERT_TRUE(curve.peak.has_value());
  const double c = 2.0 * zeta * std::sqrt(1.0 + kt0), x_s = 1.0 / kt0;
  const double omega = curve.peak->omega;
  // X from c Ω X² − (F − 4/π) X − (4/π) X_s = 0 (μF_N = 1).
  const double b = f - 4.0 / std::numbers::pi;
  const double bound = (b + std::sqrt(b * b + 4.0 * c * omega * 4.0 / std::numbers::pi * x_s)) / (2.0 * c * omega);
  // Within 1e-4: the friction work is 4 μF_N (A − X_s) with A the half peak-to-peak swing, which
  // the higher harmonics move from X by ~1e-5 (measured: 4341.77 against 4341.73).
  EXPECT_NEAR(curve.peak->amplitude_h1, bound, 1e-4 * bound);
}

// Gross slip far above the friction limit (F = 3 μF_N, k_T0/k = 1e6, ζ = 0.02 of the stuck
// system): the response follows the contact-free oscillator, some 1000 times the stuck one. With
// the stuck response as the arclength scale the curve crawled (1000 points over 0.01 % of the
// range); the contact-free bound makes it finish in a few dozen.
TEST(FrfContinuation, GrossSlipFarAboveTheLimitFinishesInFewPoints) {
  FrfOptions o;
  o.omega_start = 0.5;
  o.omega_end = 1500.0;
  o.harmonics = 7;
  o.time_samples = 128;
  const FrfCurve curve = trace_frf(oscillator(1.0e6, 1.0, 0.02), force(3.0), o);
  ASSERT_TRUE(curve.completed()) << curve.message;
  EXPECT_LT(curve.points.size(), 200u);
  // Near Ω = 0.5 the contact-free receptance (c = 0.04 √(1 + 1e6) ≈ 40) bounds the response.
  EXPECT_GT(curve.points.front().amplitude_h1, 0.5 * receptance(1.0, 0.04 * std::sqrt(1.0 + 1.0e6), 0.5, 3.0));
}

// The same oscillator undamped and forced above the friction limit (F = 0.2 > 4 μF_N / π = 0.127):
// gross slip leaves the contact-free resonance at 1 rad/s undamped, so the response grows without
// bound and the curve cannot reach its end; its message says so and names the frequency.
TEST(FrfContinuation, UnboundedGrossSlipResonanceIsNamedInTheStopMessage) {
  FrfOptions o;
  o.omega_start = 0.5;
  o.omega_end = 4.5;
  o.harmonics = 3;
  o.time_samples = 64;
  o.continuation.max_points = 300;
  const FrfCurve curve = trace_frf(oscillator(10.0, 0.1, 0.0), force(0.2), o);
  ASSERT_FALSE(curve.completed());
  EXPECT_NEAR(curve.points.back().omega, 1.0, 0.02);
  EXPECT_NE(curve.message.find("natural frequency 1 rad/s of the system with every contact slipping"),
            std::string::npos) << curve.message;
  EXPECT_NE(curve.message.find("grows without bound"), std::string::npos) << curve.message;
}

// The distance of (Ω, |X₁|) from the polyline of `curve` in (Ω / range, ln |X₁|).
double distance_to_curve(const FrfPoint& p, const FrfCurve& curve, double range) {
  double best = std::numeric_limits<double>::infinity();
  const Eigen::Vector2d at(p.omega / range, std::log(p.amplitude_h1));
  for (std::size_t i = 0; i + 1 < curve.points.size(); ++i) {
    const Eigen::Vector2d a(curve.points[i].omega / range, std::log(curve.points[i].amplitude_h1));
    const Eigen::Vector2d b(curve.points[i + 1].omega / range, std::log(curve.points[i + 1].amplitude_h1));
    const double t = std::clamp((at - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-300), 0.0, 1.0);
    best = std::min(best, (a + t * (b - a) - at).norm());
  }
  return best;
}

// The undamped 10-DOF corpus chain at F = μF_N (H = 7, N_t = 256): a light-damping known stop until
// stop 51 (min_step at Ω = 0.4085); the curve now crosses there at fixed phase and restarts at
// fixed Ω beyond. That the restart lands on the branch itself and not on another solution is
// checked against the same curve swept downward from Ω_end (an independent run, which stops
// itself at Ω = 0.4303): where both exist, the upward points lie on the downward polyline — to
// 10⁻³ in (Ω/range, ln|X₁|) but for a few points on sharp superharmonic loops that one of the two
// runs resolves more coarsely (14 of 483 when written, the largest 0.087 at an antiresonance; since
// stop 53, whose rules against turning round and creeping change the upward run's path — 814
// points, 3 crossings — 6 of 477, the largest 4.6e-3).
TEST(FrfContinuation, ChainCrossingLandsOnTheBranchSweptDownward) {
  const hb::DiscreteSystem s = hb::test::corpus_chain(0.0);
  hb::Excitation e;
  e.forces.push_back({9, 1.0, 1});
  FrfOptions o = light_damping_options(0.0);
  o.omega_start = 0.1;
  o.omega_end = 2.5;
  o.output_dof = 9;
  const FrfCurve up = trace_frf(s, e, o);
  ASSERT_TRUE(up.completed()) << up.message;
  std::swap(o.omega_start, o.omega_end);
  const FrfCurve down = trace_frf(s, e, o);
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& p : down.points) lowest = std::min(lowest, p.omega);
  ASSERT_LT(lowest, 0.45) << down.message;  // the overlap covers the restart beyond 0.4085
  int compared = 0, close = 0;
  for (const auto& p : up.points) {
    if (p.omega < 1.001 * lowest) continue;
    ++compared;
    close += distance_to_curve(p, down, 2.4) <= 1e-3;
  }
  EXPECT_GT(compared, 300);
  EXPECT_GE(close, 0.95 * compared) << close << " of " << compared;
}

// Undamped, F = 10 μF_N (k_T0/k = 1, the light-damping corpus's settings): friction cannot bound
// the contact-free resonance at Ω = 1, where the response grows without bound. The curve now
// passes it (rescaled arclength, a crossing at fixed phase beyond the top) and reaches Ω_end; the
// message says what it passed. Far above the slip amplitude the contact slips all period and its
// force is a square wave ±μF_N in phase with the velocity, so at one harmonic
// πF X sin θ = 4 μF_N X and (k − Ω²) X = F cos θ: X = √(F² − (4μF_N/π)²) / |k − Ω²|, exact up to
// O(X_s/X) — both flanks of the peak follow it.
TEST(FrfContinuation, UnboundedGrossSlipResonanceIsPassedOnItsClosedForm) {
  const double f = 10.0;
  const FrfCurve curve = trace_frf(oscillator(1.0, 1.0, 0.0), force(f), light_damping_options(1.0));
  ASSERT_TRUE(curve.completed()) << curve.message;
  EXPECT_NE(curve.message.find("grows without bound"), std::string::npos) << curve.message;
  int below = 0, above = 0;
  for (const auto& p : curve.points) {
    if (p.amplitude_h1 < 1e3) continue;  // X_s = 1
    const double ref = std::sqrt(f * f - std::pow(4.0 / std::numbers::pi, 2)) / std::abs(1.0 - p.omega * p.omega);
    EXPECT_NEAR(p.amplitude_h1, ref, 1e-2 * ref) << p.omega;
    (p.omega < 1.0 ? below : above) += 1;
  }
  EXPECT_GT(below, 10);
  EXPECT_GT(above, 10);
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
