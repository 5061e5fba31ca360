// Newmark / HHT-α integration of the discrete system with exact contact increments (newmark.hpp).
//
// Step n → n+1 with c0 = 1/(βΔt²), c1 = γ/(βΔt), and the unknown x = x_{n+1}:
//   a(x) = c0 (x - x_n) - v_n/(βΔt) - (1/(2β) - 1) a_n,   v(x) = v_n + Δt[(1-γ) a_n + γ a(x)]
//   r(x) = M a(x) + (1+α)(C v(x) + K x + B F(x)) - α(C v_n + K x_n + B F_n)
//          - (1+α) f_ex(t_{n+1}) + α f_ex(t_n)
//        = q0 + S (x - x_n) + (1+α) B F(x),         S = c0 M + (1+α)(c1 C + K),
// where B F = Σ_c F_c (e_a - e_b) and F_c(x) = scalar_step(F_c,n, g_c(x) - g_c(x_n)).
// Each F_c is non-decreasing in its increment (∂F/∂Δg ∈ [0, k_T0]), so r is the gradient of the
// strictly convex ψ(x) = ½ΔxᵀSΔx + q0ᵀΔx + (1+α) Σ_c ∫F_c dg: the Newton direction
// d = -J⁻¹r (J = S + (1+α) Σ_c ∂F_c/∂Δg b_c b_cᵀ, positive definite) is a descent direction of ψ,
// and φ'(λ) = r(x + λd)ᵀd is non-decreasing along it. When the full step does not reduce ‖r‖,
// the step length is the root of φ' in (0, 1] (regula falsi): ψ decreases in every iteration, so
// Newton cannot cycle between the stuck and sliding tangents.
#include "jointhb/timeint/newmark.hpp"

#include "period_harmonics.hpp"
#include "../support/stopwatch.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "../support/numeric_constants.hpp"
#include "jointhb/contact/preloaded_normal_law.hpp"

