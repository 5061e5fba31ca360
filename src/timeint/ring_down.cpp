// Ring-downs: free decays from a linear mode shape, cut into cycles between maxima of the modal
// coordinate, each giving amplitude, frequency and damping (ring_down.hpp, docs/time-integration.md
// §7).
#include "jointhb/timeint/ring_down.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>

namespace jointhb::timeint {

namespace {

using std::numbers::pi;

struct Extremum {
  double time = 0.0;
  double value = 0.0;
  double energy = 0.0;
};

// The extremum of the samples near the discrete extremum j, by the quartic through y[j-2..j+2]
// (symmetric, so no one-sided error); the parabola through j-1, j, j+1 when fewer samples are
// available or the quartic's stationary point leaves [-1, 1]. Returns the
// offset s ∈ [-1, 1] (in steps) and the value there.
std::pair<double, double> refine_extremum(const std::vector<double>& y, std::size_t j) {
  const double ym = y[j - 1], y0 = y[j], yp = y[j + 1];
  const double curvature = ym - 2.0 * y0 + yp;
  double s_parabola = curvature != 0.0 ? 0.5 * (ym - yp) / curvature : 0.0;
  s_parabola = std::clamp(s_parabola, -1.0, 1.0);
  const double v_parabola = y0 + 0.25 * (yp - ym) * s_parabola;

  if (j < 2 || j + 2 >= y.size()) return {s_parabola, v_parabola};
  Eigen::Matrix<double, 5, 5> v;
  Eigen::Matrix<double, 5, 1> rhs;
  for (int r = 0; r < 5; ++r) {
    const double t = r - 2;
    v.row(r) << 1.0, t, t * t, t * t * t, t * t * t * t;
    rhs[r] = y[j + static_cast<std::size_t>(r) - 2];
  }
  const Eigen::Matrix<double, 5, 1> p = v.partialPivLu().solve(rhs);  // Σ p_i s^i
  // p'(s) = 0 by Newton from the parabola's vertex (p'' ≠ 0 near an extremum).
  double s = s_parabola;
  for (int it = 0; it < 8; ++it) {
    const double d1 = p[1] + s * (2.0 * p[2] + s * (3.0 * p[3] + s * 4.0 * p[4]));
    const double d2 = 2.0 * p[2] + s * (6.0 * p[3] + s * 12.0 * p[4]);
    if (d2 == 0.0) break;
    s -= d1 / d2;
  }
  if (!std::isfinite(s) || std::abs(s) > 1.0) return {s_parabola, v_parabola};
  return {s, p[0] + s * (p[1] + s * (p[2] + s * (p[3] + s * p[4])))};
}

// Sample records of the ring-down and the extrema found in them so far.
class CycleTracker {
 public:
  explicit CycleTracker(double time_step) : dt_(time_step) {}

  void add(double q, double energy) {
    q_.push_back(q);
    energy_.push_back(energy);
  }

  // Scans the samples not yet examined for extrema (alternating: minimum, maximum, minimum, ...)
  // and closes a cycle at each new maximum that follows a maximum and a minimum.
  void scan(std::vector<RingDownCycle>& cycles, bool correct) {
    for (; next_ + 1 < q_.size(); ++next_) {
      const std::size_t j = next_;
      const bool is_max = q_[j] > q_[j - 1] && q_[j] >= q_[j + 1];
      const bool is_min = q_[j] < q_[j - 1] && q_[j] <= q_[j + 1];
      if (!(want_max_ ? is_max : is_min)) continue;
      // The quartic needs j+2: wait for the next chunk's samples.
      if (j + 2 >= q_.size()) break;
      const auto [s, value] = refine_extremum(q_, j);
      Extremum e;
      e.time = (static_cast<double>(j) + s) * dt_;
      e.value = value;
      const std::size_t lo = s >= 0.0 ? j : j - 1;
      const double w = s >= 0.0 ? s : 1.0 + s;
      e.energy = (1.0 - w) * energy_[lo] + w * energy_[lo + 1];
      if (want_max_) {
        if (has_max_) cycles.push_back(make_cycle(last_max_, last_min_, e, correct));
        last_max_ = e;
        has_max_ = true;
      } else {
        last_min_ = e;
      }
      last_extremum_time_ = e.time;
      want_max_ = !want_max_;
    }
  }

