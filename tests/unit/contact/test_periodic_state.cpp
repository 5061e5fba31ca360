// Periodic steady state (periodic_state.hpp): against brute-force cycling where cycling converges,
// the closed-form steady loop, the reference policy for stuck contacts, and the sensitivities
// against finite differences of the whole solve.
#include <cstdlib>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>
#include <numbers>

#include "jointhb/contact/closed_forms.hpp"
#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/jenkins_law.hpp"
#include "jointhb/contact/contact_point.hpp"
#include "jointhb/contact/periodic_state.hpp"
#include "lap_h3_path.hpp"

namespace jc = jointhb::contact;
using jc::Vec2;

namespace {

// A 2D multi-harmonic path with internal reversals and a varying limit/stiffness (normal motion).
jc::PeriodicPath rich_path(int n, double scale, double normal_depth) {
  jc::PeriodicPath p;
  for (int i = 0; i < n; ++i) {
    const double th = 2.0 * std::numbers::pi * i / n;
    p.slip.emplace_back(scale * (std::cos(th) + 0.4 * std::cos(3 * th + 0.5)),
                        scale * (0.3 * std::sin(th) + 0.2 * std::sin(2 * th)));
    const double pressure = std::exp(-normal_depth * std::cos(th + 0.7));
    p.limits.push_back({1.0 * pressure, 10.0 * pressure});
  }
  return p;
}

Vec2 run_cycles(const jc::TangentialLaw& law, const jc::PeriodicPath& p, Vec2 t, int cycles) {
  const std::size_t n = p.slip.size();
  for (int c = 0; c < cycles; ++c) {
    for (std::size_t i = 0; i < n; ++i) {
      t = law.step(t, p.slip[(i + 1) % n] - p.slip[i], p.limits[(i + 1) % n]).traction;
    }
  }
  return t;
}

}  // namespace

TEST(PeriodicState, MatchesLongCyclingAtLargeAmplitude) {
  jc::GaulMayerLaw law(0.3);
  const auto path = rich_path(200, 0.12, 0.3);
  const auto r = jc::solve_periodic_state(law, path);
  ASSERT_EQ(r.termination, jointhb::Termination::converged);
  EXPECT_LE(r.iterations, 10);
  const Vec2 cycled = run_cycles(law, path, Vec2::Zero(), 400);
  EXPECT_NEAR((cycled - r.traction[0]).norm(), 0.0, 1e-12);
  EXPECT_LT(r.residual, 1e-13);
  EXPECT_GT(r.dissipation, 0.0);
}

TEST(PeriodicState, SmallAmplitudeNewtonWhereCyclingStalls) {
  // Each period contracts the error only by (1 - F̂/F_s)^{2n}: here ~1 - 2e-4. Newton needs a
  // handful of periods; 100 cycles of brute force leave most of the initial error.
  const double n = 1.0 / 3.0;
  jc::GaulMayerLaw law(n);
  const jc::closed_form::MicroslipParameters p{n, 1.0, 10.0};
  const double a = 1e-4 * jc::closed_form::full_slip_span(p);
  jc::PeriodicPath path;
  const int samples = 128;
  for (int i = 0; i < samples; ++i) {
    path.slip.emplace_back(a * std::cos(2.0 * std::numbers::pi * i / samples), 0.0);
    path.limits.push_back({p.slip_limit, p.stiffness});
  }
  const auto r = jc::solve_periodic_state(law, path);
  ASSERT_EQ(r.termination, jointhb::Termination::converged);
  EXPECT_LE(r.iterations, 6);
  const auto loop = jc::closed_form::symmetric_loop(a, p);
  EXPECT_NEAR(r.traction[0].x(), loop.force_amplitude, 1e-10 * loop.force_amplitude);
  EXPECT_NEAR(r.dissipation, loop.dissipation, 1e-12 * loop.dissipation);
  // Cycling from the unloaded state for 100 periods is still far off.
  const Vec2 cycled = run_cycles(law, path, Vec2(0.5 * loop.force_amplitude, 0.0), 100);
  EXPECT_GT(std::abs(cycled.x() - loop.force_amplitude), 1e-3 * loop.force_amplitude);
}

