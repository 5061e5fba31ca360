// Den Hartog's closed form (den_hartog.hpp) against two independent references:
//  - an event-driven exact integration of m ẍ + k x + F_f sgn(ẋ) = P cos ωt (analytic motion
//    between velocity reversals, reversals and stick phases located by bisection), and
//  - the Newmark integrator with a Jenkins contact of very high k_T0 (Coulomb in the limit).
// Also: the analytic Fourier coefficients against a fine DFT of the exact x(t), the energy identity
// 4 F_f X0 = π P b1, the friction-free and resonance limits, and the regime flags.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Core>

#include "jointhb/timeint/den_hartog.hpp"
#include "jointhb/timeint/newmark.hpp"

namespace hb = jointhb::hb;
namespace ti = jointhb::timeint;
using std::numbers::pi;

namespace {

// m ẍ + k x + F_f sgn(ẋ) = P cos ωt, integrated exactly from event to event.
class CoulombOscillator {
 public:
  struct Stop {
    double time = 0.0;   // when ẋ reached zero
    double x = 0.0;      // where
    double stick = 0.0;  // how long the mass then stayed at rest
  };

  CoulombOscillator(double m, double k, double friction, double force, double omega)
      : k_(k),
        ff_(friction),
        p_(force),
        w_(omega),
        wn_(std::sqrt(k / m)),
        xp_(force / (k - m * omega * omega)),
        h_(2.0 * pi / std::max(wn_, omega) / 512.0) {}

  // Starts at rest at (t, x): moves off (or sticks first) according to the net force.
  void start_at_rest(double t, double x) {
    t_ = t;
    x_ = x;
    v_ = 0.0;
    s_ = 0.0;
  }
  // Starts moving with velocity v ≠ 0.
  void start_moving(double t, double x, double v) {
    t_ = t;
    x_ = x;
    v_ = v;
    s_ = v > 0.0 ? 1.0 : -1.0;
  }

  // Advances to the next velocity reversal (including any stick phase before the motion).
  Stop next_stop() {
    Stop stop;
    if (s_ == 0.0) stop.stick = leave_rest();
    if (std::isinf(stop.stick)) {
      stop.time = std::numeric_limits<double>::infinity();
      stop.x = x_;
      return stop;
    }
    // x(τ) = A cos ω_nτ + B sin ω_nτ + X_p cos ω(t0+τ) - s F_f/k while sgn ẋ = s.
    const double t0 = t_;
    const double a = x_ - xp_ * std::cos(w_ * t0) + s_ * ff_ / k_;
    const double b = (v_ + xp_ * w_ * std::sin(w_ * t0)) / wn_;
    const auto velocity = [&](double tau) {
      return wn_ * (-a * std::sin(wn_ * tau) + b * std::cos(wn_ * tau)) -
             xp_ * w_ * std::sin(w_ * (t0 + tau));
    };
    double lo = 0.0, hi = h_;
    while (s_ * velocity(hi) > 0.0) {
      lo = hi;
      hi += h_;
    }
    for (int i = 0; i < 200 && hi - lo > 1e-16 * (t0 + hi); ++i) {
      const double mid = 0.5 * (lo + hi);
      (s_ * velocity(mid) > 0.0 ? lo : hi) = mid;
    }
    const double tau = 0.5 * (lo + hi);
    t_ = t0 + tau;
    x_ =
        a * std::cos(wn_ * tau) + b * std::sin(wn_ * tau) + xp_ * std::cos(w_ * t_) - s_ * ff_ / k_;
    v_ = 0.0;
    s_ = 0.0;
    stop.time = t_;
    stop.x = x_;
    return stop;
  }

