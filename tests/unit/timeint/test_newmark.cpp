// Newmark / HHT-α time integration (newmark.hpp): linear steady states against the receptance
// (exact at the trapezoidal rule's warped frequency, Δt² against the true one), energy balances,
// stuck and sliding contacts against the contact layer, the Newton safeguard, and validation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <numbers>

#include "jointhb/contact/closed_forms.hpp"
#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/periodic_state.hpp"
#include "jointhb/timeint/newmark.hpp"
#include "jointhb/timeint/ring_down.hpp"
#include "unit/timeint/linear_systems.hpp"

namespace hb = jointhb::hb;
namespace ti = jointhb::timeint;
namespace jc = jointhb::contact;
using std::numbers::pi;

namespace {
// (in the anonymous namespace, like the same alias of the other test sources of its unity batch)
using Complex = std::complex<double>;

using jointhb::test_systems::linear_system;
using jointhb::test_systems::one_dof;

hb::Excitation cosine_force(int dof, double amplitude, int harmonic = 1) {
  hb::Excitation e;
  e.forces.push_back({dof, amplitude, harmonic});
  return e;
}

// Complex amplitude X of x(t) = Re[X e^{ihΩt}] under f_h cos(hΩt) at the circular frequency w.
Eigen::VectorXcd receptance(const hb::DiscreteSystem& s, const Eigen::VectorXd& f, double w,
                            const hb::SparseMatrix& stiffness) {
  const Eigen::MatrixXd m(s.mass), k(stiffness);
  Eigen::MatrixXcd z = (k - w * w * m).cast<Complex>();
  if (s.damping.nonZeros() > 0) z += Complex(0.0, w) * Eigen::MatrixXd(s.damping).cast<Complex>();
  return z.partialPivLu().solve(f.cast<Complex>());
}

// The trapezoidal rule's steady state under e^{iwt} is the exact one at (2/Δt) tan(wΔt/2).
double warped(double w, double dt) { return 2.0 / dt * std::tan(0.5 * w * dt); }

// Largest |coefficient error| of harmonic h over all DOFs, relative to the largest |X|.
double harmonic_error(const ti::SteadyStateResult& r, int h, const Eigen::VectorXcd& x) {
  double e = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    e = std::max(e, std::abs(r.coefficients(i, 2 * h - 1) - x[i].real()));
    e = std::max(e, std::abs(r.coefficients(i, 2 * h) + x[i].imag()));
  }
  return e / x.cwiseAbs().maxCoeff();
}

ti::SteadyStateOptions steady_options(int steps) {
  ti::SteadyStateOptions o;
  o.steps_per_period = steps;
  o.harmonics = 3;
  o.tolerance = 1e-11;
  o.integrator.newton_tolerance = 1e-12;
  return o;
}

double kinetic_plus_potential(const hb::DiscreteSystem& s, const ti::State& x) {
  return 0.5 * x.velocity.dot(s.mass * x.velocity) +
         0.5 * x.displacement.dot(s.stiffness * x.displacement);
}

}  // namespace

TEST(NewmarkLinear, OneDofMatchesReceptanceWithSecondOrderRate) {
  const auto sys = one_dof(0.05);
  const double omega = 0.8 * 2 * pi;
  const auto ex = cosine_force(0, 2.0);
  const Eigen::VectorXd f = Eigen::VectorXd::Constant(1, 2.0);
  const Eigen::VectorXcd exact = receptance(sys, f, omega, sys.stiffness);
  double previous = 0.0;
  for (int steps : {32, 64, 128}) {
    const auto r = ti::forced_steady_state(sys, ex, omega, steady_options(steps));
    ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
    // The discrete steady state is the receptance at the warped frequency, to round-off.
    const double dt = r.time_step;
    EXPECT_LT(harmonic_error(r, 1, receptance(sys, f, warped(omega, dt), sys.stiffness)), 1e-9)
        << "N = " << steps;
    EXPECT_LT(std::abs(r.coefficients(0, 0)), 1e-9 * std::abs(exact[0]));
    const double error = harmonic_error(r, 1, exact);
    if (previous > 0.0) {
      const double rate = std::log2(previous / error);
      std::printf("  N = %4d: relative amplitude error %.3e, observed rate %.3f\n", steps, error,
                  rate);
      EXPECT_NEAR(rate, 2.0, 0.05);
    } else {
      std::printf("  N = %4d: relative amplitude error %.3e\n", steps, error);
    }
    previous = error;
  }
}

