// The folds and the resonance peak of a finite-element FRF located between its points
// (continuation/frf_extrema.hpp through trace_interface_frf) against the discrete FRF of the same
// equations (trace_frf, whose extrema are checked against closed forms in frf_extrema tests of
// docs/stability.md §3).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cmath>
#include <cstdio>

#include "../hb/interface_test_model.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/continuation/interface_response.hpp"

namespace jointhb::continuation {
namespace {

using namespace jointhb::hb::testing;

// The one-point joint of interface_test_model.hpp loaded and observed on its normal DOF z0: with
// the contact stuck and x0, x1, y0 at rest, z̈ + 0.002 ż + 50 z + (1 − e^{−z}) = F cos Ωt (the normal
// law p = e^{−g_N} about its preload 1, tangent 1; eq. N-3 with F_N0 = k_N = 1), which softens as
// the gap opens: light damping (ζ = 1.4e-4) makes the FRF fold near ω₀ = √51.
hb::InterfaceModel normal_joint() {
  hb::InterfaceModel m = two_dof_joint(3.0);
  Eigen::MatrixXd phi;
  two_dof_joint_modes(3.0, 1.0, phi);
  m.load_modal = phi.row(3).transpose();  // f = e_z
  m.outputs[0].name = "z0";
  m.outputs[0].modal = phi.row(3).transpose();
  return m;
}

hb::DiscreteSystem normal_oscillator() {
  hb::DiscreteSystem d;
  Eigen::MatrixXd one = Eigen::MatrixXd::Ones(1, 1);
  d.mass = one.sparseView();
  d.stiffness = (50.0 * one).sparseView();
  d.damping = (0.002 * one).sparseView();
  hb::ContactElement normal;
  normal.law = "normal-exponential";
  normal.dof_a = 0;
  normal.normal_force = 1.0;
  normal.stiffness = 1.0;
  d.contacts.push_back(normal);
  return d;
}

TEST(InterfaceFrfExtrema, FoldsAndPeakAreTheDiscreteFrfsOfTheSameEquations) {
  // Both ways of solving the bordered systems: matrix-free (GMRES with the run's preconditioner,
  // the default of FE FRFs) and with the dense Jacobian (LU).
  const double force = 0.02, w0 = 6.9, w1 = 7.4;
  FrfOptions d;
  d.omega_start = w0;
  d.omega_end = w1;
  d.harmonics = 7;
  d.time_samples = 64;
  hb::Excitation e;
  e.forces.push_back({0, force, 1});
  const FrfCurve reference = trace_frf(normal_oscillator(), e, d);
  ASSERT_TRUE(reference.completed()) << reference.message;

  for (const bool matrix_free : {true, false}) {
    SCOPED_TRACE(matrix_free ? "matrix-free" : "dense");
    InterfaceFrfOptions o;
    o.omega_start = w0;
    o.omega_end = w1;
    o.load_amplitude = force;
    o.balance.harmonics = 7;
    o.balance.time_samples = 64;
    o.matrix_free = matrix_free;
    const InterfaceFrf fe = trace_interface_frf(normal_joint(), o);
    ASSERT_TRUE(fe.completed()) << fe.message;

    ASSERT_EQ(reference.folds.size(), 2u);  // the softening bend: up and back
    ASSERT_EQ(fe.folds.size(), reference.folds.size());
    for (std::size_t k = 0; k < fe.folds.size(); ++k) {
      const FrfExtremum &f = fe.folds[k], &r = reference.folds[k];
      std::printf("%s fold %zu: Ω = %.12f (discrete %.12f), bound %.1e, |u| %.9f (%.9f), %d points\n",
                  matrix_free ? "matrix-free" : "dense", k, f.omega, r.omega, f.value_bound, f.amplitude_h1,
                  r.amplitude_h1, f.points);
      EXPECT_TRUE(f.refined) << f.message;
      EXPECT_LT(f.value_bound, 1e-8);
      EXPECT_NEAR(f.omega, r.omega, 1e-8);
      // At a fold Ω is flat along the branch and the amplitude is not: a bound δ on Ω leaves the
      // amplitude within O(√δ) (measured 1.1e-6 relative with δ = 3e-10).
      EXPECT_NEAR(f.amplitude_h1, r.amplitude_h1, 1e-5 * r.amplitude_h1);
    }
    ASSERT_TRUE(fe.peak && reference.peak);
    const FrfExtremum &p = *fe.peak, &r = *reference.peak;
    std::printf("%s peak: Ω = %.12f (discrete %.12f), |u| = %.12f (%.12f), bound %.1e\n",
                matrix_free ? "matrix-free" : "dense", p.omega, r.omega,
                p.amplitude_h1, r.amplitude_h1, p.value_bound);
    EXPECT_TRUE(p.refined) << p.message;
    EXPECT_NEAR(p.amplitude_h1, r.amplitude_h1, 1e-8 * r.amplitude_h1);
    EXPECT_NEAR(p.omega, r.omega, 1e-5);  // Ω at a flat maximum: to the square root of the amplitude's
    EXPECT_LT(p.value_bound, 1e-8 * p.amplitude_h1);
    double highest = 0.0;
    for (const InterfaceFrfPoint& q : fe.points) highest = std::max(highest, q.amplitude_h1);
    EXPECT_GE(p.amplitude_h1, highest);  // the located peak is above every accepted point
    EXPECT_GT(fe.timings.refinement, 0.0);
  }
}

}  // namespace
}  // namespace jointhb::continuation