  [[nodiscard]] double last_extremum_time() const { return last_extremum_time_; }

 private:
  [[nodiscard]] RingDownCycle make_cycle(const Extremum& a, const Extremum& m, const Extremum& b,
                                         bool correct) const {
    RingDownCycle c;
    c.time = 0.5 * (a.time + b.time);
    c.first_peak = a.value;
    c.trough = m.value;
    c.second_peak = b.value;
    // (a - c)(b - c) = (c - m)²: the centre about which a, m, b decay geometrically.
    c.centre = (a.value * b.value - m.value * m.value) / (a.value + b.value - 2.0 * m.value);
    const double ra = a.value - c.centre, rb = b.value - c.centre;
    c.amplitude = std::sqrt(ra * rb);
    const double period = b.time - a.time;
    const double delta = std::log(ra / rb);
    std::complex<double> lambda(-delta / period, 2.0 * pi / period);
    if (correct) lambda = (2.0 / dt_) * std::tanh(0.5 * dt_ * lambda);
    c.omega = lambda.imag();
    c.damping_ratio = -lambda.real() / std::abs(lambda);
    c.energy_loss = a.energy - b.energy;
    c.peak_energy = 0.5 * (a.energy + b.energy);
    return c;
  }

  double dt_;
  std::vector<double> q_;
  std::vector<double> energy_;
  std::size_t next_ = 1;
  bool want_max_ = false;  // t = 0 is a maximum (ẋ = 0); the first one located is a minimum
  bool has_max_ = false;
  Extremum last_max_, last_min_;
  double last_extremum_time_ = 0.0;
};

}  // namespace

Status RingDownResult::status() const {
  switch (reason) {
    case RingDownReason::decayed:
      return {Termination::reached_end, message};
    case RingDownReason::max_periods:
      return {Termination::no_convergence, message};
    case RingDownReason::no_oscillation:  // died out above the stop ratio: more periods do not help
    case RingDownReason::integration_failed:
      return {Termination::failed, message};
  }
  return {Termination::failed, message};
}

std::string RingDownOptions::validate() const {
  if (mode < 1) return fmt::format("mode: must be >= 1, got {}", mode);
  if (!(initial_amplitude > 0.0) || !std::isfinite(initial_amplitude)) {
    return fmt::format("initial_amplitude: must be finite and > 0, got {}", initial_amplitude);
  }
  if (steps_per_period < 16) {
    return fmt::format("steps_per_period: must be >= 16, got {}", steps_per_period);
  }
  if (max_periods < 2) return fmt::format("max_periods: must be >= 2, got {}", max_periods);
  if (!(stop_ratio > 0.0 && stop_ratio < 1.0)) {
    return fmt::format("stop_ratio: must lie in (0, 1), got {}", stop_ratio);
  }
  NewmarkOptions scheme = integrator;
  scheme.time_step = 1.0;  // replaced by T_mode/N
  if (const std::string msg = scheme.validate(); !msg.empty()) return "integrator." + msg;
  return {};
}

std::vector<TwoCycleEstimate> two_cycle_estimates(const std::vector<RingDownCycle>& cycles) {
  std::vector<TwoCycleEstimate> estimates;
  for (std::size_t k = 0; k + 1 < cycles.size(); ++k) {
    const RingDownCycle& cy = cycles[k];
    const RingDownCycle& next = cycles[k + 1];
    const double rk = cy.first_peak - cy.trough, uk = cy.second_peak - cy.trough;
    const double rn = next.first_peak - next.trough, un = next.second_peak - next.trough;
    if (!(rk > 0.0 && uk > 0.0 && rn > 0.0 && un > 0.0)) continue;
    const double delta = 0.5 * (std::log(rk / rn) + std::log(uk / un));
    TwoCycleEstimate e;
    e.cycle = k;
    e.time = 0.5 * (cy.time + next.time);
    e.amplitude = 0.5 * std::pow(rk * uk * rn * un, 0.25);
    e.omega = std::sqrt(cy.omega * next.omega);
    e.damping_ratio = delta / std::sqrt(4.0 * pi * pi + delta * delta);
    estimates.push_back(e);
  }
  return estimates;
}

RingDownResult ring_down(const hb::DiscreteSystem& system, const RingDownOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (const std::string msg = options.validate(); !msg.empty()) {
    throw std::invalid_argument("ring_down: " + msg);
  }
  if (const std::string msg = system.validate(); !msg.empty()) {
    throw std::invalid_argument("ring_down: system " + msg);
  }
  const int n = system.dofs();
  if (options.mode > n) {
    throw std::invalid_argument(
        fmt::format("ring_down: mode: must be <= {} (the DOF count), got {}", n, options.mode));
  }

  const hb::LinearModes modes = hb::linear_modes(system, /*with_stuck_contacts=*/true);
  const Eigen::Index m = options.mode - 1;
  const double omega = modes.omega[m];
  if (!(omega > 0.0) || !std::isfinite(omega)) {
    throw std::invalid_argument(fmt::format(
        "ring_down: mode {} has ω = {} (a rigid-body or invalid mode)", options.mode, omega));
  }
  const Eigen::VectorXd shape = modes.shapes.col(m);
  const Eigen::VectorXd projector = system.mass * shape;  // q = (MΦ)ᵀ x
  const double period = 2.0 * pi / omega;

  RingDownResult result;
  result.linear_omega = omega;
  result.time_step = period / options.steps_per_period;

  NewmarkOptions scheme = options.integrator;
  scheme.time_step = result.time_step;
  const bool correct = options.correct_time_discretisation && scheme.alpha == 0.0;

  std::vector<double> inverse_contact_stiffness;
  for (const auto& c : system.contacts) inverse_contact_stiffness.push_back(1.0 / c.stiffness);
  const auto energy = [&](const State& s) {
    double e = 0.5 * s.velocity.dot(system.mass * s.velocity) +
               0.5 * s.displacement.dot(system.stiffness * s.displacement);
    for (std::size_t c = 0; c < s.contact_forces.size(); ++c) {
      e += 0.5 * s.contact_forces[c] * s.contact_forces[c] * inverse_contact_stiffness[c];
    }
    return e;
  };

  State state;
  state.displacement = options.initial_amplitude * shape;
  state.velocity = Eigen::VectorXd::Zero(n);
  state.time = 0.0;
  // Complete the contact forces (from the reference state) and the acceleration: zero steps.
  state = integrate(system, hb::Excitation{}, 1.0, state, 0, scheme).final_state;

  CycleTracker tracker(result.time_step);
  tracker.add(projector.dot(state.displacement), energy(state));
  const auto on_step = [&](const State& s) {
    tracker.add(projector.dot(s.displacement), energy(s));
  };

  result.reason = RingDownReason::max_periods;
  result.message = fmt::format("max_periods ({}) reached", options.max_periods);
  for (int p = 0; p < options.max_periods; ++p) {
    TransientResult chunk = integrate(system, hb::Excitation{}, 1.0, std::move(state),
                                      options.steps_per_period, scheme, on_step);
    result.steps += chunk.steps;
    result.newton_iterations += chunk.newton_iterations;
    state = std::move(chunk.final_state);
    tracker.scan(result.cycles, correct);
    if (chunk.termination != Termination::reached_end) {
      result.reason = RingDownReason::integration_failed;
      result.message = chunk.message;
      break;
    }
    if (!result.cycles.empty() &&
        result.cycles.back().amplitude < options.stop_ratio * options.initial_amplitude) {
      result.reason = RingDownReason::decayed;
      result.message = fmt::format("amplitude below {} q0 after {} cycles", options.stop_ratio,
                                   result.cycles.size());
      break;
    }
    const double last_period =
        result.cycles.empty() ? period : 2.0 * pi / result.cycles.back().omega;
    const double now = static_cast<double>(result.steps) * result.time_step;
    if (now - tracker.last_extremum_time() > std::max(50.0 * period, 4.0 * last_period)) {
      result.reason = RingDownReason::no_oscillation;
      result.message = fmt::format("no extremum of q since t = {} s", tracker.last_extremum_time());
      break;
    }
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace jointhb::timeint
