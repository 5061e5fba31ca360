// The crossing at fixed phase (continuation/phase_bridge.hpp) on the friction cap of an undamped
// Jenkins oscillator (m = k = 1, k_T0 = 1, μF_N = 1, F = 10⁻⁶): every point solves the harmonic
// balance and its phase condition, and where the cap is resolved its amplitude follows the
// one-harmonic energy balance (docs/theory.md §8, T-46).
#include "../../../src/continuation/phase_bridge.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../../../src/continuation/balance_adapters.hpp"
#include "jenkins_oscillator.hpp"
#include "jointhb/hb/harmonic_balance.hpp"

namespace jointhb::continuation::detail {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(PhaseBridge, CrossesTheFrictionCapOfAnUndampedResonance) {
  const double force = 1e-6;
  hb::HarmonicBalanceOptions ho;
  ho.harmonics = 7;
  ho.time_samples = 256;
  const hb::HarmonicBalance b(test::jenkins_oscillator(1.0, 1.0, 0.0), test::force_at_dof0(force), ho);
  const Eigen::Index a1 = b.index(0, b.basis().cosine_index(1));
  const PhaseRotation rotate = harmonic_rotation(b, 1);
  // From just above the slip amplitude X_s = 1 at phase π/64, ω_stuck = √2.
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(b.unknowns());
  x0[a1] = (1.0 + 0.1 * force) * std::cos(kPi / 64);
  x0[a1 + 1] = (1.0 + 0.1 * force) * std::sin(kPi / 64);
  PhaseBridgeOptions o;
  o.phase_cosine = a1;
  o.omega_low = 0.5;
  o.omega_high = 2.5;
  o.residual_scale = force;
  o.state_scale = 1.0;
  o.parameter_scale = 2.0;
  const PhaseBridge bridge = bridge_by_phase(residual_of(b), rotate, x0, std::sqrt(2.0), o, {});
  ASSERT_GE(bridge.points.size(), 8u) << bridge.message;
  int resolved = 0;
  for (const PhaseBridgePoint& p : bridge.points) {
    hb::HarmonicBalanceEvaluation ev;
    b.evaluate(p.x, p.omega, false, ev);
    EXPECT_LE(ev.residual.lpNorm<Eigen::Infinity>(), 1e-7 * force) << p.theta;  // the round-off floor
    EXPECT_NEAR(fundamental_phase(p.x, a1), std::remainder(p.theta, 2 * kPi), 1e-10);
    EXPECT_NEAR(p.omega, std::sqrt(2.0), 1e-5);  // the cap: Ω within 10⁻⁵ of ω_stuck
    // T-46 where sin θ ≥ 0.7; harmonics beyond the first carry a few per cent.
    if (std::sin(p.theta) < 0.7) continue;
    const double epsilon = kPi * force * std::sin(p.theta) / 4.0;
    const double excess = std::hypot(p.x[a1], p.x[a1 + 1]) - 1.0;
    EXPECT_NEAR(excess / (epsilon / (1.0 - epsilon)), 1.0, 0.05) << p.theta;
    ++resolved;
  }
  EXPECT_GE(resolved, 3);
}

}  // namespace
}  // namespace jointhb::continuation::detail
