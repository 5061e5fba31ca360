// Shooting on the Newmark period map (shooting.hpp, docs/time-integration.md §9): the monodromy
// of linear systems against the exact multipliers e^{λT} (Δt² rate) and the trapezoidal rule's own
// ((1 + λΔt/2)/(1 − λΔt/2))^N, the elimination of stuck contacts (no neutral multiplier, also on an
// orbit touching the slip limit), Jenkins oscillators against the cycled steady state and their
// own decay, the 1/N convergence of their multipliers, statuses and validation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "jointhb/timeint/newmark.hpp"
#include "jointhb/timeint/shooting.hpp"
#include "../hb/linear_floquet_model.hpp"

namespace hb = jointhb::hb;
namespace ti = jointhb::timeint;
using std::numbers::pi;

namespace {
// (in the anonymous namespace, like the same alias of the other test sources of its unity batch)
using Complex = std::complex<double>;

// Two DOFs (M = diag(1, 0.5), K = 4π²[3 −1; −1 1]), modal damping 3 % and 4 %, a static force on
// DOF 1 and f cos Ωt on DOF 0.
hb::DiscreteSystem two_dof() {
  Eigen::MatrixXd m(2, 2), k(2, 2);
  m << 1.0, 0.0, 0.0, 0.5;
  k << 3.0, -1.0, -1.0, 1.0;
  k *= 4.0 * pi * pi;
  hb::DiscreteSystem s;
  s.mass = m.sparseView();
  s.stiffness = k.sparseView();
  s.damping = hb::modal_damping_matrix(s.mass, s.stiffness, {0.03, 0.04});
  return s;
}

// two_dof() with a Jenkins link between the DOFs that never slips (μF_N = 1e6, k_T0 = 50) and a
// reference state (force 0.3, slip 0.01).
hb::DiscreteSystem two_dof_with_stuck_link() {
  auto sys = two_dof();
  hb::ContactElement link;
  link.law = "jenkins";
  link.dof_a = 0;
  link.dof_b = 1;
  link.friction_coefficient = 1.0;
  link.normal_force = 1e6;
  link.stiffness = 50.0;
  link.reference_force = 0.3;
  link.reference_slip = 0.01;
  sys.contacts.push_back(link);
  return sys;
}

hb::Excitation two_dof_forcing() {
  hb::Excitation e;
  e.static_force = Eigen::Vector2d(0.0, 5.0);
  e.forces = {{0, 1.0, 1}};
  return e;
}

using jointhb::hb::testing::exact_multipliers;
using jointhb::hb::testing::first_order_eigenvalues;
using jointhb::hb::testing::matched_error;

// The trapezoidal rule's multipliers: its one-step map has eigenvalues (1 + λΔt/2)/(1 − λΔt/2).
std::vector<Complex> trapezoidal_multipliers(const Eigen::VectorXcd& lambda, double dt, int steps) {
  std::vector<Complex> r;
  for (const Complex& l : lambda)
    r.push_back(std::pow((1.0 + 0.5 * l * dt) / (1.0 - 0.5 * l * dt), steps));
  return r;
}

void print_multipliers(const char* label, const Eigen::VectorXcd& rho) {
  std::printf("  %s:", label);
  for (const Complex& r : rho) std::printf(" %.9f%+.9fi (|%.9f|)", r.real(), r.imag(), std::abs(r));
  std::printf("\n");
}

// 1 DOF Jenkins oscillator: m = 1, k = 1, c = 0.02, k_T0 = 10, μF_N = 0.1, 0.05 cos Ωt.
hb::DiscreteSystem jenkins_oscillator() {
  hb::DiscreteSystem s;
  s.mass = Eigen::MatrixXd::Ones(1, 1).sparseView();
  s.stiffness = Eigen::MatrixXd::Ones(1, 1).sparseView();
  s.damping = Eigen::MatrixXd::Constant(1, 1, 0.02).sparseView();
  hb::ContactElement c;
  c.law = "jenkins";
  c.friction_coefficient = 0.1;
  c.normal_force = 1.0;
  c.stiffness = 10.0;
  s.contacts.push_back(c);
  return s;
}

ti::ShootingOptions shooting_options(int steps) {
  ti::ShootingOptions o;
  o.steps_per_period = steps;
  return o;
}

}  // namespace

