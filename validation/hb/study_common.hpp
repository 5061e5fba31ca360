#pragma once
// Shared helpers of the harmonic-balance validation studies linear_limit, convergence, stress and
// cost (validation/hb/README_convergence.md): model builders, the independent stuck receptance, a
// damped Newton method at fixed Ω (with an optional forcing phase), harmonic padding and time
// shifts of coefficient vectors, observed rates, CSV output and a scorecard of bounds.
//
// Everything here is written for the studies only and uses the library's public API; the
// references it computes (the complex receptance, the fixed-Ω Newton) share no code with the
// continuation they are compared with.

#include <fmt/format.h>
#include <fmt/os.h>

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
#include <tuple>
#include <utility>
#include <vector>

#include "jointhb/continuation/frf.hpp"
#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/hb/fourier.hpp"
#include "jointhb/hb/harmonic_balance.hpp"
#include "jointhb/contact/periodic_state.hpp"
#include "jointhb/timeint/newmark.hpp"
#include "study_arguments.hpp"

namespace validation_study {

namespace hb = jointhb::hb;
namespace cont = jointhb::continuation;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using Clock = std::chrono::steady_clock;

constexpr double kPi = std::numbers::pi;
constexpr double kEps = std::numeric_limits<double>::epsilon();

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// ---------------------------------------------------------------------------------------------
// Scorecard: every bound is checked through it; a failure prints one line and fails the run.
// ---------------------------------------------------------------------------------------------

class Scorecard {
 public:
  // Records `passed`; on failure prints "FAIL <what>" to stderr.
  bool check(bool passed, const std::string& what) {
    ++checks_;
    if (!passed) {
      ++failures_;
      fmt::print(stderr, "FAIL {}\n", what);
    }
    return passed;
  }
  [[nodiscard]] int checks() const { return checks_; }
  [[nodiscard]] int failures() const { return failures_; }
  // Prints the verdict and returns the exit code.
  int finish() const {
    fmt::print("\n{} checks, {} failed: {}\n", checks_, failures_, failures_ ? "FAILED" : "PASSED");
    return failures_ ? 1 : 0;
  }

 private:
  int checks_ = 0;
  int failures_ = 0;
};

// ---------------------------------------------------------------------------------------------
// CSV: a header and rows of already formatted fields; strings are quoted when needed.
// ---------------------------------------------------------------------------------------------

inline std::string csv_text(std::string s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c == '\n' ? ' ' : c;
  }
  return q + "\"";
}

inline std::string csv_number(double v) { return fmt::format("{:.17g}", v); }

class Csv {
 public:
  Csv(const std::string& path, const std::vector<std::string>& columns)
      : path_(path), out_(fmt::output_file(path)), columns_(columns.size()) {
    std::string line;
    for (std::size_t i = 0; i < columns.size(); ++i) line += (i ? "," : "") + columns[i];
    out_.print("{}\n", line);
  }
  void row(const std::vector<std::string>& fields) {
    if (fields.size() != columns_) {
      throw std::logic_error(
          fmt::format("{}: row of {} fields, header has {}", path_, fields.size(), columns_));
    }
    std::string line;
    for (std::size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + fields[i];
    out_.print("{}\n", line);
    out_.flush();
  }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  std::string path_;
  fmt::ostream out_;
  std::size_t columns_;
};

// ---------------------------------------------------------------------------------------------
// Observed rates
// ---------------------------------------------------------------------------------------------

// Least-squares slope of log y against log x over the pairs with y > 0 (NaN when fewer than two).
inline double loglog_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int count = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(x[i] > 0.0 && y[i] > 0.0)) continue;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
    ++count;
  }
  if (count < 2) return std::numeric_limits<double>::quiet_NaN();
  return (count * sxy - sx * sy) / (count * sxx - sx * sx);
}

