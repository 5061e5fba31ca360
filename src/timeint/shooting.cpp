// Shooting on the Newmark period map (shooting.hpp, docs/time-integration.md §9).
//
// The full state is z = (x, ẋ, F) of size 2n + n_c; Newton and the monodromy work on the reduced
// z_r = (x, ẋ, F of the contacts that slip), embedded by z = z* + E δz_r where a column of E for
// x_i also moves the force of every stuck contact c by k_c b_c[i] (TI-25: the slider stays), and
// restricted by R (dropping the stuck forces, which at a periodic x are periodic themselves).
// The Newton system is solved and the eigenvalues are computed in the variables scaled by the
// finite-difference scales (X, V, μF_N), a similarity that leaves the multipliers unchanged.
#include "jointhb/timeint/shooting.hpp"

#include "../support/lapack_eig.hpp"
#include "../support/stopwatch.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include "../support/numeric_constants.hpp"

namespace jointhb::timeint {
namespace {

using Vec = Eigen::VectorXd;
using support::Clock;
using support::seconds_since;

using support::group_change;

// One period from t = 0: the end state and what the residual and the classification need.
struct PeriodRun {
  bool ok = false;
  std::string message;
  Vec end;                            // full z(T)
  double x_max = 0.0;                 // largest |x| over the period (samples, both ends)
  double v_max = 0.0;                 // largest |ẋ|
  double f_max = 0.0;                 // largest |F|
  std::vector<double> contact_f_max;  // largest |F| per contact
  std::vector<double> dissipation;    // per contact
};

class PeriodMap {
 public:
  PeriodMap(const hb::DiscreteSystem& system, const hb::Excitation& excitation, double omega,
            const ShootingOptions& options)
      : system_(system),
        excitation_(excitation),
        omega_(omega),
        n_(system.dofs()),
        nc_(static_cast<int>(system.contacts.size())),
        steps_(options.steps_per_period) {
    period_ = 2.0 * std::numbers::pi / omega;
    scheme_ = options.integrator;
    scheme_.time_step = period_ / steps_;
    for (const auto& c : system.contacts) {
      limits_.push_back(c.slip_limit());
      elastic_below_limit_.push_back(hb::DiscreteSystem::make_law(c)->sticks_below_limit());
    }
  }

  [[nodiscard]] int size() const { return 2 * n_ + nc_; }
  [[nodiscard]] double period() const { return period_; }
  [[nodiscard]] double time_step() const { return scheme_.time_step; }
  [[nodiscard]] double limit(int c) const { return limits_[static_cast<std::size_t>(c)]; }
  [[nodiscard]] long count() const { return count_; }

  [[nodiscard]] Vec pack(const State& s) const {
    Vec z(size());
    z.head(n_) = s.displacement;
    z.segment(n_, n_) = s.velocity;
    for (int c = 0; c < nc_; ++c) z[2 * n_ + c] = s.contact_forces[static_cast<std::size_t>(c)];
    return z;
  }

  // The state at t = 0 (acceleration left empty: recomputed from the equation of motion).
  [[nodiscard]] State unpack(const Vec& z) const {
    State s;
    s.displacement = z.head(n_);
    s.velocity = z.segment(n_, n_);
    s.contact_forces.resize(static_cast<std::size_t>(nc_));
    for (int c = 0; c < nc_; ++c) s.contact_forces[static_cast<std::size_t>(c)] = z[2 * n_ + c];
    s.time = 0.0;
    return s;
  }

  // The perturbed periods of the monodromy see the contacts of `stuck` on their linear branch:
  // the same system with their slip limits raised 1e12-fold (TI-25; the nominal period, which
  // never reaches the limits of those contacts, is the same on it to the last bit).
  void set_linear_branch(const std::vector<int>& stuck) {
    if (stuck == linear_branch_) return;
    linear_branch_ = stuck;
    if (stuck.empty()) return;
    linear_system_ = system_;
    for (const int c : stuck) {
      linear_system_.contacts[static_cast<std::size_t>(c)].normal_force *= 1e12;
    }
  }