TEST(ShootingLinear, TwoDofMultipliersAreExpLambdaTWithSecondOrderRate) {
  const auto sys = two_dof();
  const auto ex = two_dof_forcing();
  const double omega = 2 * pi * 0.9;
  const double period = 2 * pi / omega;
  const Eigen::VectorXcd lambda = first_order_eigenvalues(sys, Eigen::MatrixXd(sys.stiffness));
  const auto exact = exact_multipliers(lambda, period);
  const Eigen::Vector2d x_static = Eigen::MatrixXd(sys.stiffness).ldlt().solve(ex.static_force);
  double previous = 0.0;
  for (int steps : {128, 256, 512}) {
    const auto r = ti::periodic_orbit_by_shooting(
        sys, ex, omega, ti::stuck_linear_state(sys, ex, omega).value(), shooting_options(steps));
    ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
    ASSERT_EQ(r.monodromy.rows(), 4);
    ASSERT_EQ(r.multipliers.size(), 4);
    EXPECT_TRUE(r.stuck_contacts.empty());
    EXPECT_LE(r.residual, 1e-10);
    const double dt = r.time_step;
    // The scheme's own multipliers, to the accuracy of the differences.
    const double discrete =
        matched_error(r.multipliers, trapezoidal_multipliers(lambda, dt, steps));
    EXPECT_LT(discrete, 1e-7) << "N = " << steps;
    // The orbit: the receptance at the warped frequency Ω_d = (2/Δt) tan(ΩΔt/2) (TI-8), with
    // x(0) = x_s + Re X and ẋ(0) = Re(iΩ_d X).
    const double wd = 2.0 / dt * std::tan(0.5 * omega * dt);
    const Eigen::MatrixXd m(sys.mass), c(sys.damping), k(sys.stiffness);
    const Eigen::MatrixXcd z =
        (k - wd * wd * m).cast<Complex>() + Complex(0.0, wd) * c.cast<Complex>();
    const Eigen::VectorXcd x1 = z.partialPivLu().solve(Eigen::Vector2cd(1.0, 0.0));
    const double x_scale = x1.cwiseAbs().maxCoeff();
    EXPECT_LT((r.orbit_start.displacement - x_static - x1.real()).cwiseAbs().maxCoeff(),
              1e-9 * x_scale);
    EXPECT_LT((r.orbit_start.velocity - (Complex(0.0, wd) * x1).real()).cwiseAbs().maxCoeff(),
              1e-9 * wd * x_scale);
    const double error = matched_error(r.multipliers, exact);
    if (previous > 0.0) {
      const double rate = std::log2(previous / error);
      std::printf(
          "  N = %4d: |rho - exp(lambda T)| = %.3e (rate %.3f), vs trapezoidal %.1e, "
          "%d Newton its, %ld period maps, %.3f s\n",
          steps, error, rate, discrete, r.newton_iterations, r.period_maps, r.seconds);
      EXPECT_NEAR(rate, 2.0, 0.05);
    } else {
      std::printf(
          "  N = %4d: |rho - exp(lambda T)| = %.3e, vs trapezoidal %.1e, %d Newton its, "
          "%ld period maps, %.3f s\n",
          steps, error, discrete, r.newton_iterations, r.period_maps, r.seconds);
      print_multipliers("rho", r.multipliers);
    }
    previous = error;
  }
}

