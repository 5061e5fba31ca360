// Ring-downs (ring_down.hpp): linear decays against ω_d and ζ (1 and 2 DOF, Δt² without the
// discretisation correction), Jenkins gross slip against the exact per-half-cycle drop, and
// Gaul–Mayer microslip against the energy method with the closed-form loop dissipation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "jointhb/contact/closed_forms.hpp"
#include "jointhb/timeint/ring_down.hpp"
#include "unit/timeint/linear_systems.hpp"

namespace hb = jointhb::hb;
namespace ti = jointhb::timeint;
namespace cf = jointhb::contact::closed_form;
using std::numbers::pi;

namespace {

using jointhb::test_systems::linear_system;
using jointhb::test_systems::one_dof;

constexpr double kSpring = 4.0 * pi * pi;  // m = 1, ω_n = 2π

ti::RingDownOptions options(double q0, int steps) {
  ti::RingDownOptions o;
  o.initial_amplitude = q0;
  o.steps_per_period = steps;
  o.integrator.newton_tolerance = 1e-12;
  return o;
}

struct RingDownErrors {
  double omega = 0.0;  // max |ω - ω_d| / ω_d
  double zeta = 0.0;   // max |ζ - ζ_exact| / ζ_exact
};

RingDownErrors linear_errors(const ti::RingDownResult& r, double omega_d, double zeta) {
  RingDownErrors e;
  for (const auto& c : r.cycles) {
    e.omega = std::max(e.omega, std::abs(c.omega - omega_d) / omega_d);
    e.zeta = std::max(e.zeta, std::abs(c.damping_ratio - zeta) / zeta);
  }
  return e;
}

}  // namespace

TEST(RingDownLinear, OneDofViscousGivesDampedFrequencyAndDampingRatio) {
  const double zeta = 0.02;
  const auto system = one_dof(zeta);
  const double omega_d = 2.0 * pi * std::sqrt(1.0 - zeta * zeta);

  auto o = options(1.0, 256);
  const auto r = ti::ring_down(system, o);
  ASSERT_EQ(r.reason, ti::RingDownReason::decayed) << r.message;
  // ln(1000)/(2πζ) ≈ 55 cycles; the first maximum located is the one after t = 0.
  EXPECT_GE(r.cycles.size(), 50U);
  const RingDownErrors corrected = linear_errors(r, omega_d, zeta);
  std::printf("[ring-down] 1 DOF, N = 256, corrected: max rel. error ω %.2e, ζ %.2e\n",
              corrected.omega, corrected.zeta);
  EXPECT_LT(corrected.omega, 1e-9);
  EXPECT_LT(corrected.zeta, 1e-8);
  for (const auto& c : r.cycles) {
    EXPECT_NEAR(c.centre, 0.0, 1e-9);
    // Viscous loss over a cycle: E_k (1 - e^{-2δ}), E at the peaks = ½ k q̂².
    const double e_first = 0.5 * kSpring * c.first_peak * c.first_peak;
    const double e_second = 0.5 * kSpring * c.second_peak * c.second_peak;
    EXPECT_NEAR(c.energy_loss, e_first - e_second, 1e-6 * e_first);
  }

  // Without the correction: the trapezoidal rule's period elongation, O(Δt²).
  o.correct_time_discretisation = false;
  double previous = 0.0;
  for (const int steps : {64, 128, 256}) {
    o.steps_per_period = steps;
    const auto raw = ti::ring_down(system, o);
    const RingDownErrors e = linear_errors(raw, omega_d, zeta);
    std::printf(
        "[ring-down] 1 DOF, N = %3d, raw: max rel. error ω %.3e, ζ %.3e%s\n", steps, e.omega,
        e.zeta,
        previous > 0.0 ? (", rate " + std::to_string(std::log2(previous / e.omega))).c_str() : "");
    if (steps == 256) {
      EXPECT_LT(e.omega, 1e-4);
      EXPECT_LT(e.zeta, 1e-3);
    }
    if (previous > 0.0) {
      EXPECT_NEAR(std::log2(previous / e.omega), 2.0, 0.05);
    }
    previous = e.omega;
  }
}