TEST(NewmarkLinear, TwoDofStaticAndTwoHarmonicsWithSecondOrderRate) {
  Eigen::MatrixXd m(2, 2), k(2, 2);
  m << 1.0, 0.0, 0.0, 0.5;
  k << 3.0, -1.0, -1.0, 1.0;
  k *= 4.0 * pi * pi;
  auto sys = linear_system(m, Eigen::MatrixXd::Zero(2, 2), k);
  sys.damping = hb::modal_damping_matrix(sys.mass, sys.stiffness, {0.03, 0.04});
  hb::Excitation ex;
  ex.static_force = Eigen::Vector2d(0.0, 5.0);
  ex.forces = {{0, 1.0, 1}, {1, 0.7, 2}, {0, -0.2, 2}};
  const double omega = 2 * pi * 0.9;
  const Eigen::Vector2d f1(1.0, 0.0), f2(-0.2, 0.7);
  const Eigen::Vector2d x_static = Eigen::MatrixXd(sys.stiffness).ldlt().solve(ex.static_force);
  double previous1 = 0.0, previous2 = 0.0;
  for (int steps : {64, 128, 256}) {
    const auto r = ti::forced_steady_state(sys, ex, omega, steady_options(steps));
    ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
    const double dt = r.time_step;
    EXPECT_LT((r.coefficients.col(0) - x_static).cwiseAbs().maxCoeff(), 1e-9 * x_static.norm());
    EXPECT_LT(harmonic_error(r, 1, receptance(sys, f1, warped(omega, dt), sys.stiffness)), 1e-9);
    EXPECT_LT(harmonic_error(r, 2, receptance(sys, f2, warped(2 * omega, dt), sys.stiffness)),
              1e-9);
    EXPECT_LT(r.coefficients.col(5).cwiseAbs().maxCoeff(), 1e-9);  // nothing at 3Ω
    const double e1 = harmonic_error(r, 1, receptance(sys, f1, omega, sys.stiffness));
    const double e2 = harmonic_error(r, 2, receptance(sys, f2, 2 * omega, sys.stiffness));
    if (previous1 > 0.0) {
      const double rate1 = std::log2(previous1 / e1), rate2 = std::log2(previous2 / e2);
      std::printf("  N = %4d: errors H1 %.3e (rate %.3f), H2 %.3e (rate %.3f)\n", steps, e1, rate1,
                  e2, rate2);
      EXPECT_NEAR(rate1, 2.0, 0.05);
      EXPECT_NEAR(rate2, 2.0, 0.05);
    } else {
      std::printf("  N = %4d: errors H1 %.3e, H2 %.3e\n", steps, e1, e2);
    }
    previous1 = e1;
    previous2 = e2;
  }
}