  // Time after the stop at t_ until the net force P cos ωt - k x exceeds F_f; sets the direction.
  double leave_rest() {
    const auto net = [&](double t) { return p_ * std::cos(w_ * t) - k_ * x_; };
    const double t0 = t_;
    if (std::abs(net(t0)) > ff_) {
      s_ = net(t0) > 0.0 ? 1.0 : -1.0;
      return 0.0;
    }
    double lo = t0, hi = t0 + h_;
    while (std::abs(net(hi)) <= ff_) {
      lo = hi;
      hi += h_;
      if (hi - t0 > 4.0 * pi / w_)
        return std::numeric_limits<double>::infinity();  // stuck for good
    }
    for (int i = 0; i < 200 && hi - lo > 1e-16 * hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      (std::abs(net(mid)) <= ff_ ? lo : hi) = mid;
    }
    t_ = hi;
    s_ = net(hi) > 0.0 ? 1.0 : -1.0;
    return t_ - t0;
  }

 private:
  double k_, ff_, p_, w_, wn_, xp_, h_;
  double t_ = 0.0, x_ = 0.0, v_ = 0.0, s_ = 0.0;
};

constexpr double kOscillatorMass = 1.0;
constexpr double kOscillatorStiffness = 4.0 * pi * pi;  // ω_n = 2π
constexpr double kForce = 1.0;

double omega_of(double beta) { return beta * 2.0 * pi; }

struct Case {
  double beta;
  double r;
};
// Inside the non-stop region (checked by the first test): below, near and above resonance.
const std::vector<Case> kCases = {{0.6, 0.3}, {0.8, 0.5}, {1.2, 0.6},
                                  {1.5, 0.5}, {2.0, 0.3}, {2.5, 0.4}};

// The exact steady motion from rest: the stops of its last period, or empty if it did not repeat
// within `max_periods` (or stuck for good).
std::vector<CoulombOscillator::Stop> exact_steady_period(double beta, double r, int max_periods) {
  const double omega = omega_of(beta);
  const double period = 2 * pi / omega;
  CoulombOscillator exact(kOscillatorMass, kOscillatorStiffness, r * kForce, kForce, omega);
  exact.start_at_rest(0.0, 0.0);
  std::vector<CoulombOscillator::Stop> stops;
  while (true) {
    stops.push_back(exact.next_stop());
    if (!(stops.back().time < max_periods * period)) return {};
    // Periodic once a stop repeats one period later.
    for (std::size_t j = stops.size() - 1; j-- > 0;) {
      const double dt = stops.back().time - stops[j].time;
      if (dt > 1.5 * period) break;
      if (std::abs(dt - period) < 1e-9 * period &&
          std::abs(stops.back().x - stops[j].x) < 1e-9 * std::abs(stops[j].x)) {
        return {stops.begin() + static_cast<std::ptrdiff_t>(j) + 1, stops.end()};
      }
    }
  }
}

hb::DiscreteSystem jenkins_oscillator(double r, double kappa) {
  hb::DiscreteSystem sys;
  sys.mass = Eigen::MatrixXd::Constant(1, 1, kOscillatorMass).sparseView();
  sys.stiffness = Eigen::MatrixXd::Constant(1, 1, kOscillatorStiffness).sparseView();
  hb::ContactElement e;
  e.friction_coefficient = 1.0;
  e.normal_force = r * kForce;
  e.stiffness = kappa * kOscillatorStiffness;
  sys.contacts.push_back(e);
  return sys;
}

}  // namespace

