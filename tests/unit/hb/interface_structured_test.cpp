// The matrix-free Jacobian-vector product of the interface balance
// (InterfaceBalance::apply_jacobian: per-point blocks B_p and per-harmonic R_k, never the U × U
// matrix) against the assembled dense Jacobian times the same vectors, and its independence of
// the OpenMP thread count.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "interface_test_model.hpp"
#include "jointhb/hb/interface_balance.hpp"

namespace jointhb::hb {
namespace {

using namespace jointhb::hb::testing;

TEST(InterfaceBalanceProduct, MatchesDenseJacobianTimesVector) {
  for (bool gm : {true, false}) {
    const Structure s = make_structure(5, 4, 11, 0.5, gm);
    const InterfaceModel model = make_model(s, 6, gm);  // 6 kept modes: R0 and R1 are not zero
    ASSERT_GT(model.residual_inertia.norm(), 0.0);
    const InterfaceBalance hb(model, {.harmonics = 3, .time_samples = 64});
    const double omega = 1.05 * std::sqrt(hb.model().omega2[0]);
    const VectorXd load = hb.cosine_load(20.0);
    const VectorXd y = slipping_state(hb, omega, load, 5);
    InterfaceBalanceEvaluation e;
    const double xi = 2.0;
    hb.evaluate(y, omega, xi, load, true, e);
    ASSERT_TRUE(e.ok) << e.message;
    EXPECT_GT(e.slipping_points, 0);
    ASSERT_EQ(e.point_blocks.size(), static_cast<std::size_t>(s.P));
    std::mt19937 rng(8);
    std::normal_distribution<double> nd(0.0, 1.0);
    double worst = 0.0;
    for (int trial = 0; trial < 4; ++trial) {
      VectorXd v(hb.unknowns());
      for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = nd(rng);
      if (trial == 1) v.head(hb.modes() * hb.basis().size()).setZero();  // gaps only
      if (trial == 2) v.tail(v.size() - hb.modes() * hb.basis().size()).setZero();  // modes only
      const VectorXd dense = e.jacobian * v;
      const VectorXd product = hb.apply_jacobian(e, omega, xi, v);
      // round-off bound: ε · Σ_j |J_ij| |v_j| per row, with a factor for the summation order
      const VectorXd bound = e.jacobian.cwiseAbs() * v.cwiseAbs();
      const double err = ((dense - product).cwiseAbs().array() / bound.array().max(1e-300)).maxCoeff();
      worst = std::max(worst, err);
    }
    std::printf("%s: |J v − apply_jacobian(v)| / (|J| |v|) worst %.2e (%d of %d points slip)\n",
                gm ? "Gaul-Mayer" : "Jenkins", worst, e.slipping_points, s.P);
    EXPECT_LT(worst, 1e-13);

    // Without the dense matrix: the same residual and blocks, no matrix, the same products.
    InterfaceBalanceOptions o = hb.options();
    o.dense_jacobian = false;
    const InterfaceBalance free(model, o);
    InterfaceBalanceEvaluation f;
    free.evaluate(y, omega, xi, load, true, f);
    EXPECT_EQ(f.jacobian.size(), 0);
    EXPECT_EQ(f.residual, e.residual);
    EXPECT_EQ(f.d_omega, e.d_omega);
    const VectorXd v = VectorXd::LinSpaced(hb.unknowns(), -1.0, 2.0);
    EXPECT_EQ(free.apply_jacobian(f, omega, xi, v), hb.apply_jacobian(e, omega, xi, v));
  }
}

TEST(InterfaceBalanceProduct, IndependentOfThreadCount) {
  const Structure s = make_structure(6, 4, 13, 0.5, true);
  const InterfaceBalance hb(make_model(s, 6, true), {.harmonics = 2, .time_samples = 32});
  const double omega = 0.98 * std::sqrt(hb.model().omega2[0]);
  const VectorXd load = hb.cosine_load(30.0);
  const VectorXd y = slipping_state(hb, omega, load, 2);
  const VectorXd v = VectorXd::LinSpaced(hb.unknowns(), -1.0, 2.0);
  const int saved = omp_get_max_threads();
  InterfaceBalanceEvaluation e1, e2;
  omp_set_num_threads(1);
  hb.evaluate(y, omega, 0.0, load, true, e1);
  const VectorXd p1 = hb.apply_jacobian(e1, omega, 0.0, v);
  const VectorXd s1 = hb.harmonic_preconditioner(e1, omega, 0.0)->solve(v);
  omp_set_num_threads(2);
  hb.evaluate(y, omega, 0.0, load, true, e2);
  const VectorXd p2 = hb.apply_jacobian(e2, omega, 0.0, v);
  const VectorXd s2 = hb.harmonic_preconditioner(e2, omega, 0.0)->solve(v);
  omp_set_num_threads(saved);
  EXPECT_EQ(e1.jacobian, e2.jacobian);
  EXPECT_EQ(p1, p2);
  EXPECT_EQ(s1, s2);
}

// The harmonic block-Jacobi preconditioner (eq. T-32c): each block is the dense Jacobian restricted
// to the rows and columns of one harmonic, and it is exact where no point couples harmonics (the
// stuck state at zero amplitude).
TEST(InterfaceHarmonicPreconditioner, BlocksAreTheJacobianRestrictedToOneHarmonic) {
  const Structure s = make_structure(5, 4, 11, 0.5, true);
  const InterfaceModel model = make_model(s, 6, true);
  const InterfaceBalance hb(model, {.harmonics = 3, .time_samples = 64});
  const double omega = 1.05 * std::sqrt(hb.model().omega2[0]);
  const VectorXd load = hb.cosine_load(20.0);
  const VectorXd y = slipping_state(hb, omega, load, 5);
  InterfaceBalanceEvaluation e;
  hb.evaluate(y, omega, 1.5, load, true, e);
  ASSERT_GT(e.slipping_points, 0);
  const auto pc = hb.harmonic_preconditioner(e, omega, 1.5);
  EXPECT_GT(pc->rcond(), 0.0);
  double worst = 0.0;
  for (int k = 0; k <= 3; ++k) {
    const MatrixXd& b = pc->block(k);
    for (Eigen::Index r = 0; r < b.rows(); ++r)
      for (Eigen::Index c = 0; c < b.cols(); ++c)
        worst = std::max(worst, std::abs(b(r, c) - e.jacobian(pc->global_index(k, r), pc->global_index(k, c))));
  }
  std::printf("harmonic blocks vs restricted dense Jacobian: %.2e (|J| %.2e)\n", worst, e.jacobian.cwiseAbs().maxCoeff());
  EXPECT_LT(worst, 1e-13 * e.jacobian.cwiseAbs().maxCoeff());
  // Every unknown belongs to exactly one block.
  std::vector<int> seen(static_cast<std::size_t>(hb.unknowns()), 0);
  for (int k = 0; k <= 3; ++k)
    for (Eigen::Index r = 0; r < pc->block(k).rows(); ++r) ++seen[static_cast<std::size_t>(pc->global_index(k, r))];
  EXPECT_EQ(*std::min_element(seen.begin(), seen.end()), 1);
  EXPECT_EQ(*std::max_element(seen.begin(), seen.end()), 1);
  // Slipping points couple harmonics: J̃⁻¹ J is not the identity there...
  const VectorXd v = VectorXd::LinSpaced(hb.unknowns(), -1.0, 2.0);
  const double slipping_error = (pc->solve(e.jacobian * v) - v).norm() / v.norm();
  // ...but at zero amplitude every point is stuck, B_p = 0 and J̃ = J.
  InterfaceBalanceEvaluation e0;
  hb.evaluate(VectorXd::Zero(hb.unknowns()), omega, 1.5, VectorXd(), true, e0);
  const auto pc0 = hb.harmonic_preconditioner(e0, omega, 1.5);
  const double stuck_error = (pc0->solve(e0.jacobian * v) - v).norm() / v.norm();
  std::printf("|J̃⁻¹ J v − v| / |v|: slipping %.2e, stuck %.2e\n", slipping_error, stuck_error);
  EXPECT_LT(stuck_error, 1e-12);
  EXPECT_GT(slipping_error, 1e-6);
}

TEST(InterfaceBalanceProduct, RejectsAnEvaluationWithoutBlocks) {
  const Structure s = make_structure(2, 4, 1, 0.0, true);
  const InterfaceBalance hb(make_model(s, 4, true), {.harmonics = 1, .time_samples = 16});
  InterfaceBalanceEvaluation e;
  hb.evaluate(VectorXd::Zero(hb.unknowns()), 1.0, 0.0, VectorXd(), false, e);
  EXPECT_THROW((void)hb.apply_jacobian(e, 1.0, 0.0, VectorXd::Zero(hb.unknowns())), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::hb