TEST(NewmarkLinear, HhtAlphaIsSecondOrderAndDampsUnresolvedModes) {
  const auto sys = one_dof(0.05);
  const double omega = 0.8 * 2 * pi;
  const auto ex = cosine_force(0, 1.0);
  const Eigen::VectorXcd exact = receptance(sys, Eigen::VectorXd::Ones(1), omega, sys.stiffness);
  double previous = 0.0;
  for (int steps : {64, 128, 256}) {
    auto o = steady_options(steps);
    o.integrator.alpha = -0.1;
    const auto r = ti::forced_steady_state(sys, ex, omega, o);
    ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
    const double error = harmonic_error(r, 1, exact);
    if (previous > 0.0) {
      EXPECT_NEAR(std::log2(previous / error), 2.0, 0.1);
    }
    previous = error;
  }
  // Free vibration at ω_nΔt = 1e4: the trapezoidal rule keeps the energy, HHT with α = -1/3
  // removes it at the spectral radius ρ∞ = (1+α)/(1-α) = 1/2 per step.
  const auto free = one_dof(0.0);
  ti::State start;
  start.displacement = Eigen::VectorXd::Ones(1);
  start.velocity = Eigen::VectorXd::Zero(1);
  ti::NewmarkOptions o;
  o.time_step = 1e4 / (2 * pi);
  const double e0 = kinetic_plus_potential(free, start);
  const auto trapezoid = ti::integrate(free, {}, 0.0, start, 100, o);
  EXPECT_NEAR(kinetic_plus_potential(free, trapezoid.final_state) / e0, 1.0, 1e-12);
  o.alpha = -1.0 / 3.0;
  const auto hht = ti::integrate(free, {}, 0.0, start, 100, o);
  std::printf("  E_100/E_0 = %.3e with alpha = -1/3 (rho_inf^200 = %.3e)\n",
              kinetic_plus_potential(free, hht.final_state) / e0, std::pow(0.5, 200));
  EXPECT_LT(kinetic_plus_potential(free, hht.final_state) / e0, 1e-40);
}

TEST(NewmarkTransient, JenkinsRingDownEnergyBalance) {
  // Free decay from x0 = 1 with a Jenkins contact: E_0 - E_end = Σ exact dissipation, up to the
  // trapezoidal work of the contact force in the steps that cross a stick/slip transition.
  auto sys = one_dof(0.0);
  hb::ContactElement c;
  c.friction_coefficient = 0.5;
  c.normal_force = 2.0;  // μF_N = 1
  c.stiffness = 10.0 * 4.0 * pi * pi;
  sys.contacts.push_back(c);
  ti::State start;
  start.displacement = Eigen::VectorXd::Ones(1);
  start.velocity = Eigen::VectorXd::Zero(1);
  start.contact_forces = {0.0};
  ti::NewmarkOptions o;
  o.time_step = 1.0 / 400;  // T_n/400 of the free system
  int calls = 0;
  const auto r = ti::integrate(sys, {}, 0.0, start, 4000, o, [&](const ti::State&) { ++calls; });
  ASSERT_EQ(r.termination, jointhb::Termination::reached_end) << r.message;
  EXPECT_EQ(calls, 4000);
  EXPECT_NEAR(r.final_state.time, 10.0, 1e-12);
  const auto energy = [&](const ti::State& s) {
    return kinetic_plus_potential(sys, s) +
           s.contact_forces[0] * s.contact_forces[0] / (2.0 * c.stiffness);
  };
  const double lost = energy(start) - energy(r.final_state);
  std::printf("  dissipated %.6f J of %.6f J, balance error %.2e\n", r.contact_dissipation[0],
              energy(start), std::abs(lost - r.contact_dissipation[0]) / r.contact_dissipation[0]);
  EXPECT_GT(r.contact_dissipation[0], 0.5 * energy(start));
  EXPECT_NEAR(lost, r.contact_dissipation[0], 1e-4 * r.contact_dissipation[0]);
  EXPECT_EQ(r.external_work, 0.0);
}

TEST(NewmarkContacts, StuckContactsAreLinearSprings) {
  // A contact to ground and one between the DOFs, limits too high to slip: the steady state is
  // that of K + k_T0 terms (at the warped frequency), to round-off.
  Eigen::MatrixXd m(2, 2), k(2, 2);
  m << 1.0, 0.0, 0.0, 2.0;
  k << 2.0, -1.0, -1.0, 1.0;
  k *= 100.0;
  auto sys = linear_system(m, Eigen::MatrixXd::Zero(2, 2), k);
  sys.damping = hb::modal_damping_matrix(sys.mass, sys.stiffness, {0.02, 0.02});
  hb::ContactElement ground, link;
  ground.law = "jenkins";
  ground.stiffness = 50.0;
  ground.normal_force = 1e6;
  link.law = "gaul-mayer";
  link.dof_a = 1;
  link.dof_b = 0;
  link.stiffness = 80.0;
  link.normal_force = 1e9;  // Gaul–Mayer softens with |F|/μF_N: keep it ~1e-9
  sys.contacts = {ground, link};
  const auto ex = cosine_force(1, 1.0);
  const double omega = 9.0;
  const auto r = ti::forced_steady_state(sys, ex, omega, steady_options(128));
  ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
  const auto x = receptance(sys, Eigen::Vector2d(0.0, 1.0), warped(omega, r.time_step),
                            hb::stuck_stiffness(sys));
  EXPECT_LT(harmonic_error(r, 1, x), 1e-7);  // Gaul–Mayer's softening is O(|F|/μF_N) ~ 1e-8
  EXPECT_EQ(r.contact_dissipation[0], 0.0);
  EXPECT_LT(r.contact_dissipation[1], 1e-12);
}