TEST(ShootingLinear, StuckContactIsEliminatedWithoutNeutralMultiplier) {
  // A Jenkins contact between the two DOFs that can never slip (μF_N = 1e6) and has a reference
  // state (force, slip): the monodromy is 4 × 4 (no neutral multiplier 1 of the slider), its
  // multipliers are those of K + k_T0 b bᵀ, and the orbit keeps the guess's slider F − k_T0 g.
  const auto sys = two_dof_with_stuck_link();
  const hb::ContactElement& c = sys.contacts[0];
  const auto ex = two_dof_forcing();
  const double omega = 2 * pi * 0.9;
  const int steps = 256;
  const Eigen::VectorXcd lambda =
      first_order_eigenvalues(sys, Eigen::MatrixXd(hb::stuck_stiffness(sys)));
  const auto start = ti::stuck_linear_state(sys, ex, omega).value();
  // A guess off the orbit (the continuous one, shifted), with the reference slider.
  ti::State guess = start;
  guess.displacement *= 1.1;
  guess.contact_forces[0] =
      c.reference_force + c.stiffness * (c.gap(guess.displacement) - c.reference_slip);
  const auto r = ti::periodic_orbit_by_shooting(sys, ex, omega, guess, shooting_options(steps));
  ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
  EXPECT_EQ(r.stuck_contacts, std::vector<int>{0});
  ASSERT_EQ(r.monodromy.rows(), 4);
  EXPECT_EQ(r.components, (std::vector<std::string>{"x[0]", "x[1]", "v[0]", "v[1]"}));
  const double discrete =
      matched_error(r.multipliers, trapezoidal_multipliers(lambda, r.time_step, steps));
  std::printf("  %s\n  vs trapezoidal multipliers of the stuck system: %.2e; max|rho| = %.6f\n",
              r.message.c_str(), discrete, r.spectral_radius);
  EXPECT_LT(discrete, 1e-7);
  EXPECT_LT(r.spectral_radius, 1.0);
  const double slider =
      r.orbit_start.contact_forces[0] - c.stiffness * c.gap(r.orbit_start.displacement);
  EXPECT_NEAR(slider, c.reference_force - c.stiffness * c.reference_slip, 1e-12 * c.stiffness);
}

TEST(ShootingJenkins, OneDofMicroslipOrbitMatchesSteadyStateAndIsStable) {
  const auto sys = jenkins_oscillator();
  hb::Excitation ex;
  ex.forces = {{0, 0.05, 1}};
  const double omega = 2.5;
  const int steps = 2048;

  const auto t0 = std::chrono::steady_clock::now();
  const auto r = ti::periodic_orbit_by_shooting(
      sys, ex, omega, ti::stuck_linear_state(sys, ex, omega).value(), shooting_options(steps));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
  std::printf("  %s\n  %d Newton its, %ld period maps, %.3f s\n", r.message.c_str(),
              r.newton_iterations, r.period_maps, seconds);
  print_multipliers("rho", r.multipliers);
  EXPECT_TRUE(r.stuck_contacts.empty());
  ASSERT_EQ(r.multipliers.size(), 3);
  EXPECT_LT(r.spectral_radius, 1.0);

  // The cycled steady state with the same scheme, from its own start.
  ti::SteadyStateOptions so;
  so.steps_per_period = steps;
  so.tolerance = 1e-12;
  so.max_periods = 20000;
  so.integrator = shooting_options(steps).integrator;
  const auto s = ti::forced_steady_state(sys, ex, omega, so);
  ASSERT_EQ(s.termination, jointhb::Termination::converged) << s.message;
  const double x_max = s.samples.cwiseAbs().maxCoeff();
  const double f_max = s.contact_force_samples.cwiseAbs().maxCoeff();
  const double dx = std::abs(s.final_state.displacement[0] - r.orbit_start.displacement[0]) / x_max;
  const double dv =
      std::abs(s.final_state.velocity[0] - r.orbit_start.velocity[0]) / (omega * x_max);
  const double df =
      std::abs(s.final_state.contact_forces[0] - r.orbit_start.contact_forces[0]) / f_max;
  std::printf("  vs forced_steady_state (%d periods, %.3f s): dx %.2e, dv %.2e, dF %.2e\n",
              s.periods, s.seconds, dx, dv, df);
  EXPECT_LT(dx, 1e-8);
  EXPECT_LT(dv, 1e-8);
  EXPECT_LT(df, 1e-8);

  // The monodromy predicts the dynamics: a perturbation of the orbit along the dominant
  // eigenvector, cycled by the integrator for 10 periods, decays by ρ_1 per period.
  Eigen::EigenSolver<Eigen::MatrixXd> eig(r.monodromy);
  Eigen::Index dominant = 0;
  eig.eigenvalues().cwiseAbs().maxCoeff(&dominant);
  const Eigen::Vector3d v1 = eig.eigenvectors().col(dominant).real();
  const Eigen::Vector3d weight(1.0 / x_max, 1.0 / (omega * x_max), 1.0 / 0.1);
  const auto pack = [](const ti::State& x) {
    return Eigen::Vector3d(x.displacement[0], x.velocity[0], x.contact_forces[0]);
  };
  const Eigen::Vector3d orbit = pack(r.orbit_start);
  const Eigen::Vector3d delta = 1e-6 * v1 / v1.cwiseProduct(weight).norm();
  ti::State p = r.orbit_start;
  p.displacement[0] += delta[0];
  p.velocity[0] += delta[1];
  p.contact_forces[0] = std::clamp(p.contact_forces[0] + delta[2], -0.1, 0.1);
  ti::NewmarkOptions scheme = so.integrator;
  scheme.time_step = r.time_step;
  const int periods = 10;
  for (int k = 0; k < periods; ++k) {
    p.time = 0.0;
    p.acceleration.resize(0);
    const auto t = ti::integrate(sys, ex, omega, p, steps, scheme);
    ASSERT_EQ(t.termination, jointhb::Termination::reached_end) << t.message;
    p = t.final_state;
  }
  const double decay =
      std::pow((pack(p) - orbit).cwiseProduct(weight).norm() / delta.cwiseProduct(weight).norm(),
               1.0 / periods);
  std::printf("  perturbation along the dominant eigenvector: decay per period %.9f (rho_1 %.9f)\n",
              decay, std::abs(eig.eigenvalues()[dominant]));
  EXPECT_NEAR(decay, r.spectral_radius, 1e-4);
}