namespace jointhb::timeint {
namespace {

using hb::SparseMatrix;
using Vec = Eigen::VectorXd;
using support::Clock;
using support::seconds_since;
using support::kEps;

std::vector<double> reference_forces(const hb::DiscreteSystem& system, const Vec& x) {
  std::vector<double> f;
  f.reserve(system.contacts.size());
  for (const auto& c : system.contacts) {
    const double limit = c.slip_limit();
    if (c.normal()) {  // elastic (N-3): the force of the gap itself
      f.push_back(contact::PreloadedNormalLaw::force(c.gap(x), c.normal_force, c.stiffness));
      continue;
    }
    f.push_back(
        std::clamp(c.reference_force + c.stiffness * (c.gap(x) - c.reference_slip), -limit, limit));
  }
  return f;
}

void check_system(const hb::DiscreteSystem& system, const hb::Excitation& excitation) {
  if (const std::string msg = system.validate(); !msg.empty()) {
    throw std::invalid_argument("time integration: system " + msg);
  }
  const int n = system.dofs();
  if (excitation.static_force.size() != 0 && excitation.static_force.size() != n) {
    throw std::invalid_argument(
        fmt::format("time integration: excitation static_force must have {} entries, got {}", n,
                    excitation.static_force.size()));
  }
  if (!excitation.static_force.allFinite()) {
    throw std::invalid_argument("time integration: excitation static_force must be finite");
  }
  for (std::size_t j = 0; j < excitation.forces.size(); ++j) {
    const auto& h = excitation.forces[j];
    if (h.dof < 0 || h.dof >= n || h.harmonic < 1 || !std::isfinite(h.amplitude)) {
      throw std::invalid_argument(fmt::format(
          "time integration: excitation forces[{}] needs dof in [0, {}], harmonic >= 1 and a "
          "finite amplitude, got dof {}, harmonic {}, amplitude {}",
          j, n - 1, h.dof, h.harmonic, h.amplitude));
    }
  }
}

void check_state(const State& s, const hb::DiscreteSystem& system) {
  const auto n = static_cast<Eigen::Index>(system.dofs());
  const auto check = [&](const Vec& v, const char* name, bool may_be_empty) {
    if (may_be_empty && v.size() == 0) return;
    if (v.size() != n || !v.allFinite()) {
      throw std::invalid_argument(fmt::format(
          "time integration: state {} must have {} finite entries, got {}", name, n, v.size()));
    }
  };
  check(s.displacement, "displacement", false);
  check(s.velocity, "velocity", false);
  check(s.acceleration, "acceleration", true);
  if (!s.contact_forces.empty()) {
    if (s.contact_forces.size() != system.contacts.size()) {
      throw std::invalid_argument(
          fmt::format("time integration: state contact_forces must have {} entries, got {}",
                      system.contacts.size(), s.contact_forces.size()));
    }
    for (std::size_t c = 0; c < s.contact_forces.size(); ++c) {
      const double f = s.contact_forces[c];
      const hb::ContactElement& e = system.contacts[c];
      if (!std::isfinite(f) || (e.normal() ? f > e.normal_force : std::abs(f) > e.slip_limit() * (1.0 + 1e-12))) {
        throw std::invalid_argument(fmt::format(
            "time integration: state contact_forces[{}] must satisfy {}, got {}", c,
            e.normal() ? "F <= F_N0 (a normal element)" : "|F| <= mu F_N", f));
      }
    }
  }
  if (!std::isfinite(s.time))
    throw std::invalid_argument("time integration: state time: not finite");
}

// The Newton matrix J = S + w Σ_c d_c b_c b_cᵀ, dense for small or dense systems (condensed
// models), sparse LDLᵀ with a fixed pattern otherwise. Refactorises only when the contact tangents
// change (a Jenkins contact alternates between two values).
class TangentSolver {
 public:
  TangentSolver(const SparseMatrix& s, const std::vector<hb::ContactElement>& contacts,
                double weight)
      : contacts_(contacts), weight_(weight) {
    const Eigen::Index n = s.rows();
    dense_ = n <= 64 || s.nonZeros() > n * n / 8;
    if (dense_) {
      s_dense_ = Eigen::MatrixXd(s);
      return;
    }
    s_sparse_ = s;
    std::vector<Eigen::Triplet<double>> t;
    for (int k = 0; k < s.outerSize(); ++k) {
      for (SparseMatrix::InnerIterator it(s, k); it; ++it) t.emplace_back(it.row(), it.col(), 0.0);
    }
    for (const auto& c : contacts_) {
      t.emplace_back(c.dof_a, c.dof_a, 0.0);
      if (c.dof_b >= 0) {
        t.emplace_back(c.dof_b, c.dof_b, 0.0);
        t.emplace_back(c.dof_a, c.dof_b, 0.0);
        t.emplace_back(c.dof_b, c.dof_a, 0.0);
      }
    }
    j_.resize(n, n);
    j_.setFromTriplets(t.begin(), t.end());
    j_.makeCompressed();
    for (int k = 0; k < s.outerSize(); ++k) {
      for (SparseMatrix::InnerIterator it(s, k); it; ++it)
        j_.coeffRef(it.row(), it.col()) = it.value();
    }
    base_.assign(j_.valuePtr(), j_.valuePtr() + j_.nonZeros());
    sparse_ldlt_.analyzePattern(j_);
  }

  [[nodiscard]] Vec apply(const Vec& dx) const {
    return dense_ ? Vec(s_dense_ * dx) : Vec(s_sparse_ * dx);
  }