TEST(NewmarkContacts, JenkinsSteadyStateEnergyBalance) {
  // Forced Jenkins oscillator with viscous damping: over the steady period the work of the force
  // equals the viscous and the contact dissipation; the contact dissipation is the Jenkins loop
  // 2 F_s (max g - min g - 2 F_s/k) of the sampled gap.
  auto sys = one_dof(0.02);
  hb::ContactElement c;
  c.normal_force = 1.0;
  c.friction_coefficient = 0.4;  // F_s = 0.4
  c.stiffness = 4.0 * pi * pi;
  sys.contacts.push_back(c);
  const auto ex = cosine_force(0, 1.0);
  auto o = steady_options(512);
  o.tolerance = 1e-10;
  const auto r = ti::forced_steady_state(sys, ex, 1.1 * 2 * pi, o);
  ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
  const double d = r.contact_dissipation[0];
  const double fs = c.slip_limit();
  const double span = r.samples.row(0).maxCoeff() - r.samples.row(0).minCoeff();
  EXPECT_NEAR(d, 2.0 * fs * (span - 2.0 * fs / c.stiffness), 1e-9 * d);
  EXPECT_GT(d, r.viscous_dissipation);  // friction dominates: the check is not trivial
  const double balance = r.external_work - r.viscous_dissipation - d;
  std::printf(
      "  W_ext %.6f, W_visc %.6f, W_contact %.6f, relative imbalance %.2e (%ld steps, "
      "%.0f ns/step)\n",
      r.external_work, r.viscous_dissipation, d, balance / r.external_work, r.steps,
      1e9 * r.seconds / static_cast<double>(r.steps));
  EXPECT_NEAR(balance, 0.0, 1e-4 * r.external_work);
}

TEST(NewmarkContacts, GaulMayerDissipationMatchesPeriodicStateOfTheGapHistory) {
  auto sys = one_dof(0.02);
  hb::ContactElement c;
  c.law = "gaul-mayer";
  c.exponent = 1.0 / 3.0;
  c.friction_coefficient = 0.5;
  c.normal_force = 1.0;
  c.stiffness = 2.0 * 4.0 * pi * pi;
  sys.contacts.push_back(c);
  const auto ex = cosine_force(0, 0.3);
  const auto r = ti::forced_steady_state(sys, ex, 1.2 * 2 * pi, steady_options(512));
  ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
  // The same law on the sampled gap history, solved for periodicity directly.
  jc::PeriodicPath path;
  for (Eigen::Index j = 0; j < r.samples.cols(); ++j) {
    path.slip.emplace_back(r.samples(0, j), 0.0);
    path.limits.push_back({c.slip_limit(), c.stiffness});
  }
  const jc::GaulMayerLaw law(c.exponent);
  const auto loop = jc::solve_periodic_state(law, path);
  ASSERT_EQ(loop.termination, jointhb::Termination::converged);
  const double peak = r.contact_force_samples.cwiseAbs().maxCoeff();
  EXPECT_GT(peak, 0.3 * c.slip_limit());  // well inside microslip, not stuck
  EXPECT_LT(peak, 0.999 * c.slip_limit());
  std::printf("  W_D time integration %.10f, periodic state %.10f (F^/F_s = %.3f, %d periods)\n",
              r.contact_dissipation[0], loop.dissipation, peak / c.slip_limit(), r.periods);
  EXPECT_NEAR(r.contact_dissipation[0], loop.dissipation, 1e-7 * loop.dissipation);
  for (Eigen::Index j = 0; j < r.samples.cols(); j += 37) {
    EXPECT_NEAR(r.contact_force_samples(0, j), loop.traction[static_cast<std::size_t>(j)].x(),
                1e-7 * peak);
  }
  // And the balance of the period: W_ext = W_visc + W_D to the trapezoidal contact work.
  EXPECT_NEAR(r.external_work, r.viscous_dissipation + r.contact_dissipation[0],
              1e-4 * r.external_work);
}