namespace jointhb::continuation {
namespace {

TEST(InterfaceFrfExtrema, HillsMethodHasMultiplierOneAtTheFoldsAndTheMonodromysVerdict) {
  // The softening FRF of normal_joint() (two folds) traced with Hill's method for its stability
  // (hb/interface_hill_stability.hpp) and again with the monodromy of the orbit (independent: the
  // variational equation integrated in time, N_f = 4096): the same verdict at every point, the
  // multipliers close, and at each located fold Hill's multiplier +1 (the Jacobian singular there).
  InterfaceFrfOptions o;
  o.omega_start = 6.9;
  o.omega_end = 7.4;
  o.load_amplitude = 0.02;
  o.balance.harmonics = 7;
  o.balance.time_samples = 64;
  o.stability = Stability::always;
  o.stability_method = StabilityMethod::hill;
  const InterfaceFrf hill = trace_interface_frf(normal_joint(), o);
  o.stability_method = StabilityMethod::monodromy;
  o.monodromy.samples = 4096;
  const InterfaceFrf monodromy = trace_interface_frf(normal_joint(), o);
  ASSERT_TRUE(hill.completed()) << hill.message;
  ASSERT_TRUE(monodromy.completed()) << monodromy.message;
  ASSERT_EQ(hill.points.size(), monodromy.points.size());  // stability does not steer the curve
  int unstable = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < hill.points.size(); ++k) {
    const InterfaceFrfPoint &h = hill.points[k], &m = monodromy.points[k];
    ASSERT_TRUE(h.stability_known && m.stability_known) << h.omega;
    ASSERT_EQ(h.omega, m.omega);
    EXPECT_EQ(h.stable, m.stable) << h.omega << ": Hill " << h.max_multiplier << ", monodromy " << m.max_multiplier;
    worst = std::max(worst, std::abs(h.max_multiplier - m.max_multiplier));
    unstable += h.stable ? 0 : 1;
  }
  EXPECT_GT(unstable, 0);  // the branch between the folds
  EXPECT_LT(worst, 2e-3);
  ASSERT_EQ(hill.folds.size(), 2u);
  const hb::InterfaceBalance balance(normal_joint(), o.balance);
  for (const FrfExtremum& f : hill.folds) {
    ASSERT_TRUE(f.refined) << f.message;
    const hb::FloquetResult r = hb::interface_hill_floquet(balance, f.coefficients, f.omega);
    ASSERT_TRUE(r.ok) << r.message;
    double nearest = 1e300;
    for (const std::complex<double>& rho : r.multipliers) nearest = std::min(nearest, std::abs(rho - 1.0));
    std::printf("fold at Ω = %.9f: Hill's multiplier nearest +1 at %.1e\n", f.omega, nearest);
    EXPECT_LT(nearest, 1e-5);  // λ ∝ √δΩ near a fold (bounds 3e-10, 3e-13); 9e-4 at the stable points (damping)
  }
  std::printf("%zu points, %d unstable; max |ρ| by Hill and by the monodromy within %.1e\n",
              hill.points.size(), unstable, worst);
}

}  // namespace
}  // namespace jointhb::continuation

namespace jointhb::continuation {
namespace {

TEST(InterfaceFrfStability, AutomaticChoiceFollowsEachMethodsCost) {
  // The monodromy (O(N_f (3P)³)) up to 10 contact points; Hill's method (O((3P(2H+1))³)) up to
  // 3P(2H + 1) = 2100 gap unknowns; always and never whatever the size.
  EXPECT_TRUE(computes_interface_stability(Stability::automatic, 10));
  EXPECT_FALSE(computes_interface_stability(Stability::automatic, 11));
  EXPECT_TRUE(computes_interface_stability(Stability::automatic, 100, StabilityMethod::hill, 3));   // 2100
  EXPECT_FALSE(computes_interface_stability(Stability::automatic, 101, StabilityMethod::hill, 3));  // 2121
  EXPECT_FALSE(computes_interface_stability(Stability::automatic, 100, StabilityMethod::hill, 7));
  EXPECT_TRUE(computes_interface_stability(Stability::always, 10000, StabilityMethod::monodromy, 7));
  EXPECT_FALSE(computes_interface_stability(Stability::never, 1, StabilityMethod::hill, 1));
}

}  // namespace
}  // namespace jointhb::continuation
