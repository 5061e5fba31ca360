// Hill's method (hb/hill_stability.hpp) against closed forms: for a linear system (no contacts, or
// contacts that never slip) the Floquet exponents are the eigenvalues of the first-order system
// and the multipliers e^{λT} exactly, whatever Ω and H; the selection must find them among the
// 2n(2H+1) shifted copies.
#include "jointhb/hb/hill_stability.hpp"

#include <gtest/gtest.h>

#include "linear_floquet_model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <complex>
#include <numbers>
#include <vector>

namespace jointhb::hb {
namespace {

using cd = std::complex<double>;

using testing::two_dof_linear;

// The closed-form multipliers with K + `extra`, by |ρ| descending.
std::vector<cd> closed_form_multipliers(const DiscreteSystem& s, const Eigen::MatrixXd& extra,
                                        double omega) {
  const Eigen::VectorXcd lambda =
      testing::first_order_eigenvalues(s, Eigen::MatrixXd(s.stiffness) + extra);
  std::vector<cd> rho = testing::exact_multipliers(lambda, 2.0 * std::numbers::pi / omega);
  std::sort(rho.begin(), rho.end(), [](cd x, cd y) {
    return std::abs(x) != std::abs(y) ? std::abs(x) > std::abs(y) : x.imag() > y.imag();
  });
  return rho;
}

void expect_multipliers(const FloquetResult& r, const std::vector<cd>& expected, double tol) {
  ASSERT_TRUE(r.ok) << r.message;
  ASSERT_EQ(r.multipliers.size(), static_cast<Eigen::Index>(expected.size()));
  // Every expected multiplier is matched by one computed multiplier (pairs may come in any order).
  std::vector<bool> used(expected.size(), false);
  for (const cd& rho : r.multipliers) {
    double best = 1e300;
    std::size_t at = 0;
    for (std::size_t j = 0; j < expected.size(); ++j) {
      if (!used[j] && std::abs(rho - expected[j]) < best) {
        best = std::abs(rho - expected[j]);
        at = j;
      }
    }
    used[at] = true;
    EXPECT_LT(best, tol) << "ρ = " << rho << " matched " << expected[at];
  }
}

TEST(HillStability, LinearSystemMultipliersAreTheFirstOrderEigenvaluesForAnyOmegaAndH) {
  const DiscreteSystem s = two_dof_linear();
  Excitation e;
  e.forces.push_back({0, 1.0, 1});
  for (const int h : {1, 3, 8}) {
    for (const double omega : {0.3, 1.1, 2.9}) {
      HarmonicBalanceOptions o;
      o.harmonics = h;
      o.time_samples = 4 * h + 4;
      o.selection = HarmonicSelection::all;
      const HarmonicBalance balance(s, e, o);
      const HillStability hill(balance);
      const FloquetResult r = hill.evaluate(balance.stuck_solution(omega), omega);
      expect_multipliers(r, closed_form_multipliers(s, Eigen::MatrixXd::Zero(2, 2), omega), 1e-9);
      EXPECT_TRUE(r.stable());
      EXPECT_LT(r.max_multiplier, 1.0);
      EXPECT_LT(r.kept_centre, r.rejected_centre) << "H = " << h << ", Ω = " << omega;
    }
  }
}

TEST(HillStability, StuckJenkinsContactActsAsItsSpringAndOddBasesAreWidened) {
  DiscreteSystem s = two_dof_linear();
  ContactElement c;
  c.dof_a = 0;
  c.dof_b = 1;
  c.stiffness = 2.0;
  c.friction_coefficient = 0.5;
  c.normal_force = 100.0;  // never slips at this force
  s.contacts.push_back(c);
  Excitation e;
  e.forces.push_back({1, 0.2, 1});
  HarmonicBalanceOptions o;
  o.harmonics = 5;
  o.time_samples = 64;
  o.selection = HarmonicSelection::odd;  // the perturbations still get every harmonic
  const HarmonicBalance balance(s, e, o);
  const HillStability hill(balance);
  const double omega = 1.7;
  const FloquetResult r = hill.evaluate(balance.stuck_solution(omega), omega);
  Eigen::MatrixXd spring(2, 2);
  spring << 2.0, -2.0, -2.0, 2.0;
  expect_multipliers(r, closed_form_multipliers(s, spring, omega), 1e-9);
}

TEST(HillStability, UndampedLinearSystemIsMarginalButNotUnstable) {
  DiscreteSystem s = two_dof_linear();
  s.damping = SparseMatrix(2, 2);
  Excitation e;
  e.forces.push_back({0, 1.0, 1});
  HarmonicBalanceOptions o;
  o.harmonics = 4;
  o.time_samples = 32;
  o.selection = HarmonicSelection::all;
  const HarmonicBalance balance(s, e, o);
  const FloquetResult r = HillStability(balance).evaluate(balance.stuck_solution(0.8), 0.8);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.max_multiplier, 1.0, 1e-9);
  EXPECT_EQ(r.unstable, 0);
}

TEST(HillStability, ClassifiesTheMultiplierThatCrossed) {
  FloquetResult stable, real_out, negative_out, pair_out;
  for (FloquetResult* r : {&stable, &real_out, &negative_out, &pair_out}) r->ok = true;
  stable.multipliers = Eigen::VectorXcd::Constant(2, cd(0.5, 0.1));
  real_out.multipliers.resize(2);
  real_out.multipliers << cd(1.2, 0.0), cd(0.3, 0.0);
  real_out.unstable = 1;
  negative_out.multipliers.resize(2);
  negative_out.multipliers << cd(-1.1, 0.0), cd(0.3, 0.0);
  negative_out.unstable = 1;
  pair_out.multipliers.resize(2);
  pair_out.multipliers << cd(0.8, 0.7), cd(0.8, -0.7);
  pair_out.unstable = 2;
  EXPECT_EQ(classify_bifurcation(stable, real_out, false), Bifurcation::branch_point);
  EXPECT_EQ(classify_bifurcation(real_out, stable, true), Bifurcation::fold);
  EXPECT_EQ(classify_bifurcation(stable, negative_out, false), Bifurcation::period_doubling);
  EXPECT_EQ(classify_bifurcation(pair_out, stable, false), Bifurcation::neimark_sacker);
  EXPECT_EQ(classify_bifurcation(stable, stable, false), Bifurcation::none);
  EXPECT_EQ(classify_bifurcation(stable, stable, true), Bifurcation::reversal);
  FloquetResult unknown;  // not computed: a turn is taken for a fold
  EXPECT_EQ(classify_bifurcation(unknown, stable, true), Bifurcation::fold);
}

TEST(HillStability, RejectsAJacobianOfTheWrongSizeAndAnOddBasis) {
  const DiscreteSystem s = two_dof_linear();
  const FourierBasis full(3, 16, false);
  const FourierBasis odd(3, 16, true);
  EXPECT_THROW(hill_floquet(s, full, Eigen::MatrixXd::Zero(3, 3), 1.0), std::invalid_argument);
  EXPECT_THROW(hill_floquet(s, odd, Eigen::MatrixXd::Zero(2 * odd.size(), 2 * odd.size()), 1.0),
               std::invalid_argument);
  HillOptions bad;
  bad.unstable_tolerance = 0.0;
  EXPECT_NE(bad.validate().find("unstable_tolerance"), std::string::npos);
}

}  // namespace
}  // namespace jointhb::hb
