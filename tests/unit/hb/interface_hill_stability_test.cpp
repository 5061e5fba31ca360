// Hill's method for a finite-element joint (hb/interface_hill_stability.hpp, eq. T-36a) against
// closed forms (a stuck joint is a linear system: its exponents are the first-order eigenvalues,
// exactly, with every mode kept) and against Hill's method of the discrete system written the
// other way (hb/hill_stability.hpp: its own Jacobian, its own AFT) on the same orbit.
#include "jointhb/hb/interface_hill_stability.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <complex>
#include <cstdio>
#include <limits>
#include <numbers>
#include <tuple>
#include <utility>
#include <vector>

#include "interface_test_model.hpp"
#include "one_point_joint_orbit.hpp"
#include "jointhb/hb/harmonic_balance.hpp"
#include "jointhb/hb/interface_orbit_monodromy.hpp"

namespace jointhb::hb {
namespace {

using namespace jointhb::hb::testing;
using cd = std::complex<double>;

// e^{λT} for each eigenvalue λ of the first-order form of M ẍ + C ẋ + K x = 0.
Eigen::VectorXcd exact_multipliers(const Eigen::MatrixXd& M, const Eigen::MatrixXd& C,
                                   const Eigen::MatrixXd& K, double period) {
  const Eigen::Index n = M.rows();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -M.ldlt().solve(K);
  a.bottomRightCorner(n, n) = -M.ldlt().solve(C);
  const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(a, false).eigenvalues();
  return (lambda * period).array().exp();
}

// The stuck joint of interface_test_model.hpp with C_pre = 2 in t1 while the law's k_T = 3: the
// contact adds the stiffness 1 to x0 beyond K_t (B ≠ 0), and the joint is the linear 4-DOF system
// K = K_t + e₀e₀ᵀ, x0 of mass ε.
Eigen::Matrix4d stuck_stiffness() {
  Eigen::Matrix4d K;
  K << 8.0, -3.0, 0.0, 0.0, -3.0, 3.0, 0.0, 0.0, 0.0, 0.0, 53.0, 0.0, 0.0, 0.0, 0.0, 51.0;
  return K;
}

TEST(InterfaceHillStability, StuckJointHasTheExponentsOfItsLinearSystem) {
  // Every mode kept: exact (round-off) for any Ω and H. Residual x0 (mass ε, ω² ≈ 8/ε): the
  // condensed multipliers approach the 4-DOF system's as ε → 0.
  const Eigen::Matrix4d K = stuck_stiffness();
  std::vector<double> errors;
  for (const double eps : {1e-2, 1e-3, 1e-4}) {
    const Eigen::Matrix4d M = Eigen::Vector4d(eps, 1.0, 1.0, 1.0).asDiagonal();
    for (const int kept : {4, 3}) {
      InterfaceModel model = two_dof_joint(3.0, kept, eps);
      model.stuck_tangents[0](0, 0) = 2.0;
      for (const auto& [h, omega] : {std::pair{1, 0.7}, std::pair{3, 1.05}, std::pair{7, 2.3}}) {
        SCOPED_TRACE(::testing::Message() << "ε " << eps << ", kept " << kept << ", H " << h << ", Ω " << omega);
        InterfaceBalanceOptions jo;
        jo.harmonics = h;
        jo.time_samples = 8 * h;
        jo.static_mean_tangential = false;  // the law's k_T on the mean too (T-28 would give it C_pre)
        const InterfaceBalance joint(model, jo);
        const FloquetResult r =
            interface_hill_floquet(joint, Eigen::VectorXd::Zero(joint.unknowns()), omega);
        ASSERT_TRUE(r.ok) << r.message;
        ASSERT_EQ(r.multipliers.size(), 2 * kept);
        EXPECT_LT(r.kept_centre, 1e-6);  // the exponents of a linear system: no harmonic content
        const Eigen::VectorXcd exact = exact_multipliers(M, 0.002 * M, K, 2.0 * std::numbers::pi / omega);
        const double error = matched(r.multipliers, exact);
        if (kept == 4) {
          EXPECT_LT(error, 1e-10);
          EXPECT_LT(matched(exact, r.multipliers), 1e-10);  // and none missing
        } else if (h == 3) {
          errors.push_back(error);
          std::printf("ε = %.0e: condensed multipliers within %.2e of the full system's\n", eps, error);
        }
        EXPECT_EQ(r.unstable, 0);
      }
    }
  }
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_LT(errors.back(), 1e-5);
  EXPECT_GT(errors[0] / errors[1], 5.0);  // converging with ε
  EXPECT_GT(errors[1] / errors[2], 5.0);
}

TEST(InterfaceHillStability, SlippingJointHasTheDiscreteSystemsExponents) {
  // Force 0.2 on x1 at Ω = 1.05 and 0.9 (below the stuck ω₁ = 1.181): the contact slips every half
  // period. On one orbit (a root of both residuals), the discrete system's four multipliers
  // (x0, x1) by its Hill's method are among the joint's eight (every mode kept), and the normal
  // direction's pair is e^{(−c/2 ± i√(51 − c²/4))T} (c = 0.002; the normal law's tangent equals
  // C_pre: a linear direction, exact). Jenkins and Gaul–Mayer.
  for (const bool gaul_mayer : {false, true}) {
    for (const double omega : {1.05, 0.9}) {
      SCOPED_TRACE(::testing::Message() << (gaul_mayer ? "gaul-mayer" : "jenkins") << " Ω " << omega);
      InterfaceBalanceOptions jo;
      jo.harmonics = 7;
      jo.time_samples = 256;
      jo.static_mean_tangential = false;  // as the discrete system: the mean of t_T from the law
      const TwinOrbit t = twin_orbit(omega, 0.2, gaul_mayer, jo);
      ASSERT_TRUE(t.at.ok) << t.at.message;
      ASSERT_LT(t.at.residual.lpNorm<Eigen::Infinity>(), 1e-10);  // one orbit, both models
      ASSERT_GT(t.at.slipping_points, 0);

      const FloquetResult rd = HillStability(t.discrete).evaluate(t.x, omega);
      const FloquetResult rj = interface_hill_floquet(t.joint, t.y, omega);
      ASSERT_TRUE(rd.ok) << rd.message;
      ASSERT_TRUE(rj.ok) << rj.message;
      ASSERT_EQ(rd.multipliers.size(), 4);
      ASSERT_EQ(rj.multipliers.size(), 8);
      const double error = matched(rd.multipliers, rj.multipliers);
      EXPECT_LT(error, 1e-9);
      EXPECT_EQ(rj.unstable, rd.unstable);
      const double period = 2.0 * std::numbers::pi / omega;
      Eigen::VectorXcd normal(2);
      for (int s = 0; s < 2; ++s)
        normal[s] = std::exp(cd(-0.001, (s == 0 ? 1.0 : -1.0) * std::sqrt(51.0 - 1e-6)) * period);
      EXPECT_LT(matched(normal, rj.multipliers), 1e-10);
      std::printf("%s Ω = %.2f: max |ρ| %.6f (discrete %.6f), the discrete four within %.1e, centres %.3f/%.3f\n",
                  gaul_mayer ? "gaul-mayer" : "jenkins", omega, rj.max_multiplier, rd.max_multiplier, error,
                  rj.kept_centre, rj.rejected_centre);
    }
  }
}

// The joint with a rigid-body mode put first (ω² = 0, Gφ = 0, unloaded, not observed), and the
// unknowns y of the joint without it extended by that mode's zero coefficients.
InterfaceModel with_rigid_mode(const InterfaceModel& joint) {
  InterfaceModel m = joint;
  const Eigen::Index ns = joint.num_modes();
  m.rigid_modes = 1;
  m.omega2.resize(ns + 1);
  m.omega2 << 0.0, joint.omega2;
  m.gap_shapes.resize(3, ns + 1);
  m.gap_shapes << Eigen::Vector3d::Zero(), joint.gap_shapes;
  m.load_modal.resize(ns + 1);
  m.load_modal << 0.0, joint.load_modal;
  for (InterfaceOutput& o : m.outputs) {
    const Eigen::VectorXd modal = o.modal;
    o.modal.resize(ns + 1);
    o.modal << 0.0, modal;
  }
  return m;
}

TEST(InterfaceHillStability, RigidBodyModesAddNothing) {
  // A free-free structure's rigid-body modes do not move the interface: the multipliers of the
  // joint with one more (rigid) kept mode are those without it, by Hill's method and by the
  // monodromy (its trivial multipliers 1 and e^{−aT} left out), on the slipping orbit of the
  // one-point Jenkins joint.
  const double omega = 1.05, force = 0.2;
  InterfaceBalanceOptions jo;
  jo.harmonics = 5;
  jo.time_samples = 128;
  const TwinOrbit t = twin_orbit(omega, force, false, jo);
  const InterfaceBalance& elastic = t.joint;
  const Eigen::VectorXd& y = t.y;
  const InterfaceBalance free(with_rigid_mode(two_dof_joint(3.0)), jo);
  const Eigen::Index m = elastic.basis().size();
  Eigen::VectorXd y_free = Eigen::VectorXd::Zero(free.unknowns());
  y_free.tail(y.size()) = y;
  InterfaceBalanceEvaluation check;
  free.evaluate(y_free, omega, 0.0, free.cosine_load(force), false, check);
  ASSERT_LT(check.residual.lpNorm<Eigen::Infinity>(), 1e-10);  // the same orbit
  ASSERT_EQ(free.modal_index(1, 0), m);

  const FloquetResult h0 = interface_hill_floquet(elastic, y, omega);
  const FloquetResult h1 = interface_hill_floquet(free, y_free, omega);
  ASSERT_TRUE(h0.ok && h1.ok) << h0.message << h1.message;
  ASSERT_EQ(h1.multipliers.size(), h0.multipliers.size());
  EXPECT_LT(matched(h1.multipliers, h0.multipliers), 1e-12);
  OrbitMonodromyOptions mo;
  mo.samples = 512;
  const FloquetResult m0 = interface_orbit_floquet(elastic, y, omega, mo);
  const FloquetResult m1 = interface_orbit_floquet(free, y_free, omega, mo);
  ASSERT_TRUE(m0.ok && m1.ok) << m0.message << m1.message;
  ASSERT_EQ(m1.multipliers.size(), m0.multipliers.size());
  EXPECT_LT(matched(m1.multipliers, m0.multipliers), 1e-12);
  EXPECT_LT(m1.max_multiplier, 1.0 - 1e-3);  // damped: the neutral rigid-body multiplier is not there
}

TEST(InterfaceHillStability, MatrixFreeBalanceGivesTheSameMultipliers) {
  // The Jacobian assembled column by column from apply_jacobian (a balance without the dense
  // matrix) against the dense one, on the slipping orbit of the one-point Jenkins joint.
  const double omega = 1.05;
  InterfaceBalanceOptions jo;
  jo.harmonics = 5;
  jo.time_samples = 128;
  const TwinOrbit t = twin_orbit(omega, 0.2, false, jo);
  const InterfaceBalance& dense = t.joint;
  const Eigen::VectorXd& y = t.y;
  jo.dense_jacobian = false;
  const InterfaceBalance matrix_free(two_dof_joint(3.0), jo);
  const FloquetResult rd = interface_hill_floquet(dense, y, omega);
  const FloquetResult rm = interface_hill_floquet(matrix_free, y, omega);
  ASSERT_TRUE(rd.ok && rm.ok) << rd.message << rm.message;
  EXPECT_LT(matched(rd.multipliers, rm.multipliers), 1e-12);
  EXPECT_NEAR(rd.max_multiplier, rm.max_multiplier, 1e-12);
}

TEST(InterfaceHillStability, RejectsWrongSizesAndReportsNonFiniteInput) {
  const InterfaceBalance joint(two_dof_joint(3.0), InterfaceBalanceOptions{});
  EXPECT_THROW((void)interface_hill_floquet(joint, Eigen::VectorXd::Zero(3), 1.0), std::invalid_argument);
  HillOptions bad;
  bad.unstable_tolerance = 0.5;
  EXPECT_THROW((void)interface_hill_floquet(joint, Eigen::VectorXd::Zero(joint.unknowns()), 1.0, bad),
               std::invalid_argument);
  const FloquetResult r = interface_hill_floquet(joint, Eigen::VectorXd::Zero(joint.unknowns()),
                                                 std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.message.empty());
}

}  // namespace
}  // namespace jointhb::hb