TEST(DenHartog, ClosedFormIsAnExactPeriodicMotion) {
  // Started at rest at the closed form's stop (t = φ/ω, x = X0), the exact event-driven motion
  // must stop again at t = (φ + jπ)/ω, x = (-1)^j X0, without sticking.
  for (const auto& c : kCases) {
    const double omega = omega_of(c.beta);
    const auto d = ti::den_hartog(kOscillatorMass, kOscillatorStiffness, c.r * kForce, kForce, omega);
    ASSERT_TRUE(d.non_stop) << "beta " << c.beta << ": " << d.message;
    EXPECT_GT(d.phase, 0.0);  // the displacement lags the force
    EXPECT_LT(d.phase, pi);
    CoulombOscillator exact(kOscillatorMass, kOscillatorStiffness, c.r * kForce, kForce, omega);
    exact.start_at_rest(d.phase / omega, d.amplitude);
    double worst_x = 0.0, worst_t = 0.0;
    for (int j = 1; j <= 6; ++j) {
      const auto stop = exact.next_stop();
      EXPECT_EQ(stop.stick, 0.0);
      worst_x = std::max(worst_x, std::abs(stop.x - (j % 2 ? -1.0 : 1.0) * d.amplitude));
      worst_t = std::max(worst_t, std::abs(stop.time - (d.phase + j * pi) / omega));
    }
    std::printf("  beta %.2f r %.2f: X0/x_st %.6f, phase %.4f rad, stops off by %.1e X0, %.1e T\n",
                c.beta, c.r, d.amplitude / d.static_deflection, d.phase, worst_x / d.amplitude,
                worst_t * omega / (2 * pi));
    EXPECT_LT(worst_x, 1e-12 * d.amplitude);
    EXPECT_LT(worst_t * omega / (2 * pi), 1e-12);
  }
}

TEST(DenHartog, RegimeFlagAgreesWithTheExactSteadyMotionFromRest) {
  // One or more cases of every regime (see the table in docs/time-integration.md). The exact
  // motion from rest is "non-stop" when its steady period has two stops and no stick phase.
  struct Expect {
    double beta, r;
    ti::DenHartogRegime regime;
  };
  using R = ti::DenHartogRegime;
  const std::vector<Expect> cases = {
      {0.6, 0.3, R::non_stop},          {0.45, 0.2, R::non_stop},
      {1.5, 0.5, R::non_stop},          {3.0, 0.5, R::non_stop},
      {0.6, 0.8, R::sticks_at_stops},   {0.45, 0.5, R::sticks_at_stops},
      {2.0, 0.62, R::sticks_at_stops},  {0.40, 0.16, R::extra_stops},
      {0.38, 0.12, R::extra_stops},     {0.36, 0.08, R::extra_stops},
      {1.5, 0.8, R::no_real_amplitude}, {0.35, 0.3, R::no_real_amplitude}};
  for (const auto& c : cases) {
    const auto d = ti::den_hartog(kOscillatorMass, kOscillatorStiffness, c.r * kForce, kForce, omega_of(c.beta));
    EXPECT_EQ(d.regime, c.regime) << "beta " << c.beta << " r " << c.r << ": " << d.message;
    const auto period = exact_steady_period(c.beta, c.r, 500);
    ASSERT_FALSE(period.empty()) << "beta " << c.beta << " r " << c.r << ": no steady motion";
    double stick = 0.0, x_max = 0.0;
    for (const auto& s : period) {
      stick += s.stick;
      x_max = std::max(x_max, std::abs(s.x));
    }
    const bool non_stop = period.size() == 2 && stick == 0.0;
    std::printf("  beta %.2f r %.2f: %zu stops per period, stick %.3f T, regime %d\n", c.beta, c.r,
                period.size(), stick * omega_of(c.beta) / (2 * pi), static_cast<int>(d.regime));
    EXPECT_EQ(non_stop, d.non_stop) << "beta " << c.beta << " r " << c.r;
    if (d.non_stop) {
      // The period is detected once its stops repeat to 1e-9; the remaining transient is larger
      // by 1/(1 - contraction per period).
      EXPECT_NEAR(x_max, d.amplitude, 1e-7 * d.amplitude);
    }
  }
}