TEST(ShootingJenkins, MultipliersConvergeAsStepsDouble) {
  // Stick/slip switches between samples make the Jenkins multipliers converge like 1/N with a
  // coefficient that changes sign with where the switches fall in their steps: the changes per
  // doubling stay below 6/N and fall by more than 8 over four doublings.
  const auto sys = jenkins_oscillator();
  hb::Excitation ex;
  ex.forces = {{0, 0.05, 1}};
  const double omega = 2.5;
  std::vector<Eigen::VectorXcd> rho;
  std::vector<int> steps_list = {1024, 2048, 4096, 8192, 16384};
  ti::State guess = ti::stuck_linear_state(sys, ex, omega).value();
  for (int steps : steps_list) {
    const auto r = ti::periodic_orbit_by_shooting(sys, ex, omega, guess, shooting_options(steps));
    ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
    ASSERT_EQ(r.multipliers.size(), 3);
    rho.push_back(r.multipliers);
    guess = r.orbit_start;
    std::printf("  N = %5d: rho = %.9f, %.9f, %.1e; %d Newton its, %.3f s\n", steps,
                r.multipliers[0].real(), r.multipliers[1].real(), std::abs(r.multipliers[2]),
                r.newton_iterations, r.seconds);
  }
  std::vector<double> change;
  for (std::size_t i = 1; i < rho.size(); ++i) {
    change.push_back((rho[i] - rho[i - 1]).cwiseAbs().maxCoeff());
    std::printf("  N = %5d -> %5d: max change %.3e (%.2f/N)\n", steps_list[i - 1], steps_list[i],
                change.back(), change.back() * steps_list[i - 1]);
    EXPECT_LT(change.back(), 6.0 / steps_list[i - 1]);
  }
  EXPECT_LT(change.back(), change.front() / 8.0);
}