TEST(RingDownLinear, SecondModeOfTwoDofsGivesItsOwnFrequencyAndDamping) {
  Eigen::MatrixXd m(2, 2), k(2, 2);
  m << 1.0, 0.0, 0.0, 2.0;
  k << 3.0, -1.0, -1.0, 1.0;
  k *= kSpring;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, m);
  const Eigen::VectorXd omega = eig.eigenvalues().cwiseSqrt();

  // Modal damping, ζ = (0.01, 0.03).
  auto system = linear_system(m, Eigen::MatrixXd::Zero(2, 2), k);
  system.damping = hb::modal_damping_matrix(system.mass, system.stiffness, {0.01, 0.03});
  auto o = options(0.5, 128);
  o.mode = 2;
  auto r = ti::ring_down(system, o);
  ASSERT_EQ(r.reason, ti::RingDownReason::decayed) << r.message;
  EXPECT_NEAR(r.linear_omega, omega[1], 1e-9 * omega[1]);
  RingDownErrors e = linear_errors(r, omega[1] * std::sqrt(1.0 - 0.03 * 0.03), 0.03);
  std::printf("[ring-down] 2 DOF modal, mode 2: max rel. error ω %.2e, ζ %.2e\n", e.omega, e.zeta);
  EXPECT_LT(e.omega, 1e-8);
  EXPECT_LT(e.zeta, 1e-7);

  // Rayleigh damping C = a M + b K: ζ_i = a/(2ω_i) + b ω_i/2.
  const double a = 0.05, b = 0.002;
  system.damping = (a * m + b * k).sparseView();
  r = ti::ring_down(system, o);
  ASSERT_EQ(r.reason, ti::RingDownReason::decayed) << r.message;
  const double zeta2 = a / (2.0 * omega[1]) + b * omega[1] / 2.0;
  e = linear_errors(r, omega[1] * std::sqrt(1.0 - zeta2 * zeta2), zeta2);
  std::printf("[ring-down] 2 DOF Rayleigh (ζ2 = %.4f), mode 2: max rel. error ω %.2e, ζ %.2e\n",
              zeta2, e.omega, e.zeta);
  EXPECT_LT(e.omega, 1e-8);
  EXPECT_LT(e.zeta, 1e-7);
  // Mode 1 has a different ζ: the projection must not mix it in.
  const double zeta1 = a / (2.0 * omega[0]) + b * omega[0] / 2.0;
  EXPECT_GT(std::abs(zeta1 - zeta2), 0.1 * zeta2);
}

