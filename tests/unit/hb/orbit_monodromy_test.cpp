// Floquet multipliers from the monodromy along a harmonic-balance orbit (hb/orbit_monodromy.hpp):
// the linear closed form e^{λT} with the trapezoidal rule's second-order rate, and a slipping
// Jenkins oscillator against the independent shooting reference (timeint/shooting.hpp), where
// Hill's method on the frozen Jacobian is far off.
#include "jointhb/hb/orbit_monodromy.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <complex>
#include <numbers>

#include "jointhb/timeint/shooting.hpp"
#include "linear_floquet_model.hpp"

namespace jointhb::hb {
namespace {

using cd = std::complex<double>;

// The distance of the closed-form multipliers to the computed ones (nearest-neighbour matching).
double largest_modulus_error(const FloquetResult& r, const DiscreteSystem& s, double omega) {
  const Eigen::VectorXcd lambda = testing::first_order_eigenvalues(s, Eigen::MatrixXd(s.stiffness));
  return testing::matched_error(r.multipliers,
                                testing::exact_multipliers(lambda, 2.0 * std::numbers::pi / omega));
}

TEST(OrbitMonodromy, LinearMultipliersConvergeToExpLambdaTAtSecondOrder) {
  const DiscreteSystem s = testing::two_dof_linear();
  Excitation e;
  e.forces.push_back({0, 1.0, 1});
  HarmonicBalanceOptions o;
  o.harmonics = 3;
  o.time_samples = 16;
  const HarmonicBalance b(s, e, o);
  const double omega = 0.9;
  std::vector<double> errors;
  for (const int n : {256, 512, 1024}) {
    OrbitMonodromyOptions mo;
    mo.samples = n;
    const FloquetResult r = orbit_floquet(b, b.stuck_solution(omega), omega, mo);
    ASSERT_TRUE(r.ok) << r.message;
    EXPECT_EQ(r.multipliers.size(), 4);
    errors.push_back(largest_modulus_error(r, s, omega));
  }
  EXPECT_LT(errors.back(), 2e-4);  // 1.3e-4 at N_f = 1024 (Ω = 0.9, T = 7)
  EXPECT_NEAR(std::log2(errors[0] / errors[1]), 2.0, 0.05);
  EXPECT_NEAR(std::log2(errors[1] / errors[2]), 2.0, 0.05);
}

TEST(OrbitMonodromy, SlippingJenkinsAgreesWithShootingWhereHillDoesNot) {
  // m = k = 1, k_T0 = 3, μF_N = 0.1, c = 1e-4, F = 0.1 at Ω = 1.3812 (the contact slips every
  // half period): shooting gives max|ρ| = 0.3093; Hill's frozen Jacobian finds an exponent damped
  // only by c (0.9998).
  DiscreteSystem s;
  s.mass = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  s.stiffness = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  s.damping = Eigen::MatrixXd::Constant(1, 1, 1e-4).sparseView();
  ContactElement c;
  c.stiffness = 3.0;
  c.friction_coefficient = 1.0;
  c.normal_force = 0.1;
  s.contacts.push_back(c);
  Excitation e;
  e.forces.push_back({0, 0.1, 1});
  HarmonicBalanceOptions o;
  o.harmonics = 15;
  o.time_samples = 512;
  const HarmonicBalance b(s, e, o);
  const double omega = 1.3812;
  // The harmonic-balance solution at Ω by Newton from the stuck solution.
  Eigen::VectorXd x = b.stuck_solution(omega);
  for (int it = 0; it < 60; ++it) {
    HarmonicBalanceEvaluation ev;
    b.evaluate(x, omega, true, ev);
    if (ev.residual.lpNorm<Eigen::Infinity>() < 1e-13) break;
    x -= 0.5 * ev.d_coefficients.partialPivLu().solve(ev.residual);  // damped: kinks
  }
  HarmonicBalanceEvaluation check;
  b.evaluate(x, omega, false, check);
  ASSERT_LT(check.residual.lpNorm<Eigen::Infinity>(), 1e-10);

  const FloquetResult orbit = orbit_floquet(b, x, omega);
  ASSERT_TRUE(orbit.ok) << orbit.message;
  timeint::ShootingOptions so;
  so.steps_per_period = 8192;
  timeint::State guess;
  guess.displacement = Eigen::VectorXd::Constant(1, b.time_history(x, 0)[0]);
  guess.velocity = Eigen::VectorXd::Zero(1);
  for (int h = 1; h <= o.harmonics; h += 2) {
    guess.velocity[0] += h * omega * x[b.index(0, b.basis().cosine_index(h)) + 1];
  }
  const timeint::ShootingResult shot =
      timeint::periodic_orbit_by_shooting(s, e, omega, guess, so);
  ASSERT_EQ(shot.termination, Termination::converged) << shot.message;
  EXPECT_NEAR(orbit.max_multiplier, shot.spectral_radius, 3e-3);
  EXPECT_LT(orbit.max_multiplier, 0.5);
  const FloquetResult hill = HillStability(b).evaluate(x, omega);
  EXPECT_GT(hill.max_multiplier, 0.99);  // the frozen memory: documented, not a defect here
}

TEST(OrbitMonodromy, RejectsTooFewSamples) {
  OrbitMonodromyOptions o;
  o.samples = 8;
  EXPECT_NE(o.validate().find("samples"), std::string::npos);
}

}  // namespace
}  // namespace jointhb::hb