TEST(PeriodicState, PreloadedTractionAcrossTheMotionRelaxesByDampedNewton) {
  // A preloaded FE contact point (bolted lap, case 05 coarse) in microslip: constant pressure,
  // tangential motion along y only, preloaded traction along x. Gaul–Mayer relaxes t_x to ~0 over
  // thousands of periods. The full Newton step overshoots (the map is only piecewise smooth): the
  // undamped Newton/fixed-point alternation needed 55 periods here, and more than 400 (residual
  // 73 Pa) on the lap's own path with its 1e-14 m of x motion; the damped Newton needs about ten
  // (docs/theory.md §5).
  jc::GaulMayerLaw law(1.0 / 3.0);
  const double limit = 0.3 * 3.392e6, stiffness = 2.714e12, a = 6.0e-9;
  jc::PeriodicPath path;
  const int samples = 32;
  for (int i = 0; i < samples; ++i) {
    path.slip.emplace_back(0.0, a * std::cos(2.0 * std::numbers::pi * i / samples));
    path.limits.push_back({limit, stiffness});
  }
  jc::PeriodicStateOptions o;
  o.tolerance = 1e-12;
  o.max_iterations = 400;
  o.reference_traction = Vec2(2.948e4, 0.0);
  o.reference_slip = path.slip[0];
  const auto r = jc::solve_periodic_state(law, path, o);
  ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
  EXPECT_LE(r.iterations, 20);
  const Vec2 cycled = run_cycles(law, path, o.reference_traction, 20000);
  EXPECT_NEAR((cycled - r.traction[0]).norm(), 0.0, 1e-9 * limit);
  EXPECT_LT(std::abs(r.traction[0].x()), 1.0);  // relaxed from 2.9e4 Pa
}

// KNOWN LIMIT, disabled until solved (docs/theory.md §5, "Creep"): a point of the lap at H = 3
// (lap_h3_path.hpp) whose steady state lies ~53 000 Pa away along a direction in which each
// period moves the state by only ~21 Pa, with a monodromy eigenvalue above 1 on the way. The
// damped Newton ends after 400 periods 21 Pa from periodic; 20 000 periods of cycling reach the
// steady state. Gating Newton by the spectral radius of M and extrapolating the fixed-point step
// along the drift solved this path in 15 periods but made the small-amplitude states of the lap
// noisy enough to stall its H = 1 damping curve at q = 2e-9 (tried 2026-11-24, reverted).
TEST(PeriodicState, TranslationLikePeriodMapIsCrossedWithinFewPeriods) {
  jc::ContactPointOptions o;
  o.normal = {lap_h3_path::kPressure, lap_h3_path::kDecay, 0.0};
  o.friction_coefficient = lap_h3_path::kMu;
  o.stiffness_model = jc::TangentialStiffnessModel::constant;
  o.tangential_stiffness = lap_h3_path::kStiffness;
  const jc::ContactPoint point(o, std::make_shared<jc::GaulMayerLaw>(1.0 / 3.0));
  std::vector<jc::Vec3> path;
  for (const auto& g : lap_h3_path::kPath) path.emplace_back(g[0], g[1], g[2]);
  jc::PeriodicStateOptions po;
  po.tolerance = 1e-12;
  po.max_iterations = 400;
  po.reference_traction = Vec2(lap_h3_path::kReferenceTraction[0], lap_h3_path::kReferenceTraction[1]);
  po.reference_slip = Vec2(lap_h3_path::kReferenceSlip[0], lap_h3_path::kReferenceSlip[1]);
  const jc::PeriodicContactResult r = point.periodic(path, po);
  ASSERT_EQ(r.tangential.termination, jointhb::Termination::converged) << r.tangential.message;
  EXPECT_LE(r.tangential.iterations, 30);
  // Brute force from the anchor: 20 000 periods of exact steps.
  Vec2 t = po.reference_traction;
  for (int period = 0; period < 20000; ++period) {
    for (std::size_t i = 0; i < path.size(); ++i)
      t = point.step(t, path[i], path[(i + 1) % path.size()]).traction.head<2>();
  }
  EXPECT_NEAR((t - r.tangential.traction[0]).norm(), 0.0, 1e-6 * t.norm());
}

TEST(PeriodicState, StuckJenkinsContactIsLinearAboutTheReference) {
  jc::JenkinsLaw law;
  jc::PeriodicPath path;
  for (int i = 0; i < 64; ++i) {
    path.slip.emplace_back(0.02 * std::cos(2.0 * std::numbers::pi * i / 64), 0.0);
    path.limits.push_back({1.0, 10.0});
  }
  jc::PeriodicStateOptions o;
  o.reference_traction = Vec2(0.3, -0.1);
  o.reference_slip = Vec2(0.01, 0.0);
  const auto r = jc::solve_periodic_state(law, path, o);
  ASSERT_TRUE(r.stuck);
  for (int i = 0; i < 64; ++i) {
    const Vec2 linear = o.reference_traction + 10.0 * (path.slip[i] - o.reference_slip);
    EXPECT_NEAR((r.traction[i] - linear).norm(), 0.0, 1e-15);
  }
  EXPECT_EQ(r.dissipation, 0.0);
}