TEST(RingDownJenkins, GrossSlipDropsAsDerivedAndStuckRingsAtTheStuckFrequency) {
  // m ẍ + k x + F = 0, Jenkins contact to ground (k_T = 100 k, F_s = 0.02 k x0). A half cycle from
  // rest at X (sliding, F = ±F_s) to rest at -Y sticks over 2F_s/k_T and slides over the rest, so
  // ½k(X² - Y²) = F_s (X + Y - 2F_s/k_T), i.e. X - Y = 2F_s/k - 4F_s²/(k k_T (X + Y)).
  auto system = one_dof(0.0);
  system.damping = hb::SparseMatrix();
  hb::ContactElement c;
  c.law = "jenkins";
  c.stiffness = 100.0 * kSpring;
  c.friction_coefficient = 1.0;
  c.normal_force = 0.02 * kSpring;
  system.contacts.push_back(c);
  const double fs = c.slip_limit(), kt = c.stiffness;
  const double omega_stuck = std::sqrt(kSpring + kt);

  auto o = options(1.0, 256);
  o.max_periods = 400;
  o.stop_ratio = 1e-12;
  const auto r = ti::ring_down(system, o);
  ASSERT_EQ(r.reason, ti::RingDownReason::max_periods) << r.message;
  ASSERT_GE(r.cycles.size(), 10U);
  const auto drop = [&](double x, double y) {
    return 2 * fs / kSpring - 4 * fs * fs / (kSpring * kt * (x + y));
  };
  int gross = 0;
  double worst = 0.0;
  for (const auto& cy : r.cycles) {
    const double x = cy.first_peak, y = -cy.trough, x2 = cy.second_peak;
    if (x2 < 4.0 * fs / kSpring) break;  // the last slipping half cycles end in stick
    ++gross;
    worst = std::max({worst, std::abs((x - y) - drop(x, y)), std::abs((y - x2) - drop(x2, y))});
    EXPECT_NEAR(x - x2, 4.0 * fs / kSpring, 0.01 * 4.0 * fs / kSpring);
    EXPECT_LT(cy.omega, omega_stuck);
  }
  std::printf(
      "[ring-down] Jenkins: %d gross-slip cycles, drop per half cycle 2F_s/k = %.5f, worst "
      "error against the derived drop %.2e\n",
      gross, 2 * fs / kSpring, worst);
  EXPECT_GE(gross, 8);
  EXPECT_LT(worst, 1e-4 * 2 * fs / kSpring);

  // Finally stuck: linear, undamped, at √((k + k_T)/m).
  const auto& last = r.cycles.back();
  std::printf("[ring-down] Jenkins stuck: ω/ω_stuck - 1 = %.2e, ζ = %.2e, amplitude %.3e\n",
              last.omega / omega_stuck - 1.0, last.damping_ratio, last.amplitude);
  EXPECT_LT(last.amplitude, 2.0 * fs / kt);
  EXPECT_NEAR(last.omega, omega_stuck, 1e-10 * omega_stuck);
  EXPECT_NEAR(last.damping_ratio, 0.0, 1e-10);
}

TEST(RingDownGaulMayer, MicroslipDampingVanishesAndMatchesTheEnergyMethod) {
  auto system = one_dof(0.0);
  system.damping = hb::SparseMatrix();
  hb::ContactElement c;
  c.law = "gaul-mayer";
  c.exponent = 1.0 / 3.0;
  c.stiffness = kSpring;
  c.friction_coefficient = 1.0;
  c.normal_force = 0.3 * kSpring;  // full slip of the virgin curve at 0.45 x0
  system.contacts.push_back(c);
  const double omega_stuck = std::sqrt(2.0 * kSpring);
  const cf::MicroslipParameters p{c.exponent, c.slip_limit(), c.stiffness};

  auto o = options(1.0, 256);
  o.max_periods = 300;
  const auto r = ti::ring_down(system, o);
  ASSERT_NE(r.reason, ti::RingDownReason::integration_failed) << r.message;
  ASSERT_GE(r.cycles.size(), 100U);
  double worst_energy = 0.0;
  int compared = 0;
  for (std::size_t i = 0; i < r.cycles.size(); ++i) {
    const auto& cy = r.cycles[i];
    ASSERT_TRUE(std::isfinite(cy.omega) && std::isfinite(cy.damping_ratio) &&
                std::isfinite(cy.amplitude));
    EXPECT_LT(cy.omega, omega_stuck);
    if (i > 0) {
      EXPECT_LT(cy.amplitude, r.cycles[i - 1].amplitude);
      EXPECT_LT(cy.damping_ratio, r.cycles[i - 1].damping_ratio) << "cycle " << i;
      EXPECT_GT(cy.omega, r.cycles[i - 1].omega) << "cycle " << i;
    }
    if (cy.damping_ratio < 0.01) {
      // Energy method: ζ ≈ W_D(a) / (4π · ½ ω² a²) for a slowly decaying cycle.
      const double wd = cf::symmetric_loop(cy.amplitude, p).dissipation;
      const double zeta_energy =
          wd / (4.0 * pi * 0.5 * cy.omega * cy.omega * cy.amplitude * cy.amplitude);
      worst_energy = std::max(worst_energy, std::abs(zeta_energy / cy.damping_ratio - 1.0));
      ++compared;
    }
  }
  const auto& first = r.cycles.front();
  const auto& last = r.cycles.back();
  std::printf(
      "[ring-down] Gaul-Mayer: %zu cycles, a %.3f → %.4f, ζ %.4f → %.2e, ω/ω_stuck %.4f → "
      "%.6f; %d cycles vs energy method, worst rel. difference %.2e\n",
      r.cycles.size(), first.amplitude, last.amplitude, first.damping_ratio, last.damping_ratio,
      first.omega / omega_stuck, last.omega / omega_stuck, compared, worst_energy);
  EXPECT_GE(compared, 20);
  EXPECT_LT(worst_energy, 0.03);
  EXPECT_LT(last.damping_ratio, 0.1 * first.damping_ratio);
  EXPECT_GT(last.omega / omega_stuck, 0.99);
}