  /// False when the factorisation fails.
  bool factorize(const Vec& d) {
    if (factorized_ && d.size() == last_d_.size() && d == last_d_) return true;
    last_d_ = d;
    factorized_ = false;
    if (dense_) {
      Eigen::MatrixXd j = s_dense_;
      for (std::size_t c = 0; c < contacts_.size(); ++c) {
        const auto& e = contacts_[c];
        const double v = weight_ * d[static_cast<Eigen::Index>(c)];
        j(e.dof_a, e.dof_a) += v;
        if (e.dof_b >= 0) {
          j(e.dof_b, e.dof_b) += v;
          j(e.dof_a, e.dof_b) -= v;
          j(e.dof_b, e.dof_a) -= v;
        }
      }
      dense_ldlt_.compute(j);
      factorized_ = dense_ldlt_.info() == Eigen::Success;
      return factorized_;
    }
    std::copy(base_.begin(), base_.end(), j_.valuePtr());
    for (std::size_t c = 0; c < contacts_.size(); ++c) {
      const auto& e = contacts_[c];
      const double v = weight_ * d[static_cast<Eigen::Index>(c)];
      j_.coeffRef(e.dof_a, e.dof_a) += v;
      if (e.dof_b >= 0) {
        j_.coeffRef(e.dof_b, e.dof_b) += v;
        j_.coeffRef(e.dof_a, e.dof_b) -= v;
        j_.coeffRef(e.dof_b, e.dof_a) -= v;
      }
    }
    sparse_ldlt_.factorize(j_);
    factorized_ = sparse_ldlt_.info() == Eigen::Success;
    return factorized_;
  }

  [[nodiscard]] Vec solve(const Vec& r) const {
    return dense_ ? Vec(dense_ldlt_.solve(r)) : Vec(sparse_ldlt_.solve(r));
  }

 private:
  const std::vector<hb::ContactElement>& contacts_;
  double weight_;
  bool dense_ = true;
  Eigen::MatrixXd s_dense_;
  Eigen::LDLT<Eigen::MatrixXd> dense_ldlt_;
  SparseMatrix s_sparse_;
  SparseMatrix j_;
  std::vector<double> base_;
  Eigen::SimplicialLDLT<SparseMatrix> sparse_ldlt_;
  Vec last_d_;
  bool factorized_ = false;
};

struct StepOutcome {
  bool converged = false;
  int iterations = 0;
  bool line_search = false;
  double residual = 0.0;  // ‖r‖∞ at the end
  double scale = 0.0;     // the largest force term of the step
};

// Energy and dissipation accumulated over steps.
struct Ledger {
  std::vector<double> contact_dissipation;
  double external_work = 0.0;
  double viscous_dissipation = 0.0;
};

class Stepper {
 public:
  Stepper(const hb::DiscreteSystem& system, const hb::Excitation& excitation, double omega,
          const NewmarkOptions& options)
      : system_(system),
        excitation_(excitation),
        omega_(omega),
        options_(options),
        n_(system.dofs()),
        nc_(system.contacts.size()),
        alpha_(options.alpha),
        beta_(0.25 * (1.0 - options.alpha) * (1.0 - options.alpha)),
        gamma_(0.5 - options.alpha),
        dt_(options.time_step),
        c0_(1.0 / (beta_ * dt_ * dt_)),
        c1_(gamma_ / (beta_ * dt_)),
        has_damping_(system.damping.nonZeros() > 0),
        solver_(effective_matrix(), system.contacts, 1.0 + options.alpha) {
    for (const auto& c : system.contacts) {
      laws_.push_back(hb::DiscreteSystem::make_law(c));
      limits_.push_back({c.slip_limit(), c.stiffness});
    }
    tangent_ = Vec::Zero(static_cast<Eigen::Index>(nc_));
    Vec row_sums = Vec::Zero(n_);
    const SparseMatrix s = effective_matrix();
    for (int k = 0; k < s.outerSize(); ++k) {
      for (SparseMatrix::InnerIterator it(s, k); it; ++it)
        row_sums[it.row()] += std::abs(it.value());
    }
    s_norm_ = row_sums.maxCoeff();
  }

  /// Fills an empty acceleration (equation of motion at t) and empty contact forces (reference).
  void complete(State& s) const {
    check_state(s, system_);
    if (s.contact_forces.empty()) s.contact_forces = reference_forces(system_, s.displacement);
    if (s.acceleration.size() == 0) {
      Vec rhs = excitation_.at(omega_, s.time, n_) - system_.stiffness * s.displacement -
                contact_vector(s.contact_forces);
      if (has_damping_) rhs -= system_.damping * s.velocity;
      Eigen::SimplicialLDLT<SparseMatrix> m(system_.mass);
      s.acceleration = m.solve(rhs);
    }
  }