// Slope between consecutive pairs, log(y_i/y_{i-1}) / log(x_i/x_{i-1}) (NaN for the first).
inline double local_slope(const std::vector<double>& x, const std::vector<double>& y,
                          std::size_t i) {
  if (i == 0 || !(y[i] > 0.0 && y[i - 1] > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return std::log(y[i] / y[i - 1]) / std::log(x[i] / x[i - 1]);
}

inline double rel(double value, double reference) { return std::abs(value / reference - 1.0); }

// ---------------------------------------------------------------------------------------------
// Models
// ---------------------------------------------------------------------------------------------

inline hb::SparseMatrix sparse(const MatrixXd& a) { return a.sparseView(); }

struct ContactSpec {
  std::string law = "jenkins";  // "jenkins" | "gaul-mayer"
  double exponent = 1.0 / 3.0;  // n (gaul-mayer)
  double stiffness = 1.0;       // k_T0 [N/m]
  double slip_limit = 1.0;      // μ F_N [N] (μ = 1, F_N = slip limit)
};

inline hb::ContactElement contact_element(const ContactSpec& spec, int dof_a, int dof_b = -1) {
  hb::ContactElement c;
  c.law = spec.law;
  c.exponent = spec.exponent;
  c.dof_a = dof_a;
  c.dof_b = dof_b;
  c.friction_coefficient = 1.0;
  c.normal_force = spec.slip_limit;
  c.stiffness = spec.stiffness;
  return c;
}

// m ẍ + c ẋ + k x + F_T = F cos Ωt, one contact to ground; c = 2 ζ √((k + k_T0) m): ζ is the
// damping ratio of the stuck system.
inline hb::DiscreteSystem oscillator(const ContactSpec& spec, double zeta, double mass = 1.0,
                                     double stiffness = 1.0) {
  hb::DiscreteSystem s;
  s.mass = sparse(MatrixXd::Constant(1, 1, mass));
  s.stiffness = sparse(MatrixXd::Constant(1, 1, stiffness));
  s.damping =
      sparse(MatrixXd::Constant(1, 1, 2.0 * zeta * std::sqrt((stiffness + spec.stiffness) * mass)));
  s.contacts.push_back(contact_element(spec, 0));
  return s;
}

// A chain of n unit masses, x_0 tied to ground and x_i to x_{i-1} by springs k; `contacts` lists
// (dof_a, dof_b) pairs (dof_b = -1: ground); damping is modal, ratio ζ on every mode of the stuck
// system (K + Σ k_T0).
inline hb::DiscreteSystem chain(int n, double k, const ContactSpec& spec,
                                const std::vector<std::pair<int, int>>& contacts, double zeta) {
  MatrixXd kk = MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    kk(i, i) += k;
    if (i > 0) {
      kk(i - 1, i - 1) += k;
      kk(i, i - 1) -= k;
      kk(i - 1, i) -= k;
    }
  }
  hb::DiscreteSystem s;
  s.mass = sparse(MatrixXd::Identity(n, n));
  s.stiffness = sparse(kk);
  for (const auto& [a, b] : contacts) s.contacts.push_back(contact_element(spec, a, b));
  s.damping = hb::modal_damping_matrix(s.mass, hb::stuck_stiffness(s),
                                       std::vector<double>(static_cast<std::size_t>(n), zeta));
  return s;
}

inline hb::Excitation cosine_force(int dof, double amplitude) {
  hb::Excitation e;
  e.forces.push_back({dof, amplitude, 1});
  return e;
}

// ---------------------------------------------------------------------------------------------
// Independent reference: the complex receptance of the stuck linear system
//   X = (K + Σ k_T0 − Ω² M + iΩ C)^{-1} F,   x(t) = Re(X e^{iΩt}),
// assembled here from the system's matrices and contact list (dense complex LU).
// ---------------------------------------------------------------------------------------------

// K + Σ k_T0 (every contact's spring stuck), dense, assembled from the contact list.
inline MatrixXd stuck_stiffness_matrix(const hb::DiscreteSystem& s) {
  MatrixXd k = MatrixXd(s.stiffness);
  for (const auto& c : s.contacts) {
    k(c.dof_a, c.dof_a) += c.stiffness;
    if (c.dof_b >= 0) {
      k(c.dof_b, c.dof_b) += c.stiffness;
      k(c.dof_a, c.dof_b) -= c.stiffness;
      k(c.dof_b, c.dof_a) -= c.stiffness;
    }
  }
  return k;
}

inline Eigen::VectorXcd stuck_receptance(const hb::DiscreteSystem& s, const hb::Excitation& e,
                                         double omega) {
  const int n = s.dofs();
  const MatrixXd k = stuck_stiffness_matrix(s);
  const MatrixXd m = MatrixXd(s.mass);
  const MatrixXd c = s.damping.nonZeros() ? MatrixXd(s.damping) : MatrixXd::Zero(n, n);
  const Eigen::MatrixXcd d = (k - omega * omega * m).cast<std::complex<double>>() +
                             std::complex<double>(0.0, omega) * c.cast<std::complex<double>>();
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(n);
  for (const auto& h : e.forces) {
    if (h.harmonic == 1) f[h.dof] += h.amplitude;
  }
  return d.fullPivLu().solve(f);
}

// ---------------------------------------------------------------------------------------------
// Coefficient vectors
// ---------------------------------------------------------------------------------------------

// X of `to` from X of `from`: common harmonics copied per DOF, the others zero.
inline VectorXd pad(const hb::HarmonicBalance& from, const VectorXd& x,
                    const hb::HarmonicBalance& to) {
  return hb::transfer_coefficients(from.basis(), to.basis(), x, to.system().dofs());
}

// Value and time derivative at t = 0 of every DOF, the contact forces of the law's periodic state
// along the harmonic-balance path at t = 0.
inline jointhb::timeint::State initial_state(const hb::HarmonicBalance& b,
                                             const hb::DiscreteSystem& system, const VectorXd& x,
                                             double omega) {
  const hb::FourierBasis& basis = b.basis();
  const int n = system.dofs();
  jointhb::timeint::State st;
  st.displacement = VectorXd::Zero(n);
  st.velocity = VectorXd::Zero(n);
  for (int dof = 0; dof < n; ++dof) {
    if (basis.has_mean()) st.displacement[dof] += x[b.index(dof, 0)];
    for (int k : basis.orders()) {
      const int a = basis.cosine_index(k);
      st.displacement[dof] += x[b.index(dof, a)];
      st.velocity[dof] += k * omega * x[b.index(dof, a + 1)];
    }
  }
  constexpr int kPathSamples = 4096;
  for (const auto& c : system.contacts) {
    jointhb::contact::PeriodicPath path;
    path.slip.resize(kPathSamples);
    path.limits.assign(kPathSamples, {c.slip_limit(), c.stiffness});
    for (int i = 0; i < kPathSamples; ++i) {
      const double theta = 2.0 * kPi * i / kPathSamples;
      double g = 0.0;
      for (int side = 0; side < 2; ++side) {
        const int dof = side == 0 ? c.dof_a : c.dof_b;
        if (dof < 0) continue;
        double v = basis.has_mean() ? x[b.index(dof, 0)] : 0.0;
        for (int k : basis.orders()) {
          const int a = basis.cosine_index(k);
          v += x[b.index(dof, a)] * std::cos(k * theta) +
               x[b.index(dof, a + 1)] * std::sin(k * theta);
        }
        g += side == 0 ? v : -v;
      }
      path.slip[static_cast<std::size_t>(i)] = jointhb::contact::Vec2(g, 0.0);
    }
    jointhb::contact::PeriodicStateOptions po;
    po.keep_step_derivatives = false;
    po.reference_traction = jointhb::contact::Vec2(c.reference_force, 0.0);
    po.reference_slip = jointhb::contact::Vec2(c.reference_slip, 0.0);
    const auto law = hb::DiscreteSystem::make_law(c);
    const jointhb::contact::PeriodicStateResult ps = jointhb::contact::solve_periodic_state(*law, path, po);
    const double limit = c.slip_limit();
    st.contact_forces.push_back(std::clamp(ps.traction.front().x(), -limit, limit));
  }
  st.time = 0.0;
  return st;
}

// The coefficients of y(θ) = x(θ + θ0) for every DOF (a time shift by θ0/Ω).
inline VectorXd shift_phase(const hb::HarmonicBalance& balance, const VectorXd& x, double theta0) {
  VectorXd y = x;
  const int n = balance.system().dofs();
  for (int dof = 0; dof < n; ++dof) {
    for (int k : balance.basis().orders()) {
      const Index a = balance.index(dof, balance.basis().cosine_index(k));
      const double c = std::cos(k * theta0), s = std::sin(k * theta0);
      y[a] = x[a] * c + x[a + 1] * s;
      y[a + 1] = x[a + 1] * c - x[a] * s;
    }
  }
  return y;
}

// Phase θ ∈ [0, 2π) of the maximum of one signal given by its coefficients (fine grid, then
// Newton on x'(θ) = 0 to round-off).
inline double maximum_phase(const hb::FourierBasis& basis, const VectorXd& c) {
  const auto derivative = [&](double theta, int d) {
    double v = d == 0 && basis.has_mean() ? c[0] : 0.0;
    for (int k : basis.orders()) {
      const int a = basis.cosine_index(k);
      const double ck = std::cos(k * theta), sk = std::sin(k * theta);
      if (d == 0) v += c[a] * ck + c[a + 1] * sk;
      if (d == 1) v += k * (-c[a] * sk + c[a + 1] * ck);
      if (d == 2) v -= k * k * (c[a] * ck + c[a + 1] * sk);
    }
    return v;
  };
  const int grid = std::max(4096, 16 * basis.harmonics());
  double best = -std::numeric_limits<double>::infinity(), theta = 0.0;
  for (int i = 0; i < grid; ++i) {
    const double t = 2.0 * kPi * i / grid;
    if (const double v = derivative(t, 0); v > best) {
      best = v;
      theta = t;
    }
  }
  for (int it = 0; it < 50; ++it) {
    const double d2 = derivative(theta, 2);
    if (!(d2 < 0.0)) break;
    const double step = -derivative(theta, 1) / d2;
    theta += step;
    if (std::abs(step) <= 1e-16 * (1.0 + std::abs(theta))) break;
  }
  theta = std::fmod(theta, 2.0 * kPi);
  return theta < 0.0 ? theta + 2.0 * kPi : theta;
}

// ---------------------------------------------------------------------------------------------
// Damped Newton method for R(X, Ω) = 0 at fixed Ω. `forcing_phase` φ replaces the excitation's
// cos Ωt terms by cos(Ωt + φ) (the library's forcing is pure cosine; R changes by a constant, the
// Jacobian not at all).
// ---------------------------------------------------------------------------------------------

struct NewtonOptions {
  int max_iterations = 80;
  double residual_tolerance = 1e-13;  // ‖R‖_∞ / force_scale at convergence
  double step_tolerance = 1e-14;  // or ‖ΔX‖_∞ / ‖X‖_∞ below this with ‖R‖ ≤ 1e3 tol
  double forcing_phase = 0.0;     // φ [rad]
};

struct NewtonResult {
  VectorXd x;
  bool converged = false;
  int iterations = 0;
  double residual = 0.0;  // ‖R‖_∞ / force_scale at x
  std::string message;
  hb::HarmonicBalanceEvaluation evaluation;  // at x (without Jacobian)
};

// The change of F_ex when the cos terms of harmonic 1 get the phase φ: F_lib − F_φ (added to R).
inline VectorXd forcing_shift(const hb::HarmonicBalance& balance, double phi) {
  VectorXd shift = VectorXd::Zero(balance.unknowns());
  if (phi == 0.0) return shift;
  const VectorXd& f = balance.forcing();
  const int a = balance.basis().cosine_index(1);
  for (int dof = 0; dof < balance.system().dofs(); ++dof) {
    const double amplitude = f[balance.index(dof, a)];
    // cos(θ + φ) = cos φ cos θ − sin φ sin θ
    shift[balance.index(dof, a)] = amplitude - amplitude * std::cos(phi);
    shift[balance.index(dof, a + 1)] = amplitude * std::sin(phi);
  }
  return shift;
}

inline double force_scale(const hb::HarmonicBalance& balance) {
  const double f = balance.forcing().lpNorm<Eigen::Infinity>();
  return f > 0.0 ? f : 1.0;
}

inline NewtonResult solve_at_omega(const hb::HarmonicBalance& balance, VectorXd x, double omega,
                                   const NewtonOptions& options = {}) {
  NewtonResult out;
  const VectorXd shift = forcing_shift(balance, options.forcing_phase);
  const double scale = force_scale(balance);
  hb::HarmonicBalanceEvaluation ev;
  const auto residual_norm = [&](const VectorXd& y, bool jacobian) {
    balance.evaluate(y, omega, jacobian, ev);
    ev.residual += shift;
    return ev.ok ? ev.residual.lpNorm<Eigen::Infinity>() / scale
                 : std::numeric_limits<double>::infinity();
  };
  double norm = residual_norm(x, true);
  double last_step = std::numeric_limits<double>::infinity();
  for (int it = 0;; ++it) {
    if (!std::isfinite(norm)) {
      out.message = ev.ok ? "non-finite residual" : ev.message;
      break;
    }
    if (norm <= options.residual_tolerance ||
        (last_step <= options.step_tolerance && norm <= 1e3 * options.residual_tolerance)) {
      out.converged = true;
      out.iterations = it;
      break;
    }
    if (it == options.max_iterations) {
      out.message = fmt::format("no convergence in {} iterations (residual {:.3g})", it, norm);
      out.iterations = it;
      break;
    }
    const VectorXd dx = ev.d_coefficients.partialPivLu().solve(-ev.residual);
    const double merit = ev.residual.norm();
    double alpha = 1.0;
    VectorXd trial;
    double trial_norm = 0.0;
    bool accepted = false;
    for (int halving = 0; halving <= 20 && !accepted; ++halving, alpha *= 0.5) {
      trial = x + alpha * dx;
      trial_norm = residual_norm(trial, true);
      if (!std::isfinite(trial_norm)) continue;
      // Armijo decrease of ‖R‖₂; near round-off the merit cannot decrease any more, so a full
      // step that lands within the tolerance band is kept (the step test then ends the run).
      accepted = ev.residual.norm() <= (1.0 - 0.25 * alpha) * merit ||
                 (halving == 0 && trial_norm <= 1e3 * options.residual_tolerance);
      if (accepted) break;
    }
    if (!accepted) {
      out.message = fmt::format("no decrease of the residual {:.3g} along the Newton step", norm);
      out.iterations = it;
      break;
    }
    last_step =
        (alpha * dx).lpNorm<Eigen::Infinity>() / std::max(x.lpNorm<Eigen::Infinity>(), 1e-300);
    x = trial;
    norm = trial_norm;
  }
  out.x = x;
  balance.evaluate(x, omega, false, out.evaluation);
  out.evaluation.residual += shift;
  out.residual = out.evaluation.residual.lpNorm<Eigen::Infinity>() / scale;
  return out;
}

// Solves at fixed Ω with the forcing phase chosen so that the maximum of DOF `dof` falls at
// θ = target (θ = 0: on a time sample for every N_t, and with half-wave symmetry the minimum at
// θ = π too; θ = π/N_t: half-way between two samples). Starts from `x` (forcing phase `phase`)
// and updates the phase. A few realignments are enough: the solution only moves by the
// difference between the sampled problems.
inline NewtonResult solve_aligned(const hb::HarmonicBalance& balance, VectorXd x, double omega,
                                  double& phase, int dof, double target = 0.0,
                                  NewtonOptions options = {}) {
  NewtonResult r;
  int iterations = 0;
  for (int pass = 0; pass < 4; ++pass) {
    options.forcing_phase = phase;
    r = solve_at_omega(balance, x, omega, options);
    iterations += r.iterations;
    r.iterations = iterations;
    if (!r.converged) return r;
    const hb::FourierBasis& b = balance.basis();
    double delta = maximum_phase(b, r.x.segment(balance.index(dof, 0), b.size())) - target;
    delta = std::remainder(delta, 2.0 * kPi);
    if (std::abs(delta) <= 1e-13) break;
    // y(θ) = x(θ + δ) has its maximum at the target and solves the problem with forcing
    // cos(θ + φ + δ).
    x = shift_phase(balance, r.x, delta);
    phase += delta;
  }
  return r;
}

// Maximum of a unimodal f on [lo, hi] by golden-section search to |hi − lo| ≤ tolerance;
// NaN when f returns NaN.
template <class F>
std::pair<double, double> golden_maximum(F f, double lo, double hi, double tolerance) {
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
  double fa = f(a), fb = f(b);
  while (hi - lo > tolerance) {
    if (!(std::isfinite(fa) && std::isfinite(fb))) {
      return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    }
    if (fa > fb) {
      hi = b;
      b = a;
      fb = fa;
      a = hi - g * (hi - lo);
      fa = f(a);
    } else {
      lo = a;
      a = b;
      fa = fb;
      b = lo + g * (hi - lo);
      fb = f(b);
    }
  }
  return fa > fb ? std::pair{a, fa} : std::pair{b, fb};
}

// ---------------------------------------------------------------------------------------------
// FRF helpers
// ---------------------------------------------------------------------------------------------

// max_i amplitude_h1 of a curve's points and its index.
inline std::size_t peak_index(const cont::FrfCurve& curve) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < curve.points.size(); ++i) {
    if (curve.points[i].amplitude_h1 > curve.points[best].amplitude_h1) best = i;
  }
  return best;
}

