// The exponential normal contact about its preload (contact/preloaded_normal_law.hpp, N-3): its
// exact increment, the curvature of its backbone against the Lindstedt–Poincaré closed form
// (softening and hardening, with the observed second-order rate), and the physical folds of a
// lightly damped FRF (docs/stability.md §4): Hill's multipliers against the monodromy of the orbit
// and against finite differences of the time-integrated period map, the multiplier +1 at both
// folds, and the two coexisting steady states between the folds by time integration (Newmark),
// independent of harmonic balance.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <complex>

#include "jointhb/contact/preloaded_normal_law.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/hb/nonlinear_mode.hpp"
#include "jointhb/hb/orbit_monodromy.hpp"
#include "jointhb/timeint/newmark.hpp"

namespace jointhb::continuation {
namespace {

// m = 1 on a spring k to ground and a preloaded normal contact (F_N0, k_N) to ground, damping c.
hb::DiscreteSystem mass_on_preloaded_contact(double k, double kn, double preload, double c) {
  hb::DiscreteSystem s;
  s.mass = Eigen::MatrixXd::Identity(1, 1).sparseView();
  s.stiffness = (k * Eigen::MatrixXd::Identity(1, 1)).sparseView();
  s.damping = (c * Eigen::MatrixXd::Identity(1, 1)).sparseView();
  hb::ContactElement e;
  e.law = "normal-exponential";
  e.stiffness = kn;
  e.normal_force = preload;
  s.contacts.push_back(e);
  return s;
}

TEST(NormalContact, IncrementsReproduceTheLawAndItsDerivatives) {
  const contact::PreloadedNormalLaw law;
  const contact::TangentialLimits limits{2.0, 5.0};  // F_N0 = 2, k_N = 5: λ = 2.5
  double g = 0.0, f = 0.0;
  for (const double dg : {0.3, -0.9, 0.05, 1.7, -2.2, 0.4}) {
    const contact::ScalarStep s = law.scalar_step(f, dg, limits);
    g += dg;
    f = s.force;
    EXPECT_NEAR(f, contact::PreloadedNormalLaw::force(g, 2.0, 5.0), 1e-13 * std::max(1.0, std::abs(f)));
    EXPECT_NEAR(s.d_slip, contact::PreloadedNormalLaw::tangent(g, 2.0, 5.0), 1e-12 * s.d_slip);
    EXPECT_EQ(s.dissipation, 0.0);
    const double h = 1e-6;
    const auto at = [&](double f0, double slip, double fn, double kn) {
      return law.scalar_step(f0, slip, {fn, kn}).force;
    };
    const double f0 = f - 0.1;
    const contact::ScalarStep d = law.scalar_step(f0, dg, limits);
    const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-7 * (1.0 + std::abs(b)); };
    EXPECT_PRED2(near, d.d_force, (at(f0 + h, dg, 2.0, 5.0) - at(f0 - h, dg, 2.0, 5.0)) / (2 * h));
    EXPECT_PRED2(near, d.d_limit, (at(f0, dg, 2.0 + h, 5.0) - at(f0, dg, 2.0 - h, 5.0)) / (2 * h));
    EXPECT_PRED2(near, d.d_stiffness, (at(f0, dg, 2.0, 5.0 + h) - at(f0, dg, 2.0, 5.0 - h)) / (2 * h));
  }
  // Opening saturates at the preload (the contact unloads), closing stiffens exponentially.
  EXPECT_NEAR(contact::PreloadedNormalLaw::force(20.0, 2.0, 5.0), 2.0, 1e-15);
  EXPECT_GT(contact::PreloadedNormalLaw::tangent(-1.0, 2.0, 5.0), 12.0 * 5.0);
}

// ω(a) = ω₀ (1 + κ a² + O(a⁴)) with κ = (1.5 r − 2.5 r²) λ²/24, r = k_N/(k + k_N) (N-3; Nayfeh &
// Mook §4.1 with α₂ = −r ω₀² λ/2, α₃ = r ω₀² λ²/6): softening for r > 0.6, hardening below. The
// EPMC's q is the fundamental's amplitude here (m = 1, one DOF). Points at fixed q by Newton.
TEST(NormalContact, BackboneCurvatureMatchesLindstedtPoincareAtSecondOrder) {
  for (const double r : {1.0, 0.9, 0.4}) {
    const double w0sq = 2.0, kn = r * w0sq, preload = 1.0, lambda = kn / preload;
    hb::NonlinearModeOptions o;
    o.mode = 1;
    o.harmonics = 8;
    o.time_samples = 64;
    const hb::NonlinearModeResidual epmc(mass_on_preloaded_contact((1.0 - r) * w0sq, kn, preload, 0.0), o);
    const double w0 = std::sqrt(w0sq);
    const double kappa = (1.5 * r - 2.5 * r * r) * lambda * lambda / 24.0;
    Eigen::VectorXd y = epmc.linear_start();
    double deviation[2] = {0.0, 0.0};
    const double amplitudes[2] = {0.01 / lambda, 0.04 / lambda};
    for (int k = 0; k < 2; ++k) {
      const double q = amplitudes[k];
      hb::NonlinearModeResidual::Evaluation e;
      for (int it = 0; it < 30; ++it) {
        epmc.evaluate(y, std::log10(q), true, e);
        ASSERT_TRUE(e.ok) << e.message;
        if (e.residual.lpNorm<Eigen::Infinity>() < 1e-15) break;
        y -= e.d_state.partialPivLu().solve(e.residual);
      }
      ASSERT_LT(e.residual.lpNorm<Eigen::Infinity>(), 1e-13) << "r = " << r;
      const hb::NonlinearModeState s = epmc.state(y, std::log10(q));
      EXPECT_NEAR(s.amplitude, q, 1e-15);
      EXPECT_NEAR(s.damping_ratio, 0.0, 1e-13);  // elastic: nothing to inject
      const double measured = (s.omega / w0 - 1.0) / (q * q);
      deviation[k] = measured - kappa;
      EXPECT_NEAR(measured, kappa, 2e-3 * std::abs(kappa) + 1e-6) << "r = " << r << ", q = " << q;
    }
    // The O(a⁴) term: the deviation grows 16-fold when a grows 4-fold (observed order 2).
    const double order = std::log(deviation[1] / deviation[0]) / std::log(4.0);
    EXPECT_NEAR(order, 2.0, 0.05) << "r = " << r << ": " << deviation[0] << ", " << deviation[1];
  }
}

// x(0) and ẋ(0) of a harmonic-balance point (the excitation's phase: cos Ωt).
timeint::State state_at_zero(const hb::HarmonicBalance& b, const Eigen::VectorXd& x, double omega) {
  const hb::FourierBasis& basis = b.basis();
  timeint::State s;
  s.displacement = Eigen::VectorXd::Constant(1, basis.has_mean() ? x[b.index(0, 0)] : 0.0);
  s.velocity = Eigen::VectorXd::Zero(1);
  for (int h = 1; h <= basis.harmonics(); ++h) {
    const int i = basis.cosine_index(h);
    if (i < 0) continue;
    s.displacement[0] += x[b.index(0, i)];
    s.velocity[0] += h * omega * x[b.index(0, i + 1)];
  }
  return s;
}

// The Floquet multipliers by finite differences of the period map (the shooting reference of
// docs/stability.md §2, here for one DOF: Φ is 2 × 2 in (x, ẋ)): Newmark over one period from the
// orbit's state at t = 0 perturbed by ±h in x and in ẋ; the contact force follows from the gap
// (State::contact_forces left empty: the law's F(g)). The largest |ρ|.
double period_map_max_multiplier(const hb::DiscreteSystem& s, const hb::Excitation& e, double omega,
                                 const timeint::State& z, double scale) {
  timeint::NewmarkOptions o;
  const int steps = 2048;
  o.time_step = 2.0 * std::acos(-1.0) / omega / steps;
  Eigen::Matrix2d phi;
  for (int j = 0; j < 2; ++j) {
    const double h = 1e-6 * scale * (j == 0 ? 1.0 : omega);
    Eigen::Vector2d end[2];
    for (int sign = 0; sign < 2; ++sign) {
      timeint::State start = z;
      (j == 0 ? start.displacement : start.velocity)[0] += sign == 0 ? h : -h;
      const timeint::TransientResult r = timeint::integrate(s, e, omega, start, steps, o);
      EXPECT_EQ(r.termination, Termination::reached_end) << r.message;
      end[sign] = {r.final_state.displacement[0], r.final_state.velocity[0]};
    }
    phi.col(j) = (end[0] - end[1]) / (2.0 * h);
  }
  return phi.eigenvalues().cwiseAbs().maxCoeff();
}

// Softening (r = 0.91, λ = 1) at ζ ≈ 0.5 % under F = 0.01: the FRF turns back twice. Every point's
// verdict by Hill's method (on the HB Jacobian) agrees with the monodromy of the variational
// equation integrated along the orbit, and away from the folds with the period map's (finite
// differences of Newmark periods); the folds carry ρ = +1; and between them time integration
// from the upper and the lower stable point stays on two different steady states.
TEST(NormalContact, LightlyDampedFrfFoldsAndItsStabilityAgreesWithTheMonodromyAndNewmark) {
  const hb::DiscreteSystem s = mass_on_preloaded_contact(0.1, 1.0, 1.0, 0.01);
  hb::Excitation e;
  e.forces.push_back({0, 0.01, 1});
  FrfOptions o;
  o.omega_start = 0.8;
  o.omega_end = 1.3;
  o.harmonics = 6;
  o.time_samples = 64;
  o.stability = Stability::always;
  o.stability_method = StabilityMethod::hill;
  const FrfCurve curve = trace_frf(s, e, o);
  ASSERT_TRUE(curve.completed()) << curve.message;
  ASSERT_EQ(curve.folds.size(), 2u);
  hb::HarmonicBalanceOptions ho;
  ho.harmonics = o.harmonics;
  ho.time_samples = o.time_samples;
  const hb::HarmonicBalance balance(s, e, ho);
  EXPECT_TRUE(balance.basis().has_mean());  // the law is not odd: a static offset develops
  int unstable = 0, compared = 0;
  double worst = 0.0;
  for (const auto& p : curve.points) {
    ASSERT_TRUE(p.stability_known) << p.omega;
    const hb::FloquetResult m = hb::orbit_floquet(balance, p.coefficients, p.omega, {});
    ASSERT_TRUE(m.ok) << m.message;
    EXPECT_EQ(m.unstable == 0, p.stable) << "Ω = " << p.omega << ": |ρ| monodromy " << m.max_multiplier
                                          << ", Hill " << p.max_multiplier;
    if (std::abs(p.max_multiplier - 1.0) > 1e-2) EXPECT_NEAR(m.max_multiplier, p.max_multiplier, 2e-3) << p.omega;
    // The period map by time integration, away from the folds' neighbourhood (there the truncated
    // orbit's multiplier is within its own error of 1, docs/stability.md §4).
    const double shooting = period_map_max_multiplier(s, e, p.omega, state_at_zero(balance, p.coefficients, p.omega), p.amplitude_h1);
    if (std::abs(p.max_multiplier - 1.0) > 1e-2) {
      EXPECT_NEAR(shooting, p.max_multiplier, 2e-3) << p.omega;
      EXPECT_EQ(shooting <= 1.0 + 1e-6, p.stable) << p.omega;
      worst = std::max(worst, std::abs(shooting - p.max_multiplier));
      ++compared;
    }
    unstable += p.stable ? 0 : 1;
  }
  EXPECT_GE(unstable, 3);
  EXPECT_GE(compared, static_cast<int>(curve.points.size()) - 8);
  std::printf("[ period map ] %d of %zu points compared, largest |Δ|ρ|| %.2e\n", compared, curve.points.size(), worst);
  const hb::HillStability hill(balance);
  for (const FrfExtremum& fold : curve.folds) {
    ASSERT_TRUE(fold.refined) << fold.message;
    const hb::FloquetResult r = hill.evaluate(fold.coefficients, fold.omega);
    ASSERT_TRUE(r.ok) << r.message;
    double closest = 1e300;
    for (const auto& rho : r.multipliers) closest = std::min(closest, std::abs(rho - 1.0));
    EXPECT_LT(closest, 1e-3);
  }
  // Softening: the upper fold (the jump down) lies above the lower one in Ω, both below ω₀.
  const double w_low = std::min(curve.folds[0].omega, curve.folds[1].omega);
  const double w_high = std::max(curve.folds[0].omega, curve.folds[1].omega);
  EXPECT_LT(w_high, std::sqrt(1.1));
  // At Ω between the folds: the two stable points, each integrated for whole periods, stay apart.
  const double omega = 0.5 * (w_low + w_high);
  std::vector<double> branch;  // |fundamental| of the stable points crossing Ω
  for (std::size_t i = 1; i < curve.points.size(); ++i) {
    const FrfPoint& a = curve.points[i - 1];
    const FrfPoint& b = curve.points[i];
    if ((a.omega - omega) * (b.omega - omega) > 0.0 || !a.stable || !b.stable) continue;
    const FrfPoint& near = std::abs(a.omega - omega) < std::abs(b.omega - omega) ? a : b;
    timeint::SteadyStateOptions so;
    so.steps_per_period = 1024;
    so.max_periods = 4000;
    so.tolerance = 1e-8;
    so.harmonics = 1;
    const timeint::SteadyStateResult t =
        timeint::forced_steady_state(s, e, near.omega, so, state_at_zero(balance, near.coefficients, near.omega));
    ASSERT_EQ(t.termination, Termination::converged) << t.message;
    const double amplitude = std::hypot(t.coefficients(0, 1), t.coefficients(0, 2));
    std::printf("[ Newmark ] Ω = %.6f: HB %.8f, Newmark %.8f (%d periods)\n", near.omega, near.amplitude_h1, amplitude, t.periods);
    EXPECT_NEAR(amplitude, near.amplitude_h1, 1e-3 * near.amplitude_h1) << "Ω = " << near.omega;
    branch.push_back(amplitude);
  }
  ASSERT_EQ(branch.size(), 2u);
  EXPECT_GT(std::abs(branch[0] - branch[1]), 0.2 * std::max(branch[0], branch[1]));
}

}  // namespace
}  // namespace jointhb::continuation
