// The point-local preconditioner of the interface balance (eq. T-34) against the assembled dense
// Jacobian: its inverse is exact where the residual flexibility couples no two points and at the
// stuck limit, an approximation elsewhere, and independent of the thread count.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdio>
#include <random>

#include "interface_test_model.hpp"
#include "jointhb/hb/interface_balance.hpp"
#include "jointhb/hb/interface_local_preconditioner.hpp"

namespace jointhb::hb {
namespace {

using namespace jointhb::hb::testing;

// R0, R1 (and the matching load parts stay) with only the 3 × 3 blocks of each point kept.
InterfaceModel point_diagonal(InterfaceModel m) {
  for (MatrixXd* r : {&m.residual_flexibility, &m.residual_inertia}) {
    MatrixXd d = MatrixXd::Zero(r->rows(), r->cols());
    for (int p = 0; p < m.num_points(); ++p) d.block(3 * p, 3 * p, 3, 3) = r->block(3 * p, 3 * p, 3, 3);
    *r = d;
  }
  return m;
}

// ‖M⁻¹ J v − v‖ / ‖v‖ over a few vectors.
double inverse_error(const InterfaceBalance& hb, const InterfaceBalanceEvaluation& e, double omega, double xi) {
  const InterfaceLocalPreconditioner pc(hb, e, omega, xi);
  EXPECT_EQ(pc.singular_points(), 0);
  std::mt19937 rng(3);
  std::normal_distribution<double> nd(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 3; ++trial) {
    VectorXd v(hb.unknowns());
    for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = nd(rng);
    worst = std::max(worst, (pc.solve(e.jacobian * v) - v).norm() / v.norm());
  }
  return worst;
}

TEST(InterfaceLocalPreconditioner, ExactWhereTheResidualFlexibilityCouplesNoPoints) {
  for (bool gm : {true, false}) {
    const Structure s = make_structure(5, 4, 11, 0.5, gm);
    const InterfaceModel full = make_model(s, 6, gm);
    const InterfaceBalance hb(point_diagonal(full), {.harmonics = 3, .time_samples = 64});
    const double omega = 1.05 * std::sqrt(hb.model().omega2[0]);
    const VectorXd load = hb.cosine_load(20.0);
    InterfaceBalanceEvaluation e;
    hb.evaluate(slipping_state(hb, omega, load, 5), omega, 1.5, load, true, e);
    ASSERT_TRUE(e.ok) << e.message;
    ASSERT_GT(e.slipping_points, 0);
    const double err = inverse_error(hb, e, omega, 1.5);
    std::printf("%s, point-diagonal R: |M⁻¹ J v − v| / |v| = %.2e\n", gm ? "Gaul–Mayer" : "Jenkins", err);
    EXPECT_LT(err, 1e-10);
  }
}

TEST(InterfaceLocalPreconditioner, ExactAtTheStuckLimitAndApproximateInSlip) {
  const Structure s = make_structure(5, 4, 11, 0.5, true);
  const InterfaceBalance hb(make_model(s, 6, true), {.harmonics = 3, .time_samples = 64});
  const double omega = 1.05 * std::sqrt(hb.model().omega2[0]);
  InterfaceBalanceEvaluation e0;
  hb.evaluate(VectorXd::Zero(hb.unknowns()), omega, 1.5, VectorXd(), true, e0);
  const double stuck = inverse_error(hb, e0, omega, 1.5);
  const VectorXd load = hb.cosine_load(20.0);
  InterfaceBalanceEvaluation e;
  hb.evaluate(slipping_state(hb, omega, load, 5), omega, 1.5, load, true, e);
  ASSERT_GT(e.slipping_points, 0);
  const double slipping = inverse_error(hb, e, omega, 1.5);
  // The harmonic block-Jacobi preconditioner on the same slipping state, for comparison.
  const auto harmonic = hb.harmonic_preconditioner(e, omega, 1.5);
  const VectorXd v = VectorXd::LinSpaced(hb.unknowns(), -1.0, 2.0);
  const double harmonic_error = (harmonic->solve(e.jacobian * v) - v).norm() / v.norm();
  std::printf("|M⁻¹ J v − v| / |v|: stuck %.2e, slipping %.2e (harmonic blocks %.2e)\n", stuck, slipping,
              harmonic_error);
  EXPECT_LT(stuck, 1e-12);
  EXPECT_GT(slipping, 1e-8);  // R couples the points: an approximation
  EXPECT_LT(slipping, 1.0);
}

// One group holding every point keeps all of R: J_loc = J, the inverse is exact.
TEST(InterfaceLocalPreconditioner, OneGroupOfAllPointsIsTheExactInverse) {
  const Structure s = make_structure(5, 4, 11, 0.5, true);
  const InterfaceBalance hb(make_model(s, 6, true), {.harmonics = 3, .time_samples = 64});
  const double omega = 1.05 * std::sqrt(hb.model().omega2[0]);
  const VectorXd load = hb.cosine_load(20.0);
  InterfaceBalanceEvaluation e;
  hb.evaluate(slipping_state(hb, omega, load, 5), omega, 1.5, load, true, e);
  ASSERT_GT(e.slipping_points, 0);
  const InterfaceLocalPreconditioner all(hb, e, omega, 1.5, hb.points());
  const InterfaceLocalPreconditioner pairs(hb, e, omega, 1.5, 2);
  EXPECT_EQ(all.groups(), 1);
  EXPECT_EQ(pairs.groups(), 3);  // 5 points: two pairs and one alone
  const VectorXd v = VectorXd::LinSpaced(hb.unknowns(), -1.0, 2.0);
  const double exact = (all.solve(e.jacobian * v) - v).norm() / v.norm();
  const double paired = (pairs.solve(e.jacobian * v) - v).norm() / v.norm();
  std::printf("|M⁻¹ J v − v| / |v|: one group %.2e, pairs %.2e\n", exact, paired);
  EXPECT_LT(exact, 1e-10);
  EXPECT_GT(paired, 1e-8);
}

TEST(InterfaceLocalPreconditioner, IndependentOfThreadCount) {
  const Structure s = make_structure(40, 4, 13, 0.5, true);
  const InterfaceBalance hb(make_model(s, 6, true), {.harmonics = 2, .time_samples = 32, .dense_jacobian = false});
  const double omega = 0.98 * std::sqrt(hb.model().omega2[0]);
  const VectorXd load = hb.cosine_load(30.0);
  const VectorXd y = slipping_state(hb, omega, load, 2);
  const VectorXd v = VectorXd::LinSpaced(hb.unknowns(), -1.0, 2.0);
  const int saved = omp_get_max_threads();
  InterfaceBalanceEvaluation e1, e2;
  omp_set_num_threads(1);
  hb.evaluate(y, omega, 0.0, load, true, e1);
  const VectorXd s1 = InterfaceLocalPreconditioner(hb, e1, omega, 0.0).solve(v);
  omp_set_num_threads(2);
  hb.evaluate(y, omega, 0.0, load, true, e2);
  const VectorXd s2 = InterfaceLocalPreconditioner(hb, e2, omega, 0.0).solve(v);
  omp_set_num_threads(saved);
  EXPECT_EQ(s1, s2);
}

TEST(InterfaceLocalPreconditioner, RejectsAnEvaluationWithoutBlocks) {
  const Structure s = make_structure(2, 4, 1, 0.0, true);
  const InterfaceBalance hb(make_model(s, 4, true), {.harmonics = 1, .time_samples = 16});
  InterfaceBalanceEvaluation e;
  hb.evaluate(VectorXd::Zero(hb.unknowns()), 1.0, 0.0, VectorXd(), false, e);
  EXPECT_THROW(InterfaceLocalPreconditioner(hb, e, 1.0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::hb