struct Peak {
  double omega = 0.0;
  double amplitude = 0.0;  // |fundamental| of the output DOF
  bool ok = false;
  std::string message;
};

// The maximum of |X_1|(Ω) of the branch through the curve's highest point, by golden-section
// search on [Ω_{i-1}, Ω_{i+1}] with fixed-Ω Newton solves (each continued from the last solution).
// Valid where the branch is single-valued in Ω around the peak (no fold there: the caller checks
// the curve's fold flags).
inline Peak refine_peak(const hb::HarmonicBalance& balance, const cont::FrfCurve& curve,
                        int output_dof, double omega_tolerance = 1e-7) {
  Peak p;
  const std::size_t i = peak_index(curve);
  if (curve.points.size() < 3 || i == 0 || i + 1 == curve.points.size()) {
    p.message = "peak at an end of the curve";
    return p;
  }
  VectorXd guess = curve.points[i].coefficients;
  NewtonOptions no;
  no.residual_tolerance = 1e-12;
  const auto amplitude = [&](double omega) {
    const NewtonResult r = solve_at_omega(balance, guess, omega, no);
    if (!r.converged) {
      p.message = fmt::format("Newton at Ω = {} failed: {}", omega, r.message);
      return std::numeric_limits<double>::quiet_NaN();
    }
    guess = r.x;
    return balance.fundamental_amplitude(r.x, output_dof);
  };
  const double lo = curve.points[i - 1].omega, hi = curve.points[i + 1].omega;
  std::tie(p.omega, p.amplitude) =
      golden_maximum(amplitude, std::min(lo, hi), std::max(lo, hi), omega_tolerance * std::abs(hi));
  p.ok = std::isfinite(p.amplitude);
  return p;
}

}  // namespace validation_study