TEST(PeriodicState, JenkinsThatCannotStickAtTheReferenceMovesToTheClosestPeriodicState) {
  // Anchored force 0.9 + 0.5 cos θ exceeds the limit 1: the contact slips once and then sticks
  // with its maximum on the limit, force 1 - 0.5 (1 - cos θ).
  jc::JenkinsLaw law;
  jc::PeriodicPath path;
  for (int i = 0; i < 64; ++i) {
    path.slip.emplace_back(0.05 * std::cos(2.0 * std::numbers::pi * i / 64), 0.0);
    path.limits.push_back({1.0, 10.0});
  }
  jc::PeriodicStateOptions o;
  o.reference_traction = Vec2(0.9, 0.0);
  const auto r = jc::solve_periodic_state(law, path, o);
  ASSERT_EQ(r.termination, jointhb::Termination::converged);
  EXPECT_TRUE(r.stuck);
  for (int i = 0; i < 64; ++i) {
    EXPECT_NEAR(r.traction[i].x(), 1.0 - 10.0 * (0.05 - path.slip[i].x()), 1e-14);
  }
}

TEST(PeriodicState, GappingErasesMemory) {
  // The limit vanishes for part of the period (the contact opens): the traction is zero there and
  // the state after reclosing follows from the path alone.
  jc::GaulMayerLaw law(0.5);
  jc::PeriodicPath path;
  for (int i = 0; i < 100; ++i) {
    const double th = 2.0 * std::numbers::pi * i / 100;
    path.slip.emplace_back(0.1 * std::cos(th), 0.05 * std::sin(th));
    const double p = std::max(0.0, std::cos(th + 1.0));
    path.limits.push_back({p, 10.0 * p});
  }
  const auto r = jc::solve_periodic_state(law, path);
  ASSERT_EQ(r.termination, jointhb::Termination::converged);
  EXPECT_LE(r.iterations, 3);
  for (int i = 0; i < 100; ++i) {
    if (path.limits[i].slip_limit == 0.0) {
      EXPECT_EQ(r.traction[i].norm(), 0.0);
    }
    EXPECT_LE(r.traction[i].norm(), path.limits[i].slip_limit + 1e-15);
  }
}

TEST(PeriodicState, SensitivityMatchesFiniteDifferencesOfTheWholeSolve) {
  for (double n : {0.2, 0.6}) {
    jc::GaulMayerLaw law(n);
    const int samples = 48;
    const auto path = rich_path(samples, 0.08, 0.4);
    const auto base = jc::solve_periodic_state(law, path);
    ASSERT_EQ(base.termination, jointhb::Termination::converged);
    // Three perturbation directions: smooth slip, limit and stiffness modulations.
    const int m = 3;
    Eigen::MatrixXd dslip = Eigen::MatrixXd::Zero(2 * samples, m);
    Eigen::MatrixXd dlimit = Eigen::MatrixXd::Zero(samples, m);
    Eigen::MatrixXd dstiff = Eigen::MatrixXd::Zero(samples, m);
    for (int i = 0; i < samples; ++i) {
      const double th = 2.0 * std::numbers::pi * i / samples;
      dslip(2 * i, 0) = std::cos(2 * th);
      dslip(2 * i + 1, 0) = std::sin(th);
      dlimit(i, 1) = std::cos(th);
      dstiff(i, 2) = 10.0 * std::sin(th + 0.3);
    }
    const Eigen::MatrixXd analytic = jc::periodic_sensitivity(base, dslip, dlimit, dstiff);
    const double h = 1e-7;
    for (int j = 0; j < m; ++j) {
      auto plus = path, minus = path;
      for (int i = 0; i < samples; ++i) {
        const Vec2 dg(dslip(2 * i, j), dslip(2 * i + 1, j));
        plus.slip[i] += h * dg;
        minus.slip[i] -= h * dg;
        plus.limits[i].slip_limit += h * dlimit(i, j);
        minus.limits[i].slip_limit -= h * dlimit(i, j);
        plus.limits[i].stiffness += h * dstiff(i, j);
        minus.limits[i].stiffness -= h * dstiff(i, j);
      }
      const auto rp = jc::solve_periodic_state(law, plus);
      const auto rm = jc::solve_periodic_state(law, minus);
      double error = 0.0, size = 0.0;
      for (int i = 0; i < samples; ++i) {
        const Vec2 fd = (rp.traction[i] - rm.traction[i]) / (2 * h);
        error = std::max(error, (fd - analytic.block<2, 1>(2 * i, j)).norm());
        size = std::max(size, fd.norm());
      }
      EXPECT_LT(error, 1e-5 * size) << "n=" << n << " direction " << j;
      EXPECT_GT(size, 1e-3);
    }
  }
}

TEST(PeriodicState, RejectsInconsistentPaths) {
  jc::GaulMayerLaw law(0.3);
  jc::PeriodicPath path;
  path.slip = {Vec2(0, 0), Vec2(1, 0)};
  path.limits = {{1.0, 1.0}};
  EXPECT_THROW((void)jc::solve_periodic_state(law, path), std::invalid_argument);
  path.limits = {{1.0, 1.0}, {std::nan(""), 1.0}};
  EXPECT_THROW((void)jc::solve_periodic_state(law, path), std::invalid_argument);
}