  /// One step from `in` to t_next (= in.time + Δt up to rounding; forcing evaluated at t_next).
  StepOutcome step(const State& in, double t_next, State& out, Ledger& ledger) {
    const Vec& xn = in.displacement;
    const Vec& vn = in.velocity;
    const Vec& an = in.acceleration;
    const double w = 1.0 + alpha_;
    const Vec f_now = excitation_.at(omega_, in.time, n_);
    const Vec f_next = excitation_.at(omega_, t_next, n_);

    // q0 = r(x_n) without the contact term.
    const Vec a0 = -(1.0 / (beta_ * dt_)) * vn - (0.5 / beta_ - 1.0) * an;
    const Vec v0 = vn + dt_ * ((1.0 - gamma_) * an + gamma_ * a0);
    // q0 is a sum of terms that cancel: its round-off follows the largest term, not q0 itself.
    const Vec inertia = system_.mass * a0;
    const Vec elastic = w * (system_.stiffness * xn);
    q0_ = inertia + elastic - w * f_next;
    q0_scale_ = std::max({inertia.cwiseAbs().maxCoeff(), elastic.cwiseAbs().maxCoeff(),
                          w * f_next.cwiseAbs().maxCoeff()});
    if (has_damping_) {
      const Vec viscous = w * (system_.damping * v0);
      q0_ += viscous;
      q0_scale_ = std::max(q0_scale_, viscous.cwiseAbs().maxCoeff());
    }
    if (alpha_ != 0.0) {
      Vec previous = system_.stiffness * xn + contact_vector(in.contact_forces) - f_now;
      if (has_damping_) previous += system_.damping * vn;
      q0_ -= alpha_ * previous;
      q0_scale_ = std::max(q0_scale_, std::abs(alpha_) * previous.cwiseAbs().maxCoeff());
    }
    gaps_n_.resize(nc_);
    for (std::size_t c = 0; c < nc_; ++c) gaps_n_[c] = system_.contacts[c].gap(xn);

    StepOutcome outcome;
    Vec x = xn + dt_ * vn + 0.5 * dt_ * dt_ * an;  // constant-acceleration predictor
    double scale = 0.0;
    Vec r = residual(in, x, &scale);
    for (int it = 0;; ++it) {
      outcome.iterations = it;
      outcome.residual = r.cwiseAbs().maxCoeff();
      outcome.scale = scale;
      // Converged to the tolerance, or to the round-off floor: one ulp of x moves r by about
      // ‖J‖∞ ε ‖x‖∞ (large for stiff contacts or small Δt, where c0 = 1/(βΔt²) dominates J).
      const double contact_norm = nc_ > 0 ? 2.0 * w * tangent_.cwiseAbs().maxCoeff() : 0.0;
      const double floor =
          8.0 * kEps * (scale + (s_norm_ + contact_norm) * x.cwiseAbs().maxCoeff());
      if (outcome.residual <= std::max(options_.newton_tolerance * scale, floor)) {
        outcome.converged = true;
        break;
      }
      if (it == options_.max_newton_iterations) break;
      if (!solver_.factorize(tangent_)) break;
      const Vec d = -solver_.solve(r);
      if (!d.allFinite()) break;
      double scale1 = 0.0;
      Vec r1 = residual(in, x + d, &scale1);
      const double slope0 = r.dot(d);  // φ'(0) < 0
      const double slope1 = r1.dot(d);
      if (r1.norm() <= (1.0 - 1e-4) * r.norm() || slope1 <= 0.0 || !(slope0 < 0.0)) {
        x += d;
        r = std::move(r1);
        scale = scale1;
        continue;
      }
      // Regula falsi (Illinois) for φ'(λ) = r(x + λd)ᵀd = 0 on [0, 1]; stop once
      // |φ'(λ)| ≤ ¼|φ'(0)| (ψ then decreased by at least about ¾ of the linear model).
      outcome.line_search = true;
      double lo = 0.0, f_lo = slope0, hi = 1.0, f_hi = slope1;
      double lambda = 1.0;
      Vec r_best = r1;
      Vec tangent_best = tangent_;
      double scale_best = scale1;
      double best = std::abs(slope1);
      int side = 0;
      for (int k = 0; k < options_.max_line_search; ++k) {
        const double trial = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        double scale_t = 0.0;
        Vec r_t = residual(in, x + trial * d, &scale_t);
        const double f_t = r_t.dot(d);
        if (std::abs(f_t) < best || k == 0) {
          best = std::abs(f_t);
          lambda = trial;
          r_best = r_t;
          tangent_best = tangent_;
          scale_best = scale_t;
        }
        if (std::abs(f_t) <= 0.25 * std::abs(slope0)) break;
        if (f_t < 0.0) {
          lo = trial;
          f_lo = f_t;
          if (side == -1) f_hi *= 0.5;
          side = -1;
        } else {
          hi = trial;
          f_hi = f_t;
          if (side == 1) f_lo *= 0.5;
          side = 1;
        }
      }
      x += lambda * d;
      r = std::move(r_best);
      tangent_ = std::move(tangent_best);
      scale = scale_best;
    }
    if (!outcome.converged) return outcome;

    // Accept: exact contact forces with their dissipation, then a, v.
    out.contact_forces.resize(nc_);
    for (std::size_t c = 0; c < nc_; ++c) {
      const contact::ScalarStep s = laws_[c]->scalar_step(
          in.contact_forces[c], system_.contacts[c].gap(x) - gaps_n_[c], limits_[c], true);
      out.contact_forces[c] = s.force;
      ledger.contact_dissipation[c] += s.dissipation;
    }
    const Vec dx = x - xn;
    out.acceleration = c0_ * dx - (1.0 / (beta_ * dt_)) * vn - (0.5 / beta_ - 1.0) * an;
    out.velocity = vn + dt_ * ((1.0 - gamma_) * an + gamma_ * out.acceleration);
    out.displacement = std::move(x);
    out.time = t_next;
    ledger.external_work += 0.5 * (f_now + f_next).dot(dx);
    if (has_damping_) {
      ledger.viscous_dissipation += 0.5 * dx.dot(system_.damping * (vn + out.velocity));
    }
    return outcome;
  }