  // True when every contact force of z lies within its slip limit (for a perturbed period: the
  // contacts not on their linear branch).
  [[nodiscard]] bool admissible(const Vec& z, bool perturbed = false) const {
    for (int c = 0; c < nc_; ++c) {
      if (perturbed && on_linear_branch(c)) continue;
      if (std::abs(z[2 * n_ + c]) > limit(c)) return false;
    }
    return true;
  }

  void clamp_forces(Vec& z, bool perturbed = false) const {
    for (int c = 0; c < nc_; ++c) {
      if (perturbed && on_linear_branch(c)) continue;
      z[2 * n_ + c] = std::clamp(z[2 * n_ + c], -limit(c), limit(c));
    }
  }

  // A contact that can stick exactly (Jenkins) and dissipated nothing over the period.
  [[nodiscard]] bool stuck(const PeriodRun& run, int c) const {
    return elastic_below_limit_[static_cast<std::size_t>(c)] &&
           run.dissipation[static_cast<std::size_t>(c)] == 0.0;
  }

  // One period from z; `perturbed`: a perturbed period of the monodromy (set_linear_branch).
  PeriodRun run(Vec z, bool perturbed = false) {
    PeriodRun out;
    ++count_;
    if (!z.allFinite()) {
      out.message = "non-finite state";
      return out;
    }
    clamp_forces(z, perturbed);
    State s = unpack(z);
    out.contact_f_max.assign(static_cast<std::size_t>(nc_), 0.0);
    const auto track = [&](const State& x) {
      out.x_max = std::max(out.x_max, x.displacement.cwiseAbs().maxCoeff());
      out.v_max = std::max(out.v_max, x.velocity.cwiseAbs().maxCoeff());
      for (std::size_t c = 0; c < x.contact_forces.size(); ++c) {
        out.contact_f_max[c] = std::max(out.contact_f_max[c], std::abs(x.contact_forces[c]));
        out.f_max = std::max(out.f_max, out.contact_f_max[c]);
      }
    };
    track(s);
    const bool linear_branch = perturbed && !linear_branch_.empty();
    const TransientResult r = integrate(linear_branch ? linear_system_ : system_, excitation_,
                                        omega_, std::move(s), steps_, scheme_, track);
    if (r.termination == Termination::failed) {
      out.message = r.message;
      return out;
    }
    out.end = pack(r.final_state);
    if (!out.end.allFinite()) {
      out.message = "non-finite state at the end of the period";
      return out;
    }
    out.dissipation = r.contact_dissipation;
    out.ok = true;
    return out;
  }

  // TI-9's relative change of z over the period.
  [[nodiscard]] double residual(const Vec& z, const PeriodRun& run) const {
    const Vec d = run.end - z;
    double r = std::max(group_change(d.head(n_).cwiseAbs().maxCoeff(), run.x_max),
                        group_change(d.segment(n_, n_).cwiseAbs().maxCoeff(), run.v_max));
    if (nc_ > 0) r = std::max(r, group_change(d.tail(nc_).cwiseAbs().maxCoeff(), run.f_max));
    return r;
  }

  // Displacement and velocity scales of the differences: the period's, else from each other, else
  // the contacts' elastic range μF_N/k_T0, else 1.
  [[nodiscard]] std::pair<double, double> scales(const PeriodRun& run) const {
    double x = run.x_max;
    if (!(x > 0.0)) x = run.v_max / omega_;
    if (!(x > 0.0)) {
      for (const auto& c : system_.contacts) x = std::max(x, c.slip_limit() / c.stiffness);
    }
    if (!(x > 0.0)) x = 1.0;
    const double v = run.v_max > 0.0 ? run.v_max : omega_ * x;
    return {x, v};
  }