TEST(NewmarkNewton, StiffJenkinsContactsWithLargeStepsConverge) {
  // Three masses, two very stiff Jenkins contacts (k_T0 = 1e6 k), 64 steps per period: the
  // Newton iterate overshoots between stuck and sliding tangents; the line search must settle it.
  Eigen::MatrixXd k(3, 3);
  k << 2, -1, 0, -1, 2, -1, 0, -1, 1;
  k *= 1000.0;
  auto sys = linear_system(Eigen::MatrixXd::Identity(3, 3), Eigen::MatrixXd::Zero(3, 3), k);
  sys.damping = hb::modal_damping_matrix(sys.mass, sys.stiffness, {0.01, 0.01, 0.01});
  hb::ContactElement a, b;
  a.dof_a = 2;
  a.stiffness = 1e9;
  a.normal_force = 1.0;
  b.dof_a = 1;
  b.dof_b = 0;
  b.stiffness = 1e9;
  b.normal_force = 2.0;
  sys.contacts = {a, b};
  const auto ex = cosine_force(2, 10.0);
  ti::NewmarkOptions o;
  o.time_step = 2 * pi / 20.0 / 64;
  const auto r = ti::integrate(sys, ex, 20.0, ti::rest_state(sys), 64 * 20, o);
  ASSERT_EQ(r.termination, jointhb::Termination::reached_end) << r.message;
  std::printf("  %ld Newton iterations in %d steps (max %d in one), %ld line searches\n",
              r.newton_iterations, r.steps, r.max_step_iterations, r.line_searches);
  EXPECT_GT(r.contact_dissipation[0], 0.0);
  EXPECT_GT(r.contact_dissipation[1], 0.0);
  EXPECT_LE(r.max_step_iterations, 20);
}

TEST(NewmarkNewton, NonConvergenceIsAStatus) {
  auto sys = one_dof(0.02);
  hb::ContactElement c;
  c.law = "gaul-mayer";
  c.stiffness = 100.0;
  c.normal_force = 1.0;
  sys.contacts.push_back(c);
  ti::NewmarkOptions o;
  o.time_step = 0.01;
  o.max_newton_iterations = 1;
  o.newton_tolerance = 1e-14;
  const auto r = ti::integrate(sys, cosine_force(0, 5.0), 2 * pi, ti::rest_state(sys), 200, o);
  EXPECT_EQ(r.termination, jointhb::Termination::failed);
  EXPECT_NE(r.message.find("Newton did not converge"), std::string::npos) << r.message;
  // The status convention (contact/termination.hpp): a Newton failure in a step is `failed`, for
  // the transient as for the steady state below; max_periods is `no_convergence`.
  EXPECT_EQ(r.status().termination, jointhb::Termination::failed);
  EXPECT_EQ(r.status().message, r.message);
  EXPECT_LT(r.steps, 200);
  EXPECT_NEAR(r.final_state.time, r.steps * o.time_step, 1e-12);

  auto so = steady_options(64);
  so.integrator = o;
  so.integrator.time_step = 0.0;
  const auto s = ti::forced_steady_state(sys, cosine_force(0, 5.0), 2 * pi, so);
  EXPECT_EQ(s.termination, jointhb::Termination::failed);
  EXPECT_EQ(s.status().termination, jointhb::Termination::failed);
  EXPECT_NE(s.message.find("Newton"), std::string::npos);

  so = steady_options(64);
  so.max_periods = 2;
  const auto t = ti::forced_steady_state(sys, cosine_force(0, 5.0), 2 * pi, so);
  EXPECT_EQ(t.termination, jointhb::Termination::no_convergence);
  EXPECT_EQ(t.status().termination, jointhb::Termination::no_convergence);
  EXPECT_EQ(t.periods, 2);
  EXPECT_NE(t.message.find("no steady state after 2 periods"), std::string::npos) << t.message;
}