 private:
  [[nodiscard]] SparseMatrix effective_matrix() const {
    SparseMatrix s = c0_ * system_.mass + (1.0 + alpha_) * system_.stiffness;
    if (has_damping_) s += ((1.0 + alpha_) * c1_) * system_.damping;
    return s;
  }

  [[nodiscard]] Vec contact_vector(const std::vector<double>& f) const {
    Vec b = Vec::Zero(n_);
    for (std::size_t c = 0; c < nc_; ++c) {
      const auto& e = system_.contacts[c];
      b[e.dof_a] += f[c];
      if (e.dof_b >= 0) b[e.dof_b] -= f[c];
    }
    return b;
  }

  // r(x) = q0 + S(x - x_n) + (1+α) B F(x); fills the contact forces and tangents at x.
  Vec residual(const State& in, const Vec& x, double* scale) {
    const double w = 1.0 + alpha_;
    const Vec sdx = solver_.apply(x - in.displacement);
    Vec r = q0_ + sdx;
    double contact_scale = 0.0;
    for (std::size_t c = 0; c < nc_; ++c) {
      const auto& e = system_.contacts[c];
      const contact::ScalarStep s =
          laws_[c]->scalar_step(in.contact_forces[c], e.gap(x) - gaps_n_[c], limits_[c], false);
      tangent_[static_cast<Eigen::Index>(c)] = s.d_slip;
      r[e.dof_a] += w * s.force;
      if (e.dof_b >= 0) r[e.dof_b] -= w * s.force;
      contact_scale = std::max(contact_scale, w * std::abs(s.force));
    }
    *scale = std::max({q0_scale_, sdx.cwiseAbs().maxCoeff(), contact_scale});
    return r;
  }

