// The trial-direction generalisation of the tangential laws to two directions
// (tangential_law.hpp): reduction to 1D on straight paths, bounds, derivatives, and the 2D Jenkins
// steady state on a circular path against its closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/jenkins_law.hpp"
#include "jointhb/contact/periodic_state.hpp"

namespace jc = jointhb::contact;
using jc::Mat2;
using jc::Vec2;

TEST(TangentialStep2D, StraightPathInAnyDirectionReducesExactlyTo1D) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  jc::GaulMayerLaw law(0.35);
  const jc::TangentialLimits lim{1.5, 20.0};
  for (double angle : {0.0, 0.3, 2.0, -2.7}) {
    const Vec2 e(std::cos(angle), std::sin(angle));
    double f1d = 0.0;
    Vec2 t = Vec2::Zero();
    for (int i = 0; i < 2000; ++i) {
      const double slip = 0.05 * u(rng);
      const auto s1 = law.scalar_step(f1d, slip, lim);
      const auto s2 = law.step(t, slip * e, lim);
      f1d = s1.force;
      t = s2.traction;
      ASSERT_NEAR(t.dot(e), f1d, 1e-14 * lim.slip_limit) << "step " << i;
      ASSERT_NEAR((t - t.dot(e) * e).norm(), 0.0, 1e-14 * lim.slip_limit);
      ASSERT_NEAR(s2.dissipation, s1.dissipation, 1e-13 * (1 + s1.dissipation));
    }
  }
}

TEST(TangentialStep2D, BoundedAndDissipativeOnRandomPaths) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  for (double n : {0.1, 0.5, 0.9}) {
    jc::GaulMayerLaw law(n);
    Vec2 t = Vec2::Zero();
    for (int i = 0; i < 20000; ++i) {
      // The limit varies too (normal motion), sometimes below |t| (radial slip onto it).
      const jc::TangentialLimits lim{1.0 + 0.5 * std::sin(0.01 * i), 10.0};
      const auto s = law.step(t, 0.03 * Vec2(g(rng), g(rng)), lim);
      ASSERT_TRUE(s.traction.allFinite() && s.d_traction.allFinite() && s.d_slip.allFinite());
      ASSERT_LE(s.traction.norm(), lim.slip_limit * (1 + 1e-15));
      ASSERT_GE(s.dissipation, 0.0);
      t = s.traction;
    }
  }
}

TEST(TangentialStep2D, OpenContactHasNoTractionAndFiniteTangents) {
  jc::GaulMayerLaw law(1.0 / 3.0);
  const auto s = law.step(Vec2(0.3, -0.2), Vec2(1e-3, 2e-3), {0.0, 0.0});
  EXPECT_EQ(s.traction.norm(), 0.0);
  EXPECT_TRUE(s.d_traction.allFinite() && s.d_slip.allFinite() && s.d_limit.allFinite());
}

TEST(TangentialStep2D, AnalyticDerivativesMatchFiniteDifferences) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  jc::GaulMayerLaw gm(0.3);
  jc::JenkinsLaw jk;
  int compared = 0;
  for (const jc::TangentialLaw* law :
       {static_cast<const jc::TangentialLaw*>(&gm), static_cast<const jc::TangentialLaw*>(&jk)}) {
    for (int trial = 0; trial < 300; ++trial) {
      const jc::TangentialLimits lim{1.0 + 0.2 * u(rng), 10.0 * (1.0 + 0.2 * u(rng))};
      const Vec2 t0 = 1.05 * lim.slip_limit * Vec2(u(rng), u(rng)) / std::sqrt(2.0);
      const Vec2 dg = 0.1 * Vec2(u(rng), u(rng));
      const auto s = law->step(t0, dg, lim);
      const auto at = [&](const Vec2& t, const Vec2& d, double L, double k) {
        return law->step(t, d, {L, k}).traction;
      };
      const double h = 1e-7;
      Mat2 fd_t, fd_g;
      Vec2 fd_l, fd_k;
      bool smooth = true;
      const auto check = [&](const Vec2& plus, const Vec2& minus, const Vec2& centre, double step) {
        // Skip differences that straddle a branch change (one-sided slopes disagree).
        const Vec2 fwd = (plus - centre) / step, bwd = (centre - minus) / step;
        if ((fwd - bwd).norm() > 1e-4 * (1 + fwd.norm())) smooth = false;
        return Vec2((plus - minus) / (2 * step));
      };
      const Vec2 c = s.traction;
      for (int j = 0; j < 2; ++j) {
        const Vec2 e = Vec2::Unit(j);
        fd_t.col(j) = check(at(t0 + h * e, dg, lim.slip_limit, lim.stiffness),
                            at(t0 - h * e, dg, lim.slip_limit, lim.stiffness), c, h);
        fd_g.col(j) = check(at(t0, dg + h * e, lim.slip_limit, lim.stiffness),
                            at(t0, dg - h * e, lim.slip_limit, lim.stiffness), c, h);
      }
      fd_l = check(at(t0, dg, lim.slip_limit + h, lim.stiffness),
                   at(t0, dg, lim.slip_limit - h, lim.stiffness), c, h);
      const double hk = h * lim.stiffness;
      fd_k = check(at(t0, dg, lim.slip_limit, lim.stiffness + hk),
                   at(t0, dg, lim.slip_limit, lim.stiffness - hk), c, hk);
      if (!smooth) continue;
      ++compared;
      EXPECT_LT((s.d_traction - fd_t).norm(), 1e-6 * (1 + fd_t.norm())) << law->name();
      EXPECT_LT((s.d_slip - fd_g).norm(), 1e-6 * (1 + fd_g.norm())) << law->name();
      EXPECT_LT((s.d_limit - fd_l).norm(), 1e-6 * (1 + fd_l.norm())) << law->name();
      EXPECT_LT((s.d_stiffness - fd_k).norm(), 1e-6 * (1 + fd_k.norm())) << law->name();
    }
  }
  EXPECT_GT(compared, 500);  // almost all random states are away from branch changes
}

TEST(TangentialStep2D, JenkinsOnACircleConvergesToTheClosedForm) {
  // Steady sliding on g = a (cos θ, sin θ): |t| = F_s, the slider runs on a circle of radius
  // ρ = sqrt(a² - (F_s/k)²) with t ⊥ its position, so W_D = 2π F_s ρ.
  jc::JenkinsLaw law;
  const double fs = 1.0, k = 10.0, a = 0.25;
  const double exact = 2.0 * std::numbers::pi * fs * std::sqrt(a * a - (fs / k) * (fs / k));
  double previous_error = 0.0;
  for (int n : {64, 256, 1024, 4096}) {
    jc::PeriodicPath path;
    for (int i = 0; i < n; ++i) {
      const double th = 2.0 * std::numbers::pi * i / n;
      path.slip.emplace_back(a * std::cos(th), a * std::sin(th));
      path.limits.push_back({fs, k});
    }
    const auto r = jc::solve_periodic_state(law, path);
    ASSERT_EQ(r.termination, jointhb::Termination::converged);
    const double error = std::abs(r.dissipation - exact) / exact;
    if (previous_error > 0.0) {
      // first-order splitting in the direction: the error falls at least ~4x per 4x samples
      EXPECT_LT(error, previous_error / 3.0) << "N=" << n;
    }
    previous_error = error;
  }
  EXPECT_LT(previous_error, 2e-3);
}