TEST(RingDownValidation, ValidateNamesTheField) {
  ti::RingDownOptions o;
  EXPECT_NE(o.validate().find("initial_amplitude"), std::string::npos);
  o.initial_amplitude = 1.0;
  EXPECT_EQ(o.validate(), "");
  auto bad = o;
  bad.mode = 0;
  EXPECT_EQ(bad.validate().rfind("mode:", 0), 0U);
  bad = o;
  bad.steps_per_period = 8;
  EXPECT_EQ(bad.validate().rfind("steps_per_period:", 0), 0U);
  bad = o;
  bad.max_periods = 1;
  EXPECT_EQ(bad.validate().rfind("max_periods:", 0), 0U);
  bad = o;
  bad.stop_ratio = 1.0;
  EXPECT_EQ(bad.validate().rfind("stop_ratio:", 0), 0U);
  bad = o;
  bad.integrator.alpha = 0.5;
  EXPECT_EQ(bad.validate().rfind("integrator.alpha:", 0), 0U);
  EXPECT_THROW((void)ti::ring_down(one_dof(0.01), bad), std::invalid_argument);
  bad = o;
  bad.mode = 2;
  EXPECT_THROW((void)ti::ring_down(one_dof(0.01), bad), std::invalid_argument);
}

// Synthetic cycles of q(t) = c0 + v t + A r^(t/T) cos(2πt/T) sampled at its peaks and troughs: the
// fixed-centre ζ_k is biased by the drift v, the two-cycle estimate cancels it to first order.
TEST(RingDownTwoCycle, DriftingCentreCancelsToFirstOrder) {
  const double period = 0.01, amplitude = 1.0, r = 0.9, drift = 5e-3 / period;  // v T = 5e-3 A
  const double delta = -std::log(r), zeta = delta / std::sqrt(4.0 * pi * pi + delta * delta);
  const auto q_at = [&](double t, double sign) {
    return drift * t + sign * amplitude * std::pow(r, t / period);
  };
  std::vector<ti::RingDownCycle> cycles;
  for (int k = 0; k < 6; ++k) {
    ti::RingDownCycle c;
    c.first_peak = q_at(k * period, 1.0);
    c.trough = q_at((k + 0.5) * period, -1.0);
    c.second_peak = q_at((k + 1) * period, 1.0);
    c.time = (k + 0.5) * period;
    c.omega = 2.0 * pi / period;
    cycles.push_back(c);
  }
  const auto estimates = ti::two_cycle_estimates(cycles);
  ASSERT_EQ(estimates.size(), 5u);
  for (const auto& e : estimates) {
    // Drift enters at second order: (vT/(2 a))² ~ 1e-5 relative, against ~1e-2 at first order.
    EXPECT_NEAR(e.damping_ratio / zeta - 1.0, 0.0, 2e-4) << "cycle " << e.cycle;
    EXPECT_NEAR(e.omega, 2.0 * pi / period, 1e-12);
    EXPECT_GT(e.amplitude, 0.0);
  }
  // The same data read with a fixed centre (the first-order estimate) is off by ≥ 1e-3.
  const auto& c0 = cycles[2];
  const double biased = std::log((c0.first_peak - c0.trough) / (c0.second_peak - c0.trough));
  EXPECT_GT(std::abs(biased / delta - 1.0), 1e-3);
  // A pair that is not a decaying oscillation (a range ≤ 0) is skipped.
  cycles[3].trough = cycles[3].first_peak + 1.0;
  EXPECT_EQ(ti::two_cycle_estimates(cycles).size(), 3u);
}