  const hb::DiscreteSystem& system_;
  const hb::Excitation& excitation_;
  double omega_;
  NewmarkOptions options_;
  int n_;
  std::size_t nc_;
  double alpha_, beta_, gamma_, dt_, c0_, c1_;
  bool has_damping_;
  TangentSolver solver_;
  std::vector<std::shared_ptr<const contact::TangentialLaw>> laws_;
  std::vector<contact::TangentialLimits> limits_;
  std::vector<double> gaps_n_;
  Vec tangent_;
  Vec q0_;
  double q0_scale_ = 0.0;
  double s_norm_ = 0.0;  // ‖S‖∞
};

std::string newton_failure(const StepOutcome& o, int step, double time, int max_iterations) {
  return fmt::format(
      "Newton did not converge in step {} (t = {:.9g} s): residual {:.3g} of force scale {:.3g} "
      "after {} iterations (max_newton_iterations = {})",
      step, time, o.residual, o.scale, o.iterations, max_iterations);
}

}  // namespace

Status TransientResult::status() const {
  if (termination == Termination::reached_end && message.empty())
    return {termination, std::to_string(steps) + " steps"};
  return {termination, message};
}

std::string NewmarkOptions::validate() const {
  if (!(time_step > 0.0) || !std::isfinite(time_step)) {
    return fmt::format("time_step: must be finite and > 0, got {}", time_step);
  }
  if (!(alpha >= -1.0 / 3.0 && alpha <= 0.0)) {
    return fmt::format("alpha: must lie in [-1/3, 0], got {}", alpha);
  }
  if (max_newton_iterations < 1) {
    return fmt::format("max_newton_iterations: must be >= 1, got {}", max_newton_iterations);
  }
  if (!(newton_tolerance > 0.0 && newton_tolerance <= 1e-3)) {
    return fmt::format("newton_tolerance: must lie in (0, 1e-3], got {}", newton_tolerance);
  }
  if (max_line_search < 1) {
    return fmt::format("max_line_search: must be >= 1, got {}", max_line_search);
  }
  return {};
}

std::string SteadyStateOptions::validate() const {
  if (harmonics < 1) return fmt::format("harmonics: must be >= 1, got {}", harmonics);
  if (steps_per_period < 2 * harmonics + 2) {
    return fmt::format("steps_per_period: must be >= 2 harmonics + 2 = {}, got {}",
                       2 * harmonics + 2, steps_per_period);
  }
  if (max_periods < 1) return fmt::format("max_periods: must be >= 1, got {}", max_periods);
  if (!(tolerance > 0.0 && tolerance <= 1e-2)) {
    return fmt::format("tolerance: must lie in (0, 1e-2], got {}", tolerance);
  }
  NewmarkOptions scheme = integrator;
  scheme.time_step = 1.0;  // replaced by T/N
  if (const std::string msg = scheme.validate(); !msg.empty()) return "integrator." + msg;
  return {};
}

State rest_state(const hb::DiscreteSystem& system, double time) {
  State s;
  s.displacement = Vec::Zero(system.dofs());
  s.velocity = Vec::Zero(system.dofs());
  s.contact_forces = reference_forces(system, s.displacement);
  s.time = time;
  return s;
}

std::optional<State> stuck_linear_state(const hb::DiscreteSystem& system,
                                        const hb::Excitation& excitation, double omega,
                                        double time) {
  check_system(system, excitation);
  const int n = system.dofs();
  const SparseMatrix ks = hb::stuck_stiffness(system);
  State s = rest_state(system, time);

  // Static part: K_s x = f_static - Σ_c (F_ref - k g_ref) b_c.
  Vec f = excitation.static_force.size() == n ? excitation.static_force : Vec::Zero(n);
  for (const auto& c : system.contacts) {
    const double offset = c.reference_force - c.stiffness * c.reference_slip;
    f[c.dof_a] -= offset;
    if (c.dof_b >= 0) f[c.dof_b] += offset;
  }
  if (f.cwiseAbs().maxCoeff() > 0.0) {
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(ks);
    if (ldlt.info() != Eigen::Success) return std::nullopt;
    const Vec x = ldlt.solve(f);
    if (!x.allFinite() || (ks * x - f).norm() > 1e-8 * f.norm()) return std::nullopt;
    s.displacement = x;
  }

  // Harmonic parts, grouped by harmonic order: X_h = (K_s - (hΩ)² M + i hΩ C)⁻¹ f_h.
  std::map<int, Vec> by_order;
  for (const auto& h : excitation.forces) {
    auto [it, inserted] = by_order.try_emplace(h.harmonic, Vec::Zero(n));
    it->second[h.dof] += h.amplitude;
  }
  using Complex = std::complex<double>;
  using ComplexSparse = Eigen::SparseMatrix<Complex>;
  for (const auto& [order, amplitude] : by_order) {
    if (amplitude.cwiseAbs().maxCoeff() == 0.0) continue;
    const double w = order * omega;
    ComplexSparse z = (ks - w * w * system.mass).cast<Complex>();
    if (system.damping.nonZeros() > 0) z += Complex(0.0, w) * system.damping.cast<Complex>();
    z.makeCompressed();
    Eigen::SparseLU<ComplexSparse> lu(z);
    if (lu.info() != Eigen::Success) return std::nullopt;
    const Eigen::VectorXcd rhs = amplitude.cast<Complex>();
    const Eigen::VectorXcd x = lu.solve(rhs);
    if (!x.allFinite() || (z * x - rhs).norm() > 1e-8 * rhs.norm()) return std::nullopt;
    const Complex phase = std::polar(1.0, w * time);
    s.displacement += (x * phase).real();
    s.velocity += (Complex(0.0, w) * x * phase).real();
  }
  s.contact_forces = reference_forces(system, s.displacement);
  return s;
}

TransientResult integrate(const hb::DiscreteSystem& system, const hb::Excitation& excitation,
                          double omega, State initial, int steps, const NewmarkOptions& options,
                          const std::function<void(const State&)>& on_step) {
  const auto start = Clock::now();
  if (const std::string msg = options.validate(); !msg.empty()) {
    throw std::invalid_argument("newmark options: " + msg);
  }
  if (steps < 0)
    throw std::invalid_argument(fmt::format("integrate: steps must be >= 0, got {}", steps));
  if (!std::isfinite(omega)) throw std::invalid_argument("integrate: omega must be finite");
  check_system(system, excitation);
  Stepper stepper(system, excitation, omega, options);
  stepper.complete(initial);

  TransientResult result;
  Ledger ledger;
  ledger.contact_dissipation.assign(system.contacts.size(), 0.0);
  const double t0 = initial.time;
  State current = std::move(initial);
  State next;
  for (int i = 0; i < steps; ++i) {
    const StepOutcome o =
        stepper.step(current, t0 + static_cast<double>(i + 1) * options.time_step, next, ledger);
    result.newton_iterations += o.iterations;
    result.max_step_iterations = std::max(result.max_step_iterations, o.iterations);
    result.line_searches += o.line_search ? 1 : 0;
    if (!o.converged) {
      result.termination = Termination::failed;
      result.message = newton_failure(o, i + 1, next.time, options.max_newton_iterations);
      break;
    }
    std::swap(current, next);
    ++result.steps;
    if (on_step) on_step(current);
  }
  result.final_state = std::move(current);
  result.contact_dissipation = std::move(ledger.contact_dissipation);
  result.external_work = ledger.external_work;
  result.viscous_dissipation = ledger.viscous_dissipation;
  result.seconds = seconds_since(start);
  return result;
}

namespace {

using support::group_change;

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

}  // namespace

SteadyStateResult forced_steady_state(const hb::DiscreteSystem& system,
                                      const hb::Excitation& excitation, double omega,
                                      const SteadyStateOptions& options,
                                      std::optional<State> initial) {
  const auto start = Clock::now();
  if (const std::string msg = options.validate(); !msg.empty()) {
    throw std::invalid_argument("steady state options: " + msg);
  }
  if (!(omega > 0.0) || !std::isfinite(omega)) {
    throw std::invalid_argument(
        fmt::format("steady state: omega must be finite and > 0, got {}", omega));
  }
  check_system(system, excitation);
  const int n = system.dofs();
  const auto nc = static_cast<Eigen::Index>(system.contacts.size());
  const int steps = options.steps_per_period;

  SteadyStateResult result;
  result.period = 2.0 * std::numbers::pi / omega;
  result.time_step = result.period / steps;
  NewmarkOptions scheme = options.integrator;
  scheme.time_step = result.time_step;

  State state;
  if (initial) {
    state = std::move(*initial);
  } else {
    state = stuck_linear_state(system, excitation, omega).value_or(rest_state(system, 0.0));
  }
  Stepper stepper(system, excitation, omega, scheme);
  stepper.complete(state);
  const double t0 = state.time;

  result.samples.resize(n, steps);
  result.contact_force_samples.resize(nc, steps);
  Ledger ledger;
  State next;
  for (int p = 0; p < options.max_periods; ++p) {
    const State period_start = state;
    ledger = Ledger{};
    ledger.contact_dissipation.assign(system.contacts.size(), 0.0);
    double v_max = 0.0;
    for (int j = 0; j < steps; ++j) {
      result.samples.col(j) = state.displacement;
      for (Eigen::Index c = 0; c < nc; ++c) {
        result.contact_force_samples(c, j) = state.contact_forces[static_cast<std::size_t>(c)];
      }
      v_max = std::max(v_max, state.velocity.cwiseAbs().maxCoeff());
      const long index = static_cast<long>(p) * steps + j + 1;
      const StepOutcome o =
          stepper.step(state, t0 + static_cast<double>(index) * result.time_step, next, ledger);
      ++result.steps;
      result.newton_iterations += o.iterations;
      if (!o.converged) {
        result.termination = Termination::failed;
        result.message = newton_failure(o, static_cast<int>(index),
                                        t0 + static_cast<double>(index) * result.time_step,
                                        scheme.max_newton_iterations);
        result.periods = p;
        result.samples.resize(0, 0);  // the interrupted period is not reported
        result.contact_force_samples.resize(0, 0);
        result.final_state = std::move(state);
        result.seconds = seconds_since(start);
        return result;
      }
      std::swap(state, next);
    }
    result.periods = p + 1;
    result.start_time = period_start.time;
    const double x_max =
        std::max(result.samples.cwiseAbs().maxCoeff(), state.displacement.cwiseAbs().maxCoeff());
    const double f_max = nc > 0 ? result.contact_force_samples.cwiseAbs().maxCoeff() : 0.0;
    result.change = std::max(
        {group_change((state.displacement - period_start.displacement).cwiseAbs().maxCoeff(),
                      x_max),
         group_change((state.velocity - period_start.velocity).cwiseAbs().maxCoeff(), v_max),
         group_change(max_abs_difference(state.contact_forces, period_start.contact_forces),
                      f_max)});
    if (result.change <= options.tolerance) {
      result.termination = Termination::converged;
      break;
    }
  }

  // Harmonics of the last period by direct sums over the samples (absolute-time phase).
  result.coefficients = period_harmonics(result.samples, omega, t0, options.harmonics);
  result.amplitude_max = result.samples.cwiseAbs().rowwise().maxCoeff();
  result.contact_dissipation = ledger.contact_dissipation;
  result.external_work = ledger.external_work;
  result.viscous_dissipation = ledger.viscous_dissipation;
  result.final_state = std::move(state);
  if (result.termination == Termination::converged) {
    result.message = fmt::format("steady state after {} periods (relative change {:.2e})",
                                 result.periods, result.change);
  } else {
    result.message =
        fmt::format("no steady state after {} periods: relative change {:.2e} > tolerance {:.2e}",
                    result.periods, result.change, options.tolerance);
  }
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace jointhb::timeint