TEST(ShootingJenkins, StuckContactBesideASlippingOneIsEliminated) {
  // Two DOFs: a Jenkins contact to ground at DOF 0 that slips, and one between the DOFs (with a
  // reference state) that cannot: the second is eliminated (TI-25), the monodromy is 5 × 5
  // (x, ẋ, F_0), the orbit is the cycled steady state's, whose slider is the same.
  auto sys = two_dof_with_stuck_link();
  hb::ContactElement ground;
  ground.law = "jenkins";
  ground.dof_a = 0;
  ground.friction_coefficient = 0.5;
  ground.normal_force = 1.0;
  ground.stiffness = 20.0 * 4.0 * pi * pi;
  sys.contacts.insert(sys.contacts.begin(), ground);
  const auto ex = two_dof_forcing();
  const double omega = 2 * pi * 0.9;
  const int steps = 1024;
  const auto r = ti::periodic_orbit_by_shooting(
      sys, ex, omega, ti::stuck_linear_state(sys, ex, omega).value(), shooting_options(steps));
  ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
  std::printf("  %s (%ld period maps, %.3f s)\n", r.message.c_str(), r.period_maps, r.seconds);
  print_multipliers("rho", r.multipliers);
  EXPECT_EQ(r.stuck_contacts, std::vector<int>{1});
  EXPECT_EQ(r.components, (std::vector<std::string>{"x[0]", "x[1]", "v[0]", "v[1]", "F[0]"}));
  EXPECT_LT(r.spectral_radius, 1.0);
  EXPECT_LT(std::abs(r.multipliers[4]), 1e-6);  // the slipping Jenkins force's memory

  ti::SteadyStateOptions so;
  so.steps_per_period = steps;
  so.tolerance = 1e-12;
  so.max_periods = 5000;
  so.integrator = shooting_options(steps).integrator;
  const auto s = ti::forced_steady_state(sys, ex, omega, so);
  ASSERT_EQ(s.termination, jointhb::Termination::converged) << s.message;
  const double x_max = s.samples.cwiseAbs().maxCoeff();
  const double dx = (s.final_state.displacement - r.orbit_start.displacement).cwiseAbs().maxCoeff();
  const double dv = (s.final_state.velocity - r.orbit_start.velocity).cwiseAbs().maxCoeff();
  double df = 0.0;
  for (int c = 0; c < 2; ++c) {
    df = std::max(df, std::abs(s.final_state.contact_forces[c] - r.orbit_start.contact_forces[c]));
  }
  const double f_max = s.contact_force_samples.cwiseAbs().maxCoeff();
  std::printf(
      "  vs forced_steady_state (%d periods): dx %.2e, dv %.2e, dF %.2e (relative); "
      "contact 0 dissipates %.3e J per period\n",
      s.periods, dx / x_max, dv / (omega * x_max), df / f_max, s.contact_dissipation[0]);
  EXPECT_GT(s.contact_dissipation[0], 0.0);
  EXPECT_EQ(s.contact_dissipation[1], 0.0);
  EXPECT_LT(dx / x_max, 1e-8);
  EXPECT_LT(dv / (omega * x_max), 1e-8);
  EXPECT_LT(df / f_max, 1e-8);
}