TEST(DenHartog, NewmarkWithStiffJenkinsConvergesToTheClosedForm) {
  // A Jenkins contact of stiffness κk approaches Coulomb friction as κ^(-1/2): each reversal
  // sticks for ~1/ω_c (ω_c = √(κ) ω_n) and leaves a velocity defect ~ ẍ/ω_c. Two stiffnesses
  // (Δt resolving ω_c: ω_cΔt = 0.31/β) check the rate and extrapolate it away,
  //   X∞ = 2 X(4κ) - X(κ),
  // leaving the O(1/κ) term and the time-step error (measured ≤ 3e-4).
  for (const auto& c : kCases) {
    const double omega = omega_of(c.beta);
    const auto d = ti::den_hartog(kOscillatorMass, kOscillatorStiffness, c.r * kForce, kForce, omega);
    const Eigen::VectorXd exact = d.coefficients(1);
    ti::State start;  // on the exact orbit, the slider sliding with the velocity
    start.displacement = Eigen::VectorXd::Constant(1, d.displacement(0.0));
    start.velocity = Eigen::VectorXd::Constant(1, d.velocity(0.0));
    start.contact_forces = {std::copysign(c.r * kForce, d.velocity(0.0))};
    hb::Excitation ex;
    ex.forces.push_back({0, kForce, 1});
    double error[2] = {0.0, 0.0};
    Eigen::Vector2d harmonic[2];
    for (int i = 0; i < 2; ++i) {
      const double kappa = i == 0 ? 1e4 : 4e4;
      ti::SteadyStateOptions o;
      o.steps_per_period = static_cast<int>(20.0 * std::sqrt(kappa));
      o.harmonics = 1;
      o.tolerance = 1e-8;
      o.max_periods = 200;
      const auto r = ti::forced_steady_state(jenkins_oscillator(c.r, kappa), ex, omega, o, start);
      ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
      error[i] = (r.amplitude_max[0] - d.amplitude) / d.amplitude;
      harmonic[i] = Eigen::Vector2d(r.coefficients(0, 1), r.coefficients(0, 2));
    }
    const double extrapolated = 2.0 * error[1] - error[0];
    const double harmonic_error =
        (2.0 * harmonic[1] - harmonic[0] - exact.tail(2)).norm() / exact.tail(2).norm();
    std::printf(
        "  beta %.2f r %.2f: X0 error %+.2e (k_T0 = 1e4 k), %+.2e (4e4 k), ratio %.3f; "
        "extrapolated X0 %+.1e, first harmonic %.1e\n",
        c.beta, c.r, error[0], error[1], error[0] / error[1], extrapolated, harmonic_error);
    EXPECT_LT(std::abs(error[0]), 2.5e-2);  // ≈ (0.15 … 2) / √κ
    EXPECT_NEAR(error[0] / error[1], 2.0, 0.1);
    EXPECT_LT(std::abs(extrapolated), 5e-4);
    EXPECT_LT(harmonic_error, 5e-4);
  }
}

TEST(DenHartog, FourierCoefficientsAndEnergyIdentity) {
  for (const auto& c : kCases) {
    const double omega = omega_of(c.beta);
    const auto d = ti::den_hartog(kOscillatorMass, kOscillatorStiffness, c.r * kForce, kForce, omega);
    const int harmonics = 7, samples = 4096;
    const Eigen::VectorXd analytic = d.coefficients(harmonics);
    Eigen::VectorXd dft = Eigen::VectorXd::Zero(2 * harmonics + 1);
    for (int j = 0; j < samples; ++j) {
      const double theta = 2 * pi * j / samples;
      const double x = d.displacement(theta / omega);
      dft[0] += x / samples;
      for (int k = 1; k <= harmonics; ++k) {
        dft[2 * k - 1] += 2.0 / samples * x * std::cos(k * theta);
        dft[2 * k] += 2.0 / samples * x * std::sin(k * theta);
      }
    }
    EXPECT_LT((analytic - dft).cwiseAbs().maxCoeff(), 1e-9 * d.amplitude) << "beta " << c.beta;
    for (int k = 2; k <= harmonics; k += 2) {  // half-wave symmetry: no even harmonics
      EXPECT_EQ(analytic[2 * k - 1], 0.0);
      EXPECT_EQ(analytic[2 * k], 0.0);
    }
    // The work of the force per cycle, π P b1, is what friction dissipates, 4 F_f X0.
    EXPECT_NEAR(pi * kForce * analytic[2], d.dissipation_per_cycle,
                1e-12 * d.dissipation_per_cycle);
    EXPECT_NEAR(d.first_harmonic_amplitude, std::hypot(analytic[1], analytic[2]), 1e-15);
    // The velocity is the derivative of the displacement (central differences), and the peak is X0.
    const double h = 1e-6 / omega;
    double peak = 0.0;
    for (int j = 0; j < 64; ++j) {
      const double t = (j + 0.5) / 64.0 * 2 * pi / omega;
      const double fd = (d.displacement(t + h) - d.displacement(t - h)) / (2 * h);
      EXPECT_NEAR(d.velocity(t), fd, 1e-7 * omega * d.amplitude);
      peak = std::max(peak, std::abs(d.displacement(t)));
    }
    EXPECT_LE(peak, d.amplitude * (1 + 1e-15));
    EXPECT_NEAR(d.displacement(d.phase / omega), d.amplitude, 1e-14 * d.amplitude);
  }
}