TEST(NewmarkStatus, CompletedRunsReachTheEndAndRingDownReasonsMapOneToOne) {
  auto sys = one_dof(0.02);
  ti::NewmarkOptions o;
  o.time_step = 0.01;
  const auto r = ti::integrate(sys, cosine_force(0, 5.0), 2 * pi, ti::rest_state(sys), 20, o);
  ASSERT_EQ(r.termination, jointhb::Termination::reached_end) << r.message;
  EXPECT_EQ(r.status().termination, jointhb::Termination::reached_end);
  EXPECT_EQ(r.status().brief(), "reached_end: 20 steps");

  ti::RingDownResult d;
  d.reason = ti::RingDownReason::decayed;
  EXPECT_EQ(d.status().termination, jointhb::Termination::reached_end);
  d.reason = ti::RingDownReason::max_periods;
  EXPECT_EQ(d.status().termination, jointhb::Termination::no_convergence);
  d.reason = ti::RingDownReason::no_oscillation;
  EXPECT_EQ(d.status().termination, jointhb::Termination::failed);
  d.reason = ti::RingDownReason::integration_failed;
  EXPECT_EQ(d.status().termination, jointhb::Termination::failed);
}

TEST(NewmarkOptions, ValidationNamesTheField) {
  ti::NewmarkOptions o;
  EXPECT_NE(o.validate().find("time_step"), std::string::npos);
  o.time_step = 1e-3;
  EXPECT_EQ(o.validate(), "");
  o.alpha = 0.1;
  EXPECT_NE(o.validate().find("alpha"), std::string::npos);
  o.alpha = -0.5;
  EXPECT_NE(o.validate().find("alpha"), std::string::npos);
  o.alpha = 0.0;
  o.max_newton_iterations = 0;
  EXPECT_NE(o.validate().find("max_newton_iterations"), std::string::npos);
  o.max_newton_iterations = 10;
  o.newton_tolerance = 0.0;
  EXPECT_NE(o.validate().find("newton_tolerance"), std::string::npos);
  o.newton_tolerance = 1e-10;
  o.max_line_search = 0;
  EXPECT_NE(o.validate().find("max_line_search"), std::string::npos);

  ti::SteadyStateOptions s;
  EXPECT_EQ(s.validate(), "");  // the integrator's time step is set from the period
  s.harmonics = 10;
  s.steps_per_period = 20;
  EXPECT_NE(s.validate().find("steps_per_period"), std::string::npos);
  s.steps_per_period = 512;
  s.tolerance = 0.5;
  EXPECT_NE(s.validate().find("tolerance"), std::string::npos);
  s.tolerance = 1e-9;
  s.max_periods = 0;
  EXPECT_NE(s.validate().find("max_periods"), std::string::npos);
  s.max_periods = 10;
  s.integrator.alpha = 1.0;
  EXPECT_NE(s.validate().find("integrator.alpha"), std::string::npos);

  const auto sys = one_dof(0.0);
  ti::NewmarkOptions good;
  good.time_step = 1e-3;
  ti::State bad = ti::rest_state(sys);
  bad.velocity = Eigen::VectorXd::Zero(2);
  EXPECT_THROW(ti::integrate(sys, {}, 0.0, bad, 1, good), std::invalid_argument);
  EXPECT_THROW(ti::integrate(sys, cosine_force(3, 1.0), 1.0, ti::rest_state(sys), 1, good),
               std::invalid_argument);
  EXPECT_THROW(ti::integrate(sys, {}, 0.0, ti::rest_state(sys), 1, ti::NewmarkOptions{}),
               std::invalid_argument);
  EXPECT_THROW(ti::forced_steady_state(sys, {}, 0.0, ti::SteadyStateOptions{}),
               std::invalid_argument);
}