TEST(ShootingJenkins, OrbitTouchingTheSlipLimitKeepsTheLinearBranch) {
  // The stuck orbit of the linked two-DOF system, then the link's slip limit lowered to the
  // orbit's max|F| (1 + 1e-10): the same orbit now touches the limit (as after a shakedown), and a
  // perturbation of one sign would slip. The monodromy is still the stuck system's: the perturbed
  // periods keep the stuck contact on its linear branch (TI-25).
  auto sys = two_dof_with_stuck_link();
  const auto ex = two_dof_forcing();
  const double omega = 2 * pi * 0.9;
  const int steps = 256;
  const auto stuck = ti::periodic_orbit_by_shooting(
      sys, ex, omega, ti::stuck_linear_state(sys, ex, omega).value(), shooting_options(steps));
  ASSERT_EQ(stuck.termination, jointhb::Termination::converged) << stuck.message;
  double f_max = std::abs(stuck.orbit_start.contact_forces[0]);
  ti::NewmarkOptions scheme = shooting_options(steps).integrator;
  scheme.time_step = stuck.time_step;
  ti::State start = stuck.orbit_start;
  start.acceleration.resize(0);
  (void)ti::integrate(sys, ex, omega, start, steps, scheme, [&](const ti::State& s) {
    f_max = std::max(f_max, std::abs(s.contact_forces[0]));
  });
  sys.contacts[0].normal_force = f_max * (1.0 + 1e-10);

  const auto r =
      ti::periodic_orbit_by_shooting(sys, ex, omega, stuck.orbit_start, shooting_options(steps));
  ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
  ASSERT_EQ(r.stuck_contacts, std::vector<int>{0});
  ASSERT_EQ(r.stuck_margins.size(), 1U);
  const Eigen::VectorXcd lambda =
      first_order_eigenvalues(sys, Eigen::MatrixXd(hb::stuck_stiffness(sys)));
  const double discrete =
      matched_error(r.multipliers, trapezoidal_multipliers(lambda, r.time_step, steps));
  std::printf(
      "  %s\n  margin to the slip limit %.2e, vs trapezoidal multipliers of the stuck "
      "system %.2e\n",
      r.message.c_str(), r.stuck_margins[0], discrete);
  EXPECT_LE(r.stuck_margins[0], 1e-9);
  EXPECT_GE(r.stuck_margins[0], 0.0);
  EXPECT_LT(discrete, 1e-7);
  EXPECT_LT((r.orbit_start.displacement - stuck.orbit_start.displacement).cwiseAbs().maxCoeff(),
            1e-12);
}

TEST(ShootingJenkins, BudgetExhaustedIsNoConvergenceWithTheMonodromyOfTheGuess) {
  const auto sys = jenkins_oscillator();
  hb::Excitation ex;
  ex.forces = {{0, 0.05, 1}};
  auto o = shooting_options(256);
  o.max_newton_iterations = 0;
  const auto r =
      ti::periodic_orbit_by_shooting(sys, ex, 2.5, ti::stuck_linear_state(sys, ex, 2.5).value(), o);
  EXPECT_EQ(r.termination, jointhb::Termination::no_convergence) << r.message;
  EXPECT_FALSE(r.status().ok());
  EXPECT_GT(r.residual, 1e-3);
  EXPECT_EQ(r.newton_iterations, 0);
  EXPECT_EQ(r.monodromy.rows(), 3);
  EXPECT_EQ(r.multipliers.size(), 3);
  EXPECT_EQ(r.components, (std::vector<std::string>{"x[0]", "v[0]", "F[0]"}));
}

TEST(ShootingOptions, InvalidOptionsNameTheField) {
  const auto sys = jenkins_oscillator();
  hb::Excitation ex;
  ex.forces = {{0, 0.05, 1}};
  const ti::State guess = ti::rest_state(sys);
  const auto expect_field = [&](const ti::ShootingOptions& o, const std::string& field) {
    try {
      (void)ti::periodic_orbit_by_shooting(sys, ex, 2.5, guess, o);
      ADD_FAILURE() << "no exception for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  ti::ShootingOptions o;
  o.steps_per_period = 3;
  expect_field(o, "steps_per_period");
  o = {};
  o.max_newton_iterations = -1;
  expect_field(o, "max_newton_iterations");
  o = {};
  o.tolerance = 0.0;
  expect_field(o, "tolerance");
  o = {};
  o.perturbation = -1e-7;
  expect_field(o, "perturbation");
  o = {};
  o.perturbation = std::nan("");
  expect_field(o, "perturbation");
  o = {};
  o.max_cycled_periods = -1;
  expect_field(o, "max_cycled_periods");
  o = {};
  o.integrator.alpha = 0.5;
  expect_field(o, "integrator.alpha");
  EXPECT_THROW((void)ti::periodic_orbit_by_shooting(sys, ex, 0.0, guess, {}),
               std::invalid_argument);
  ti::State wrong = guess;
  wrong.displacement = Eigen::VectorXd::Zero(2);
  EXPECT_THROW((void)ti::periodic_orbit_by_shooting(sys, ex, 2.5, wrong, {}),
               std::invalid_argument);
}
