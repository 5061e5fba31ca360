// Damping curves and FRFs of a preloaded joint in modal/interface form
// (continuation/interface_response.hpp): the linear limit of the backbone, the energy balance
// injected = viscous + contact dissipation at every point (contact W_D from the law's own loop
// integral), the backbone against fixed-amplitude Newton solves, and FRF peaks on the backbone.
#include "jointhb/continuation/interface_response.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cstdio>
#include <memory>

#include "../hb/interface_test_model.hpp"
#include "jointhb/contact/jenkins_law.hpp"
#include "jointhb/continuation/backbone.hpp"
#include "jointhb/hb/nonlinear_mode.hpp"

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

// The turns of a finite-element damping curve (docs/stability.md §7), checked as the discrete ones
// are (NonlinearMode.ChainDampingCurveNamesTheInternalResonanceWhereItStops), by Newton's method at
// fixed λ, independent of the continuation: at a turn λ* the residual vanishes, and roots near
// the turn's state exist on one side of λ* only.
TEST(InterfaceBackbone, TurnsAtAnInternalResonanceAreExtremaOfTheAmplitude) {
  for (const double k2 : {3.0, 2.0}) {
    SCOPED_TRACE(k2);
    const hb::InterfaceModel model = two_dof_joint(k2);
    ASSERT_EQ(model.validate(), "");
    InterfaceBackboneOptions o;
    o.mode.balance = {.harmonics = 3, .time_samples = 64};
    o.log10_amplitude_start = -3.0;
    o.log10_amplitude_end = 1.0;
    const InterfaceBackbone b = trace_interface_backbone(model, o);  // 51 unknowns: dense (dense_below)
    ASSERT_TRUE(b.completed()) << b.message;
    std::printf("2-DOF joint, k_2 = %g: %zu points, %zu turns\n", k2, b.points.size(), b.turns.size());
    ASSERT_GE(b.turns.size(), 2u);
    hb::InterfaceModeOptions mode = o.mode;
    mode.balance.dense_jacobian = true;
    const hb::InterfaceModeResidual epmc(model, mode);
    // From y0 at fixed λ: converged to a root within `near` of y0?
    const auto root_near = [&](const Eigen::VectorXd& y0, double lambda, double near) {
      Eigen::VectorXd y = y0;
      hb::InterfaceModeResidual::Evaluation e;
      for (int it = 0; it < 20; ++it) {
        epmc.evaluate(y, lambda, true, e);
        if (e.residual.lpNorm<Eigen::Infinity>() < 1e-11) return (y - y0).norm() < near * y0.norm();
        y -= e.d_state.partialPivLu().solve(e.residual);
      }
      return false;
    };
    for (std::size_t k = 0; k < b.turns.size(); ++k) {
      const BackboneTurn& t = b.turns[k];
      std::printf("  turn at log10 q = %.9f ± %.1e (%d points), Ω = %.6f, ζ = %.5f\n", t.log10_amplitude,
                  t.log10_amplitude_bound, t.points, t.omega, t.damping_ratio);
      ASSERT_TRUE(t.refined) << k << ": " << t.message;
      EXPECT_LT(t.log10_amplitude_bound, 1e-5) << k;
      hb::InterfaceModeResidual::Evaluation e;
      epmc.evaluate(t.unknowns, t.log10_amplitude, false, e);
      EXPECT_LT(e.residual.lpNorm<Eigen::Infinity>(), 1e-9) << k;
      EXPECT_NEAR(t.omega, t.unknowns[epmc.balance().unknowns()], 1e-15);
      const double delta = 1e-4;  // above every bound; roots within ~√δ of the turn
      const bool below = root_near(t.unknowns, t.log10_amplitude - delta, 5e-2);
      const bool above = root_near(t.unknowns, t.log10_amplitude + delta, 5e-2);
      EXPECT_NE(below, above) << "turn " << k << " at log10 q = " << t.log10_amplitude;
    }
    // The first turn is a maximum of λ (the curve comes back), the second a minimum.
    EXPECT_GT(b.turns[0].log10_amplitude, b.turns[1].log10_amplitude);
    // A second method: the same system as a discrete model (hb/nonlinear_mode.hpp: DOF coordinates,
    // its own AFT of the Jenkins law, the amplitude normalised by the mass norm of the fundamental
    // instead of the modal coordinate). With k_2 = 2 its curve stopped at log10 q = −0.668 until
    // stop 48: after a natural-parameter step the tangent oriented by τ_k pointed back along the
    // branch, although Newton's method at fixed λ finds it going on (docs/continuation.md,
    // "Natural-parameter fallback at corners"). Every point of its damping curve, mapped to the joint's
    // unknowns (η = Φᵀx, M = I; δg = (x0, 0, 0); ŷ = y/q with q = η₁'s a₁; the phase conditions
    // coincide, b₁ᵀMφ₁ = η₁'s b₁), is a root of the joint's EPMC residual at λ = log10 q: the two
    // implementations trace the same branch through both turns.
    const hb::DiscreteSystem d = two_dof_discrete(k2);
    BackboneOptions dopt;
    dopt.mode.harmonics = 3;
    dopt.mode.time_samples = 64;
    dopt.log10_amplitude_start = -3.0;
    dopt.log10_amplitude_end = 1.0;
    dopt.error_estimate = false;
    const BackboneCurve discrete = trace_backbone(d, dopt);
    ASSERT_TRUE(discrete.completed()) << discrete.message;
    const hb::NonlinearModeResidual dm(d, dopt.mode);
    const hb::FourierBasis& db = dm.balance().basis();
    const hb::FourierBasis& fb = epmc.balance().basis();
    Eigen::MatrixXd modes;
    two_dof_joint_modes(k2, 1.0, modes);
    const Eigen::MatrixXd phi = modes.topRows(2);  // x rows of the joint's mode shapes
    const Eigen::Index U = epmc.balance().unknowns();
    double worst = 0.0;
    int crossed_turns = 0;
    for (const BackbonePoint& p : discrete.points) {
      const double qd = p.state.amplitude;
      Eigen::VectorXd y = Eigen::VectorXd::Zero(U + 2);
      for (const int k : db.orders())
        for (int c = 0; c < 2; ++c) {
          const Eigen::Vector2d x(qd * p.unknowns[dm.balance().index(0, db.cosine_index(k) + c)],
                                  qd * p.unknowns[dm.balance().index(1, db.cosine_index(k) + c)]);
          for (int j = 0; j < 4; ++j) y[epmc.balance().modal_index(j, fb.cosine_index(k) + c)] = phi.col(j).dot(x);
          y[epmc.balance().gap_index(0, 0, fb.cosine_index(k) + c)] = x[0];
        }
      const double q = y[epmc.balance().modal_index(epmc.followed_mode(), fb.cosine_index(1))];
      y /= q;
      y[U] = p.state.omega;
      y[U + 1] = p.unknowns[p.unknowns.size() - 1];  // ξ
      hb::InterfaceModeResidual::Evaluation e;
      epmc.evaluate(y, std::log10(q), false, e);
      worst = std::max(worst, e.residual.lpNorm<Eigen::Infinity>());
      for (const BackboneTurn& t : b.turns)
        if (std::abs(p.state.omega - t.omega) < 2e-3) ++crossed_turns;
    }
    std::printf("discrete 2-DOF model: %zu points, worst joint residual %.1e\n", discrete.points.size(), worst);
    EXPECT_LT(worst, 1e-9);
    EXPECT_GT(crossed_turns, 0);  // its points reach the turns' neighbourhood
    if (k2 != 3.0) continue;
    // Matrix-free (dense_below = 0) the curve starts too: at the linear start the followed mode's
    // block is singular and the preconditioner, exact on this one-point joint, divided by zero
    // ("GMRES: relative residual 1 after 0 iterations", InterfaceModeResidual::preconditioner).
    o.dense_below = 0;
    o.continuation.max_points = 12;
    const InterfaceBackbone free = trace_interface_backbone(model, o);
    ASSERT_EQ(free.points.size(), 12u) << free.message;
    EXPECT_NEAR(free.points.front().state.omega / b.linear_omega, 1.0, 1e-9);
    for (std::size_t i = 0; i < 12; ++i)
      EXPECT_NEAR(free.points[i].state.omega, b.points[i].state.omega, 1e-8 * b.linear_omega) << i;
  }
}

}  // namespace
}  // namespace jointhb::continuation