 private:
  const hb::DiscreteSystem& system_;
  const hb::Excitation& excitation_;
  double omega_;
  int n_, nc_, steps_;
  double period_ = 0.0;
  NewmarkOptions scheme_;
  std::vector<double> limits_;
  std::vector<bool> elastic_below_limit_;
  std::vector<int> linear_branch_;
  hb::DiscreteSystem linear_system_;  // system_ with the linear_branch_ contacts unlimited
  long count_ = 0;

  [[nodiscard]] bool on_linear_branch(int c) const {
    return std::find(linear_branch_.begin(), linear_branch_.end(), c) != linear_branch_.end();
  }
};

// The reduced coordinates of one iterate: E (as directions), R (as indices) and the scales.
struct Reduction {
  std::vector<int> full_index;     // R: full index of reduced component j
  std::vector<Vec> direction;      // E e_j in full coordinates
  Vec scale;                       // X, V or μF_N per reduced component
  std::vector<std::string> names;  // "x[i]", "v[i]", "F[c]"
  std::vector<int> stuck;          // eliminated contacts

  [[nodiscard]] Eigen::Index size() const { return scale.size(); }
  [[nodiscard]] Vec restrict(const Vec& full) const {
    Vec r(size());
    for (Eigen::Index j = 0; j < size(); ++j) r[j] = full[full_index[static_cast<std::size_t>(j)]];
    return r;
  }
  [[nodiscard]] Vec embed(const Vec& reduced) const {
    Vec f = Vec::Zero(direction.front().size());
    for (Eigen::Index j = 0; j < size(); ++j)
      f += reduced[j] * direction[static_cast<std::size_t>(j)];
    return f;
  }
};

Reduction reduce(const hb::DiscreteSystem& system, const PeriodMap& map, const PeriodRun& run) {
  const int n = system.dofs();
  const int nc = static_cast<int>(system.contacts.size());
  Reduction r;
  for (int c = 0; c < nc; ++c) {
    if (map.stuck(run, c)) r.stuck.push_back(c);
  }
  const auto [x_scale, v_scale] = map.scales(run);
  const int m = 2 * n + nc - static_cast<int>(r.stuck.size());
  r.scale.resize(m);
  int j = 0;
  for (int i = 0; i < 2 * n; ++i, ++j) {
    Vec u = Vec::Zero(map.size());
    u[i] = 1.0;
    if (i < n) {
      for (const int c : r.stuck) {  // TI-25: the stuck contact's slider stays put
        const auto& e = system.contacts[static_cast<std::size_t>(c)];
        if (e.dof_a == i) u[2 * n + c] += e.stiffness;
        if (e.dof_b == i) u[2 * n + c] -= e.stiffness;
      }
    }
    r.full_index.push_back(i);
    r.direction.push_back(std::move(u));
    r.scale[j] = i < n ? x_scale : v_scale;
    r.names.push_back(fmt::format("{}[{}]", i < n ? "x" : "v", i < n ? i : i - n));
  }
  for (int c = 0; c < nc; ++c) {
    if (std::find(r.stuck.begin(), r.stuck.end(), c) != r.stuck.end()) continue;
    Vec u = Vec::Zero(map.size());
    u[2 * n + c] = 1.0;
    r.full_index.push_back(2 * n + c);
    r.direction.push_back(std::move(u));
    r.scale[j++] = map.limit(c);
    r.names.push_back(fmt::format("F[{}]", c));
  }
  return r;
}

// Φ = R ∂P/∂z E by central differences, one-sided where a contact force would leave its range,
// with the stuck contacts on their linear branch (PeriodMap::set_linear_branch: a perturbation
// does not make them slip, also on an orbit that touches their limit, as after a shakedown).
// Empty with `message` set when a perturbed period fails.
Eigen::MatrixXd monodromy(PeriodMap& map, const Reduction& red, const Vec& z, const PeriodRun& run,
                          double perturbation, std::string& message) {
  const Eigen::Index m = red.size();
  Eigen::MatrixXd phi(m, m);
  const auto failure = [&](Eigen::Index j, const PeriodRun& r) {
    message = fmt::format("perturbed period ({}) failed: {}",
                          red.names[static_cast<std::size_t>(j)], r.message);
    return Eigen::MatrixXd();
  };
  for (Eigen::Index j = 0; j < m; ++j) {
    const double h = perturbation * red.scale[j];
    const Vec& u = red.direction[static_cast<std::size_t>(j)];
    const Vec zp = z + h * u;
    const Vec zm = z - h * u;
    const bool plus = map.admissible(zp, true);
    const bool minus = map.admissible(zm, true);
    Vec column;
    if (plus == minus) {  // both admissible, or (a corner) neither: central, forces clamped
      const PeriodRun a = map.run(zp, true);
      if (!a.ok) return failure(j, a);
      const PeriodRun b = map.run(zm, true);
      if (!b.ok) return failure(j, b);
      column = (a.end - b.end) / (2.0 * h);
    } else {
      const PeriodRun a = map.run(plus ? zp : zm, true);
      if (!a.ok) return failure(j, a);
      column = plus ? Vec((a.end - run.end) / h) : Vec((run.end - a.end) / h);
    }
    phi.col(j) = red.restrict(column);
  }
  return phi;
}

constexpr int kHalvings = 12;   // step halvings of a Newton step before cycling
constexpr double kNear = 1e-6;  // residual below which a Newton step without decrease stops

std::string stuck_list(const std::vector<int>& stuck) {
  if (stuck.empty()) return "no stuck contacts";
  return fmt::format("stuck contacts [{}] eliminated", fmt::join(stuck, ", "));
}

}  // namespace

std::string ShootingOptions::validate() const {
  if (steps_per_period < 4) {
    return fmt::format("steps_per_period: must be >= 4, got {}", steps_per_period);
  }
  if (max_newton_iterations < 0) {
    return fmt::format("max_newton_iterations: must be >= 0, got {}", max_newton_iterations);
  }
  if (!(tolerance > 0.0 && tolerance <= 1e-2)) {
    return fmt::format("tolerance: must lie in (0, 1e-2], got {}", tolerance);
  }
  if (!(perturbation > 0.0 && perturbation <= 1e-2)) {
    return fmt::format("perturbation: must lie in (0, 1e-2], got {}", perturbation);
  }
  if (max_cycled_periods < 0) {
    return fmt::format("max_cycled_periods: must be >= 0, got {}", max_cycled_periods);
  }
  NewmarkOptions scheme = integrator;
  scheme.time_step = 1.0;  // replaced by T/N
  if (const std::string msg = scheme.validate(); !msg.empty()) return "integrator." + msg;
  return {};
}

ShootingResult periodic_orbit_by_shooting(const hb::DiscreteSystem& system,
                                          const hb::Excitation& excitation, double omega,
                                          State initial, const ShootingOptions& options) {
  const auto start = Clock::now();
  if (const std::string msg = options.validate(); !msg.empty()) {
    throw std::invalid_argument("shooting options: " + msg);
  }
  if (!(omega > 0.0) || !std::isfinite(omega)) {
    throw std::invalid_argument(
        fmt::format("shooting: omega must be finite and > 0, got {}", omega));
  }
  for (std::size_t c = 0; c < system.contacts.size(); ++c) {
    if (system.contacts[c].normal()) {  // the period map carries friction forces as states
      throw std::invalid_argument(fmt::format(
          "shooting: contacts[{}] is a normal element (normal-exponential), which shooting does not "
          "take yet; integrate with timeint::integrate or use harmonic balance", c));
    }
  }
  PeriodMap map(system, excitation, omega, options);
  ShootingResult result;
  result.period = map.period();
  result.time_step = map.time_step();

  // Complete and check the guess (sizes, forces within their limits, system, excitation): zero
  // steps of the integrator, which throws std::invalid_argument on invalid input.
  initial.time = 0.0;
  initial.acceleration.resize(0);
  NewmarkOptions scheme = options.integrator;
  scheme.time_step = map.time_step();
  Vec z = map.pack(integrate(system, excitation, omega, std::move(initial), 0, scheme).final_state);

  const auto finish = [&](Termination termination, std::string message) {
    result.termination = termination;
    result.message = std::move(message);
    Vec zc = z;
    map.clamp_forces(zc);
    result.orbit_start =
        integrate(system, excitation, omega, map.unpack(zc), 0, scheme).final_state;
    result.period_maps = map.count();
    result.seconds = seconds_since(start);
    return result;
  };

  PeriodRun run = map.run(z);
  if (!run.ok)
    return finish(Termination::failed, "period map at the initial state: " + run.message);
  result.residual = map.residual(z, run);

  // The monodromy of the current iterate into the result (multipliers by modulus descending).
  const auto store = [&](const Eigen::MatrixXd& phi, const Eigen::MatrixXd& phi_s,
                         const Reduction& red) {
    result.monodromy = phi;
    result.components = red.names;
    result.stuck_contacts = red.stuck;
    result.stuck_margins.clear();
    for (const int c : red.stuck) {
      result.stuck_margins.push_back(1.0 -
                                     run.contact_f_max[static_cast<std::size_t>(c)] / map.limit(c));
    }
    // Balanced QR (support/lapack_eig.hpp): the state mixes displacements, velocities and forces.
    const support::EigenDecomposition eig = support::eigen_decomposition(phi_s, false);
    if (!eig.ok) return false;
    std::vector<std::complex<double>> rho(eig.values.begin(), eig.values.end());
    std::sort(rho.begin(), rho.end(), [](const auto& a, const auto& b) {
      if (std::abs(a) != std::abs(b)) return std::abs(a) > std::abs(b);
      return a.imag() > b.imag();
    });
    result.multipliers =
        Eigen::Map<const Eigen::VectorXcd>(rho.data(), static_cast<Eigen::Index>(rho.size()));
    result.spectral_radius = std::abs(rho.front());
    return true;
  };

  const auto clear_monodromy = [&] {  // nothing of an earlier iterate is reported
    result.monodromy.resize(0, 0);
    result.multipliers.resize(0);
    result.spectral_radius = 0.0;
    result.components.clear();
    result.stuck_contacts.clear();
    result.stuck_margins.clear();
  };

  std::string stop;  // non-empty: stop with no_convergence once the monodromy of z is stored
  for (int attempt = 0;; ++attempt) {
    const Reduction red = reduce(system, map, run);
    map.set_linear_branch(red.stuck);
    std::string message;
    const Eigen::MatrixXd phi = monodromy(map, red, z, run, options.perturbation, message);
    if (phi.size() == 0) {
      clear_monodromy();
      return finish(Termination::failed,
                    fmt::format("Newton iteration {}: {}", result.newton_iterations, message));
    }
    // Scaled: Φ_s = S⁻¹ Φ S, the same multipliers.
    const Vec& s = red.scale;
    const Eigen::MatrixXd phi_s = s.cwiseInverse().asDiagonal() * phi * s.asDiagonal();
    if (!store(phi, phi_s, red)) {
      return finish(Termination::failed, "eigenvalues of the monodromy did not converge");
    }
    const std::string cycled = result.cycled_periods > 0
                                   ? fmt::format(" and {} cycled periods", result.cycled_periods)
                                   : std::string();
    if (result.residual <= options.tolerance) {
      return finish(Termination::converged,
                    fmt::format("periodic orbit after {} Newton iterations{} (residual {:.2e}); "
                                "{} multipliers, max |rho| = {:.9g}; {}",
                                result.newton_iterations, cycled, result.residual, red.size(),
                                result.spectral_radius, stuck_list(red.stuck)));
    }
    if (!stop.empty()) return finish(Termination::no_convergence, stop);
    if (attempt == options.max_newton_iterations) {
      return finish(
          Termination::no_convergence,
          fmt::format("no periodic orbit after {} Newton iterations{}: residual {:.2e} > "
                      "tolerance {:.2e}",
                      result.newton_iterations, cycled, result.residual, options.tolerance));
    }

    // Newton step in scaled reduced variables: (Φ_s − I) y = −S⁻¹ R (P(z) − z), δ = S y.
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(
        phi_s - Eigen::MatrixXd::Identity(red.size(), red.size()));
    const double rcond = lu.rcond();
    if (!(rcond > 1e-14)) {
      return finish(Termination::failed,
                    fmt::format("Newton iteration {}: Phi - I is singular (reciprocal condition "
                                "{:.2e}): a multiplier at 1, the orbit is not isolated",
                                result.newton_iterations, rcond));
    }
    const Vec y = lu.solve(-(s.cwiseInverse().asDiagonal() * red.restrict(run.end - z)));
    const Vec step = red.embed(s.asDiagonal() * y);
    if (!step.allFinite()) {
      return finish(Termination::failed,
                    fmt::format("Newton iteration {}: non-finite step", result.newton_iterations));
    }
    // Step halving until the residual falls (the full step near the orbit).
    bool accepted = false;
    for (int k = 0; k < kHalvings && !accepted; ++k) {
      Vec trial = z + std::ldexp(1.0, -k) * step;
      map.clamp_forces(trial);
      PeriodRun trial_run = map.run(trial);
      if (!trial_run.ok) continue;
      const double r = map.residual(trial, trial_run);
      if (r < result.residual) {
        z = std::move(trial);
        run = std::move(trial_run);
        result.residual = r;
        accepted = true;
      }
    }
    if (accepted) {
      ++result.newton_iterations;
      continue;
    }
    if (result.residual <= kNear) {
      // Near the orbit the linearisation holds: no decrease means the residual has reached the
      // round-off of the period map (or a switch kink), which cycling would not cure.
      return finish(Termination::no_convergence,
                    fmt::format("the residual stalls at {:.2e} > tolerance {:.2e} after {} Newton "
                                "iterations{} (round-off of the period map at N = {}?)",
                                result.residual, options.tolerance, result.newton_iterations,
                                cycled, options.steps_per_period));
    }
    if (options.max_cycled_periods == 0) {
      return finish(
          Termination::failed,
          fmt::format("Newton iteration {}: no decrease of the residual {:.2e} "
                      "(tolerance {:.2e}) in {} step halvings",
                      result.newton_iterations, result.residual, options.tolerance, kHalvings));
    }
    // No decrease along the Newton direction (far from the orbit, where the switches differ from
    // the linearisation's): integrate whole periods, z ← P(z), until the residual halves.
    const double target = 0.5 * result.residual;
    while (result.residual > target) {
      if (result.cycled_periods == options.max_cycled_periods) {
        stop = fmt::format(
            "no periodic orbit: Newton steps stopped decreasing the residual and "
            "max_cycled_periods = {} periods did not halve it (residual {:.2e} after "
            "{} Newton iterations)",
            options.max_cycled_periods, result.residual, result.newton_iterations);
        break;
      }
      Vec next = run.end;
      map.clamp_forces(next);
      PeriodRun next_run = map.run(next);
      ++result.cycled_periods;
      if (!next_run.ok) {
        z = std::move(next);
        clear_monodromy();
        return finish(Termination::failed,
                      fmt::format("cycled period {}: {}", result.cycled_periods, next_run.message));
      }
      z = std::move(next);
      run = std::move(next_run);
      result.residual = map.residual(z, run);
    }
  }
}

}  // namespace jointhb::timeint