TEST(DenHartog, FrictionFreeAndResonanceLimits) {
  for (double beta : {0.3, 0.5, 0.9, 1.1, 2.0}) {
    const auto d = ti::den_hartog(kOscillatorMass, kOscillatorStiffness, 0.0, kForce, omega_of(beta));
    ASSERT_TRUE(d.non_stop) << d.message;
    const double linear = kForce / kOscillatorStiffness / std::abs(1 - beta * beta);
    EXPECT_NEAR(d.amplitude, linear, 1e-14 * linear);
    EXPECT_NEAR(d.first_harmonic_amplitude, linear, 1e-13 * linear);
    EXPECT_NEAR(d.phase, beta < 1 ? 0.0 : pi, 1e-15);
  }
  // Den Hartog's resonance result: bounded motion needs r < π/4 as β → 1.
  for (double beta : {1.0 - 1e-5, 1.0 + 1e-5}) {
    const auto d = ti::den_hartog(kOscillatorMass, kOscillatorStiffness, 0.5, kForce, omega_of(beta));
    EXPECT_NEAR(d.boundary_friction_ratio, pi / 4, 1e-4);
  }
  const auto at_resonance = ti::den_hartog(kOscillatorMass, kOscillatorStiffness, 0.5, kForce, omega_of(1.0));
  EXPECT_EQ(at_resonance.regime, ti::DenHartogRegime::singular_frequency);
  EXPECT_FALSE(at_resonance.non_stop);
  EXPECT_EQ(at_resonance.amplitude, 0.0);
}

TEST(DenHartog, NeverNanAndValidation) {
  for (int i = 0; i <= 400; ++i) {
    const double beta = 0.1 + 0.01 * i;
    for (double r : {0.0, 1e-3, 0.1, 0.5, 0.9, 1.0, 2.0}) {
      const auto d = ti::den_hartog(kOscillatorMass, kOscillatorStiffness, r * kForce, kForce, omega_of(beta));
      for (double v : {d.magnification, d.friction_function, d.boundary_friction_ratio,
                       d.formula_amplitude, d.amplitude, d.phase, d.first_harmonic_amplitude,
                       d.dissipation_per_cycle, d.displacement(0.3), d.velocity(0.3)}) {
        ASSERT_TRUE(std::isfinite(v)) << "beta " << beta << " r " << r;
      }
      EXPECT_EQ(d.non_stop, d.regime == ti::DenHartogRegime::non_stop);
      if (!d.non_stop) {
        EXPECT_EQ(d.amplitude, 0.0);
        EXPECT_FALSE(d.message.empty());
      }
    }
  }
  EXPECT_THROW(ti::den_hartog(0.0, 1.0, 0.1, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(ti::den_hartog(1.0, -1.0, 0.1, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(ti::den_hartog(1.0, 1.0, -0.1, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(ti::den_hartog(1.0, 1.0, 0.1, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(ti::den_hartog(1.0, 1.0, 0.1, 1.0, NAN), std::invalid_argument);
  const auto d = ti::den_hartog(1.0, 1.0, 0.1, 1.0, 2.0);
  EXPECT_THROW((void)d.coefficients(0), std::invalid_argument);
}
