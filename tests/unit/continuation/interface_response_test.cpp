// Damping curves and FRFs of a preloaded joint in modal/interface form
// (continuation/interface_response.hpp): the linear limit of the backbone, the energy balance
// injected = viscous + contact dissipation at every point (contact W_D from the law's own loop
// integral), the backbone against fixed-amplitude Newton solves, and FRF peaks on the backbone.
#include "jointhb/continuation/interface_response.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../hb/interface_test_model.hpp"

namespace jointhb::continuation {
namespace {

using namespace jointhb::hb::testing;

TEST(InterfaceBackbone, LinearLimitEnergyBalanceAndSoftening) {
  for (bool gm : {true, false}) {
    const Structure s = make_structure(4, 4, 9, 0.0, gm);
    const hb::InterfaceModel model = make_model(s, s.n, gm);  // every mode kept: exact energy ledger
    InterfaceBackboneOptions o;
    o.mode.balance = {.harmonics = 3, .time_samples = 64};
    o.log10_amplitude_start = gm ? -9.0 : -7.0;
    o.log10_amplitude_end = -3.5;
    const InterfaceBackbone b = trace_interface_backbone(model, o);
    ASSERT_TRUE(b.completed()) << b.message;
    const auto& first = b.points.front().state;
    std::printf("%s: %zu points, %d Newton iterations; linear ω %.6f ζ %.6e; first ω %.6f ζ %.6e; last ω %.6f ζ %.4e (%d slip)\n",
                gm ? "Gaul-Mayer" : "Jenkins", b.points.size(), b.newton_iterations, b.linear_omega,
                b.linear_damping_ratio, first.omega, first.damping_ratio, b.points.back().state.omega,
                b.points.back().state.damping_ratio, b.points.back().state.slipping_points);
    EXPECT_NEAR(first.omega / b.linear_omega, 1.0, gm ? 1e-5 : 1e-9);
    EXPECT_NEAR(first.damping_ratio / b.linear_damping_ratio, 1.0, gm ? 2e-2 : 1e-6);
    double worst = 0.0;
    for (const auto& p : b.points) {
      const auto& st = p.state;
      worst = std::max(worst, std::abs(st.injected_energy - st.viscous_dissipation - st.fourier_dissipation) / st.injected_energy);
    }
    std::printf("  energy balance worst %.2e\n", worst);
    EXPECT_LT(worst, 1e-7);
    // microslip: frequency falls and damping rises over the curve
    EXPECT_LT(b.points.back().state.omega, 0.999 * first.omega);
    EXPECT_GT(b.points.back().state.damping_ratio, 1.2 * first.damping_ratio);
  }
}

// A damping curve started at q = 1e-14 (issue 23): there the contact forces are increments of
// ~1e-14 relative on preload-sized tractions, the linear limit holds exactly, and the curve must
// start and go on (it failed at its first step: residual floored by cancellation).
TEST(InterfaceBackbone, StartsAtATinyAmplitudeOnTheLinearLimit) {
  const Structure s = make_structure(4, 4, 9, 0.0, true);
  const hb::InterfaceModel model = make_model(s, s.n, true);
  InterfaceBackboneOptions o;
  o.mode.balance = {.harmonics = 3, .time_samples = 64};
  o.log10_amplitude_start = -14.0;
  o.log10_amplitude_end = -6.0;
  const InterfaceBackbone b = trace_interface_backbone(model, o);
  ASSERT_TRUE(b.completed()) << b.message;
  const auto& first = b.points.front().state;
  EXPECT_NEAR(first.omega / b.linear_omega, 1.0, 1e-9);
  EXPECT_NEAR(first.damping_ratio / b.linear_damping_ratio, 1.0, 1e-9);
  std::printf("q = 1e-14 .. 1e-6: %zu points, first omega/linear - 1 = %.2e, zeta/linear - 1 = %.2e\n", b.points.size(),
              first.omega / b.linear_omega - 1.0, first.damping_ratio / b.linear_damping_ratio - 1.0);
}

TEST(InterfaceFrf, PeaksLieOnTheBackbone) {
  const Structure s = make_structure(4, 4, 9, 0.0, false);
  const hb::InterfaceModel model = make_model(s, 10, false);
  InterfaceBackboneOptions bo;
  bo.mode.balance = {.harmonics = 3, .time_samples = 64};
  bo.log10_amplitude_start = -7.0;
  bo.log10_amplitude_end = -3.0;
  const InterfaceBackbone b = trace_interface_backbone(model, bo);
  ASSERT_TRUE(b.completed()) << b.message;
  const hb::InterfaceBalance hb(model, bo.mode.balance);
  const int a1 = hb.basis().cosine_index(1);
  for (double force : {2.0, 20.0, 60.0}) {
    InterfaceFrfOptions fo;
    fo.omega_start = 0.9 * b.linear_omega;
    fo.omega_end = 1.05 * b.linear_omega;
    fo.load_amplitude = force;
    fo.balance = bo.mode.balance;
    fo.continuation.max_step = 0.05;
    const InterfaceFrf f = trace_interface_frf(model, fo);
    ASSERT_TRUE(f.completed()) << f.message;
    // the peak of the followed mode's modal amplitude, refined by a parabola through 3 points
    std::size_t best = 0;
    auto q_of = [&](const InterfaceFrfPoint& p) {
      return std::hypot(p.unknowns[hb.modal_index(0, a1)], p.unknowns[hb.modal_index(0, a1 + 1)]);
    };
    for (std::size_t i = 0; i < f.points.size(); ++i)
      if (q_of(f.points[i]) > q_of(f.points[best])) best = i;
    ASSERT_GT(best, 0u);
    ASSERT_LT(best + 1, f.points.size());
    const double x0 = f.points[best - 1].omega, x1 = f.points[best].omega, x2 = f.points[best + 1].omega;
    const double y0 = q_of(f.points[best - 1]), y1 = q_of(f.points[best]), y2 = q_of(f.points[best + 1]);
    const double denom = (x0 - x1) * (x0 - x2) * (x1 - x2);
    const double A = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / denom;
    const double B = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / denom;
    const double w_peak = -B / (2 * A);
    const double q_peak = y1;
    // backbone Ω at q_peak (linear interpolation in log q)
    double w_bb = 0.0;
    for (std::size_t i = 0; i + 1 < b.points.size(); ++i) {
      const double qa = b.points[i].state.amplitude, qb = b.points[i + 1].state.amplitude;
      if (q_peak >= qa && q_peak <= qb) {
        const double t = std::log(q_peak / qa) / std::log(qb / qa);
        w_bb = (1 - t) * b.points[i].state.omega + t * b.points[i + 1].state.omega;
      }
    }
    std::printf("force %5.1f: peak q %.3e at Ω %.6f, backbone Ω %.6f, relative %.2e (%zu points, %d Newton)\n",
                force, q_peak, w_peak, w_bb, std::abs(w_peak - w_bb) / w_bb, f.points.size(), f.newton_iterations);
    ASSERT_GT(w_bb, 0.0);
    EXPECT_LT(std::abs(w_peak - w_bb) / w_bb, 2e-3);
  }
}

}  // namespace
}  // namespace jointhb::continuation
