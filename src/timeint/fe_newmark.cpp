// Newmark / HHT-α integration of the full FE model with exact contact increments (fe_newmark.hpp).
//
// Step n → n+1 with c0 = 1/(βΔt²), c1 = γ/(βΔt), ω = 1+α and the unknown w = w_{n+1}
// (the same algebra as newmark.cpp):
//   a(w) = c0 (w − w_n) + a0,   a0 = −v_n/(βΔt) − (1/(2β) − 1) a_n
//   v(w) = c1 (w − w_n) + v0,   v0 = v_n + Δt[(1 − γ) a_n + γ a0]
//   r(w) = q0 + S (w − w_n) + ω Δf_c(w),   S = c0 M + ω(c1 C + K_L),
//   q0   = M a0 + ω(C v0 + K_L w_n − f_{n+1}) − α(C v_n + K_L w_n + Δf_c,n − f_n),
// Δf_c(w) = Σ_I G_Iᵀ A_I (t_I(w) − t_I,pre), t_p(w) = ContactPoint::step(t_T,n, g_n, g_pre + G w).
// Newton: w ← w − J̃⁻¹ r with J̃ = S + ω Σ_I G_Iᵀ A C̃_I G_I (fe_newmark.hpp), lagged across
// iterations and steps; refactored (same CHOLMOD analysis) when ‖r‖ falls by less than
// refactor_ratio in an iteration. The residual is exact, so the converged step is that of the
// consistent Newton method; only the iteration count depends on the lag.
//
// Energy (trapezoidal identity, exact for the scheme with α = 0): over a step,
//   ½(f_n + f_{n+1})·Δw = Δ(½vᵀMv + ½wᵀK_L w) + ½(v_n + v_{n+1})ᵀC Δw + ½(f_c,n + f_c,n+1)·Δw,
// so over a periodic steady state external work = viscous dissipation + contact work.
#include "jointhb/timeint/fe_newmark.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "period_harmonics.hpp"
#include "../support/contact_tangent.hpp"
#include "../support/numeric_constants.hpp"
#include "../support/stopwatch.hpp"
#include "jointhb/fe/sparse_cholesky.hpp"

namespace jointhb::timeint {
namespace {

using Vec = Eigen::VectorXd;
using SpMat = Eigen::SparseMatrix<double>;
using support::Clock;
using support::seconds_since;
using support::kEps;

std::string excitation_problem(const FeExcitation& e, int n) {
  for (std::size_t j = 0; j < e.forces.size(); ++j) {
    const auto& f = e.forces[j];
    if (f.dof < 0 || f.dof >= n)
      return fmt::format("excitation forces[{}].dof: must lie in [0, {}], got {}", j, n - 1, f.dof);
    if (!std::isfinite(f.amplitude))
      return fmt::format("excitation forces[{}].amplitude: must be finite, got {}", j, f.amplitude);
  }
  if (e.static_force.size() != 0 && (e.static_force.size() != n || !e.static_force.allFinite()))
    return fmt::format("excitation static_force: must be empty or {} finite entries, got {}", n,
                       e.static_force.size());
  return {};
}

void check_inputs(const preload::PreloadModel& model, const preload::PreloadResult& preload,
                  const FeExcitation& excitation) {
  if (model.mesh == nullptr) throw std::invalid_argument("fe time integration: model has no mesh");
  const int n = model.mesh->num_dofs();
  if (model.structure.mass.rows() != n || model.structure.stiffness.rows() != n)
    throw std::invalid_argument("fe time integration: structure matrices do not match the mesh");
  if (preload.displacement.size() != n || preload.dynamic_stiffness.rows() != n ||
      preload.interfaces.size() != model.interfaces.size())
    throw std::invalid_argument("fe time integration: preload result does not match the model");
  if (const std::string msg = excitation_problem(excitation, n); !msg.empty())
    throw std::invalid_argument("fe time integration: " + msg);
}

// Contact quantities at one trial displacement.
struct ContactEvaluation {
  Vec force;                                        // Δf_c = Σ Gᵀ A (t − t_pre), full DOFs
  std::vector<Vec> traction, gap;                   // per interface, 3P
  std::vector<std::vector<Eigen::Matrix3d>> tangent;  // consistent C_p
  std::vector<double> dissipation;                  // Σ_p a_p D_p per interface [J]
  double scale = 0.0;                               // max |Δf_c|
};

// Everything that stays fixed over an integration: matrices, preload contact state, factor.
class FeStepper {
 public:
  FeStepper(const preload::PreloadModel& model, const preload::PreloadResult& preload,
            const FeExcitation& excitation, double omega, const FeNewmarkOptions& options)
      : model_(model),
        preload_(preload),
        excitation_(excitation),
        omega_(omega),
        options_(options),
        n_(model.mesh->num_dofs()),
        alpha_(options.alpha),
        beta_(0.25 * (1.0 - options.alpha) * (1.0 - options.alpha)),
        gamma_(0.5 - options.alpha),
        dt_(options.time_step),
        c0_(1.0 / (beta_ * dt_ * dt_)),
        c1_(gamma_ / (beta_ * dt_)),
        laws_(fe_point_laws(model, preload, options)) {
    const double w = 1.0 + alpha_;
    k_linear_ = model.structure.stiffness + preload::bolt_stiffness(model.bolts, n_);
    damping_ = options.mass_damping * model.structure.mass +
               options.stiffness_damping * preload.dynamic_stiffness;
    has_damping_ = options.mass_damping > 0.0 || options.stiffness_damping > 0.0;
    dofs_ = fe::DofMap::from_fixed_nodes(model.mesh->num_nodes(), model.constraints);
    constrained_ = dofs_.num_free() != n_;
    f_pre_ = Vec::Zero(n_);
    for (std::size_t i = 0; i < model.interfaces.size(); ++i) {
      f_pre_ += fe::interface_force(model.interfaces[i].geometry,
                                    preload.interfaces[i].state.traction);
    }
    fc_abs_ = f_pre_.size() ? f_pre_.cwiseAbs().maxCoeff() : 0.0;
    // S + 0·(the full 3×3 contact pattern): the pattern every J̃ has, analysed once.
    SpMat pattern = contact_matrix(/*ones=*/true, {});
    s_ = c0_ * model.structure.mass + w * (c1_ * damping_ + k_linear_);
    s_pattern_ = s_ + 0.0 * pattern;
    Vec row_sums = Vec::Zero(n_);
    for (int k = 0; k < s_.outerSize(); ++k)
      for (SpMat::InnerIterator it(s_, k); it; ++it) row_sums[it.row()] += std::abs(it.value());
    s_norm_ = row_sums.maxCoeff();
  }

  [[nodiscard]] int num_dofs() const { return n_; }
  [[nodiscard]] int factorizations() const { return factorizations_; }
  [[nodiscard]] const SpMat& damping() const { return damping_; }

  /// ½ẇᵀMẇ + ½wᵀK_L w (the structure's and bolts' share of the stored energy).
  [[nodiscard]] double stored_energy(const FeState& s) const {
    return 0.5 * s.velocity.dot(model_.structure.mass * s.velocity) +
           0.5 * s.displacement.dot(k_linear_ * s.displacement);
  }

  /// Contact state at w from the state `in` (exact increments).
  [[nodiscard]] ContactEvaluation contact(const FeState& in, const Vec& w) const {
    ContactEvaluation e;
    e.force = -f_pre_;
    for (std::size_t i = 0; i < model_.interfaces.size(); ++i) {
      const auto& ci = model_.interfaces[i];
      const Vec g = preload_.interfaces[i].state.gap + fe::gaps(ci.geometry, w);
      Vec t(g.size());
      std::vector<Eigen::Matrix3d> c(static_cast<std::size_t>(ci.geometry.num_points()));
      double d = 0.0;
      for (int p = 0; p < ci.geometry.num_points(); ++p) {
        const Eigen::Index k = 3 * p;
        const contact::ContactStep s = laws_[i][static_cast<std::size_t>(p)].step(
            in.traction[i].segment<2>(k), in.gap[i].segment<3>(k), g.segment<3>(k));
        t.segment<3>(k) = s.traction;
        c[static_cast<std::size_t>(p)] = s.tangent;
        d += ci.geometry.points[static_cast<std::size_t>(p)].area * s.dissipation;
      }
      e.force += fe::interface_force(ci.geometry, t);
      e.traction.push_back(std::move(t));
      e.gap.push_back(g);
      e.tangent.push_back(std::move(c));
      e.dissipation.push_back(d);
    }
    e.scale = e.force.size() ? e.force.cwiseAbs().maxCoeff() : 0.0;
    return e;
  }

  /// Δf_c of a state's own tractions.
  [[nodiscard]] Vec contact_force(const FeState& s) const {
    Vec f = -f_pre_;
    for (std::size_t i = 0; i < model_.interfaces.size(); ++i)
      f += fe::interface_force(model_.interfaces[i].geometry, s.traction[i]);
    return f;
  }

  /// Fills an empty acceleration from M a = f − C v − K_L w − Δf_c (free DOFs).
  void complete(FeState& s) const {
    if (s.acceleration.size() != 0) return;
    Vec rhs = excitation_.at(omega_, s.time, n_) - k_linear_ * s.displacement - contact_force(s);
    if (has_damping_) rhs -= damping_ * s.velocity;
    fe::SparseCholesky m;
    m.compute(restrict(model_.structure.mass));
    s.acceleration = expand(m.solve(restrict(rhs)));
  }

  struct Outcome {
    bool converged = false;
    int iterations = 0;
    int line_search_cuts = 0;
    double residual = 0.0, scale = 0.0;
  };

  /// One step from `in` to t_next; on convergence fills `out` and adds to the ledger.
  Outcome step(const FeState& in, double t_next, FeState& out, FeTransientResult& ledger) {
    const double w = 1.0 + alpha_;
    const Vec& wn = in.displacement;
    const Vec& vn = in.velocity;
    const Vec& an = in.acceleration;
    const Vec f_now = excitation_.at(omega_, in.time, n_);
    const Vec f_next = excitation_.at(omega_, t_next, n_);
    const Vec fc_now = contact_force(in);

    const Vec a0 = -(1.0 / (beta_ * dt_)) * vn - (0.5 / beta_ - 1.0) * an;
    const Vec v0 = vn + dt_ * ((1.0 - gamma_) * an + gamma_ * a0);
    const Vec inertia = model_.structure.mass * a0;
    const Vec elastic = w * (k_linear_ * wn);
    Vec q0 = inertia + elastic - w * f_next;
    double q0_scale = std::max({max_abs(inertia), max_abs(elastic), w * max_abs(f_next)});
    if (has_damping_) {
      const Vec viscous = w * (damping_ * v0);
      q0 += viscous;
      q0_scale = std::max(q0_scale, max_abs(viscous));
    }
    if (alpha_ != 0.0) {
      Vec previous = k_linear_ * wn + fc_now - f_now;
      if (has_damping_) previous += damping_ * vn;
      q0 -= alpha_ * previous;
      q0_scale = std::max(q0_scale, std::abs(alpha_) * max_abs(previous));
    }

    // r(w) and its force scale; `e` holds the contact state at w.
    ContactEvaluation e;
    const auto residual = [&](const Vec& x, double& scale) {
      const Vec sdx = s_ * (x - wn);
      e = contact(in, x);
      scale = std::max({q0_scale, max_abs(sdx), w * e.scale});
      return restrict(Vec(q0 + sdx + w * e.force));
    };

    Outcome o;
    // Predictor: constant acceleration, or w_n when that is closer (a suddenly applied load
    // gives a_n large and local, which the exponential normal law does not forgive).
    Vec x = wn + dt_ * vn + 0.5 * dt_ * dt_ * an;
    double scale = 0.0;
    Vec r = residual(x, scale);
    {
      double scale_n = 0.0;
      ContactEvaluation e_pred = e;
      Vec r_n = residual(wn, scale_n);
      if (max_abs(r_n) < max_abs(r)) {
        x = wn;
        r = std::move(r_n);
        scale = scale_n;
      } else {
        e = std::move(e_pred);
      }
    }
    for (int it = 0;; ++it) {
      o.iterations = it;
      o.residual = max_abs(r);
      o.scale = scale;
      // One ulp of w moves r by about ‖J‖∞ ε ‖w‖∞; the contact forces carry ε of their
      // absolute (preloaded) size.
      const double floor = 8.0 * kEps * (scale + fc_abs_ + s_norm_ * max_abs(x));
      if (o.residual <= std::max(options_.newton_tolerance * scale, floor)) {
        o.converged = true;
        break;
      }
      if (it == options_.max_newton_iterations || !r.allFinite()) break;
      // Modified Newton: the lagged J̃ unless it was marked stale. A step that increases ‖r‖∞
      // with a lagged J̃ is redone with J̃ at the current iterate; one that still does is halved
      // (at most 8 times).
      const ContactEvaluation e_x = e;
      bool fresh = false;
      if (refactor_ || !factored_) {
        if (!factor(e)) break;
        fresh = true;
      }
      Vec d = expand(cholesky_.solve(-r));
      double scale1 = 0.0;
      Vec r1 = residual(x + d, scale1);
      if (!(max_abs(r1) <= o.residual) && !fresh) {
        if (!factor(e_x)) break;
        d = expand(cholesky_.solve(-r));
        r1 = residual(x + d, scale1);
      }
      for (int k = 0; k < 8 && !(max_abs(r1) <= o.residual); ++k) {
        d *= 0.5;
        r1 = residual(x + d, scale1);
        ++o.line_search_cuts;
      }
      x += d;
      if (max_abs(r1) > options_.refactor_ratio * o.residual) refactor_ = true;
      r = std::move(r1);
      scale = scale1;
    }
    if (!o.converged) return o;

    out.traction = std::move(e.traction);
    out.gap = std::move(e.gap);
    const Vec dx = x - wn;
    out.acceleration = c0_ * dx + a0;
    out.velocity = v0 + c1_ * dx;
    ledger.external_work += 0.5 * (f_now + f_next).dot(dx);
    ledger.contact_work += 0.5 * (fc_now + e.force).dot(dx);
    if (has_damping_) ledger.viscous_dissipation += 0.5 * dx.dot(damping_ * (vn + out.velocity));
    for (std::size_t i = 0; i < e.dissipation.size(); ++i)
      ledger.contact_dissipation[i] += e.dissipation[i];
    out.displacement = std::move(x);
    out.time = t_next;
    return o;
  }

  [[nodiscard]] Vec restrict(const Vec& full) const { return constrained_ ? dofs_.restrict(full) : full; }
  [[nodiscard]] Vec expand(const Vec& free) const { return constrained_ ? dofs_.expand(free) : free; }
  [[nodiscard]] SpMat restrict(const SpMat& full) const {
    return constrained_ ? dofs_.restrict(full) : full;
  }

 private:
  static double max_abs(const Vec& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

  // Σ_I G_Iᵀ A C̃_I G_I (C̃: symmetric PSD part of the tangents), or the pattern (all-ones C).
  [[nodiscard]] SpMat contact_matrix(bool ones, const ContactEvaluation& e) const {
    std::vector<Eigen::Triplet<double>> t;
    for (std::size_t i = 0; i < model_.interfaces.size(); ++i) {
      const auto& geometry = model_.interfaces[i].geometry;
      std::vector<Eigen::Matrix3d> c(static_cast<std::size_t>(geometry.num_points()),
                                     Eigen::Matrix3d::Ones());
      if (!ones)
        for (std::size_t p = 0; p < c.size(); ++p) c[p] = support::symmetric_psd_part(e.tangent[i][p]);
      fe::add_interface_stiffness(geometry, c, t);
    }
    SpMat k(n_, n_);
    k.setFromTriplets(t.begin(), t.end());
    return k;
  }

  // J̃ at the contact state e; one symbolic analysis for all factorisations.
  bool factor(const ContactEvaluation& e) {
    const SpMat j = restrict(SpMat(s_pattern_ + (1.0 + alpha_) * contact_matrix(false, e)));
    try {
      if (!cholesky_.analyzed()) cholesky_.analyze(j);
      cholesky_.factorize(j);
    } catch (const std::exception&) {
      factored_ = false;
      return false;
    }
    ++factorizations_;
    factored_ = true;
    refactor_ = false;
    return true;
  }

  const preload::PreloadModel& model_;
  const preload::PreloadResult& preload_;
  const FeExcitation& excitation_;
  double omega_;
  FeNewmarkOptions options_;
  int n_;
  double alpha_, beta_, gamma_, dt_, c0_, c1_;
  std::vector<std::vector<contact::ContactPoint>> laws_;  // per interface, per point
  SpMat k_linear_, damping_, s_, s_pattern_;
  bool has_damping_ = false;
  fe::DofMap dofs_;
  bool constrained_ = false;
  Vec f_pre_;
  double fc_abs_ = 0.0, s_norm_ = 0.0;
  fe::SparseCholesky cholesky_;
  bool factored_ = false, refactor_ = false;
  int factorizations_ = 0;
};

void check_state(const FeState& s, const preload::PreloadModel& model) {
  const auto n = static_cast<Eigen::Index>(model.mesh->num_dofs());
  const auto check = [&](const Vec& v, const char* name, bool may_be_empty) {
    if (may_be_empty && v.size() == 0) return;
    if (v.size() != n || !v.allFinite())
      throw std::invalid_argument(fmt::format(
          "fe time integration: state {}: must have {} finite entries, got {}", name, n, v.size()));
  };
  check(s.displacement, "displacement", false);
  check(s.velocity, "velocity", false);
  check(s.acceleration, "acceleration", true);
  if (s.traction.size() != model.interfaces.size() || s.gap.size() != model.interfaces.size())
    throw std::invalid_argument(fmt::format(
        "fe time integration: state traction/gap: need one vector per interface ({})",
        model.interfaces.size()));
  for (std::size_t i = 0; i < model.interfaces.size(); ++i) {
    const Eigen::Index p3 = 3 * model.interfaces[i].geometry.num_points();
    if (s.traction[i].size() != p3 || s.gap[i].size() != p3)
      throw std::invalid_argument(fmt::format(
          "fe time integration: state traction[{}]/gap[{}]: must have {} entries", i, i, p3));
  }
}

std::string newton_failure(const FeStepper::Outcome& o, long step, double time, int max_it) {
  return fmt::format(
      "Newton did not converge in step {} (t = {:.9g} s): residual {:.3g} of force scale {:.3g} "
      "after {} iterations (max_newton_iterations = {})",
      step, time, o.residual, o.scale, o.iterations, max_it);
}

}  // namespace

Status FeTransientResult::status() const {
  if (termination == Termination::reached_end && message.empty())
    return {termination, std::to_string(steps) + " steps"};
  return {termination, message};
}

Eigen::VectorXd FeExcitation::at(double omega, double time, int num_dofs) const {
  Vec f = static_force.size() == num_dofs ? static_force : Vec::Zero(num_dofs);
  const double c = std::cos(omega * time);
  for (const auto& h : forces) f[h.dof] += h.amplitude * c;
  return f;
}

std::string FeNewmarkOptions::validate() const {
  if (!(time_step > 0.0) || !std::isfinite(time_step))
    return fmt::format("time_step: must be finite and > 0, got {}", time_step);
  if (!(alpha >= -1.0 / 3.0 && alpha <= 0.0))
    return fmt::format("alpha: must lie in [-1/3, 0], got {}", alpha);
  if (!(mass_damping >= 0.0) || !std::isfinite(mass_damping))
    return fmt::format("mass_damping: must be finite and >= 0, got {}", mass_damping);
  if (!(stiffness_damping >= 0.0) || !std::isfinite(stiffness_damping))
    return fmt::format("stiffness_damping: must be finite and >= 0, got {}", stiffness_damping);
  if (max_newton_iterations < 1)
    return fmt::format("max_newton_iterations: must be >= 1, got {}", max_newton_iterations);
  if (!(newton_tolerance > 0.0 && newton_tolerance <= 1e-3))
    return fmt::format("newton_tolerance: must lie in (0, 1e-3], got {}", newton_tolerance);
  if (!(refactor_ratio > 0.0 && refactor_ratio < 1.0))
    return fmt::format("refactor_ratio: must lie in (0, 1), got {}", refactor_ratio);
  return {};
}

std::string FeSteadyStateOptions::validate() const {
  if (harmonics < 1) return fmt::format("harmonics: must be >= 1, got {}", harmonics);
  if (steps_per_period < 2 * harmonics + 2)
    return fmt::format("steps_per_period: must be >= 2 harmonics + 2 = {}, got {}",
                       2 * harmonics + 2, steps_per_period);
  if (max_periods < 1) return fmt::format("max_periods: must be >= 1, got {}", max_periods);
  if (!(tolerance > 0.0 && tolerance <= 1e-2))
    return fmt::format("tolerance: must lie in (0, 1e-2], got {}", tolerance);
  FeNewmarkOptions scheme = integrator;
  scheme.time_step = 1.0;  // replaced by T/N
  if (const std::string msg = scheme.validate(); !msg.empty()) return "integrator." + msg;
  return {};
}

std::vector<std::vector<contact::ContactPoint>> fe_point_laws(const preload::PreloadModel& model,
                                                             const preload::PreloadResult& preload,
                                                             const FeNewmarkOptions& options) {
  check_inputs(model, preload, {});
  std::vector<std::vector<contact::ContactPoint>> laws(model.interfaces.size());
  for (std::size_t i = 0; i < model.interfaces.size(); ++i) {
    const auto& ci = model.interfaces[i];
    const contact::ContactPointOptions& o = ci.law.options();
    const int points = ci.geometry.num_points();
    const bool freeze = options.preloaded_tangential_stiffness &&
                        o.stiffness_model == contact::TangentialStiffnessModel::proportional;
    if (!freeze) {
      laws[i].assign(static_cast<std::size_t>(points), ci.law);
      continue;
    }
    // k_T,p = χ λ p_N(g_pre,p) (eq. T-30), floored as hb/interface_balance.cpp does: a point open
    // in the preload keeps a valid (positive) constant stiffness and is open anyway.
    const double floor = o.tangential_stiffness_floor();
    laws[i].reserve(static_cast<std::size_t>(points));
    for (int p = 0; p < points; ++p) {
      const double gap = preload.interfaces[i].state.gap[3 * p + 2];
      const double k = ci.law.tangential_state(gap).limits.stiffness;
      laws[i].push_back(ci.law.with_constant_stiffness(std::max(k, floor)));
    }
  }
  return laws;
}

FeState preloaded_state(const preload::PreloadModel& model, const preload::PreloadResult& preload,
                        double time) {
  const int n = model.mesh->num_dofs();
  FeState s;
  s.displacement = Vec::Zero(n);
  s.velocity = Vec::Zero(n);
  for (const auto& i : preload.interfaces) {
    s.traction.push_back(i.state.traction);
    s.gap.push_back(i.state.gap);
  }
  s.time = time;
  return s;
}

std::optional<FeState> stuck_linear_fe_state(const preload::PreloadModel& model,
                                             const preload::PreloadResult& preload,
                                             const FeExcitation& excitation, double omega,
                                             const FeNewmarkOptions& options, double time) {
  check_inputs(model, preload, excitation);
  using Complex = std::complex<double>;
  using ComplexSparse = Eigen::SparseMatrix<Complex>;
  const int n = model.mesh->num_dofs();
  const fe::DofMap dofs = fe::DofMap::from_fixed_nodes(model.mesh->num_nodes(), model.constraints);
  const SpMat& kt = preload.dynamic_stiffness;
  const SpMat& m = model.structure.mass;
  FeState s = preloaded_state(model, preload, time);
  Vec amplitude = Vec::Zero(n);
  for (const auto& h : excitation.forces) amplitude[h.dof] += h.amplitude;
  if (!model.constraints.empty() && excitation.static_force.size() == n) {
    fe::SparseCholesky k;
    k.compute(dofs.restrict(kt));
    s.displacement = dofs.expand(k.solve(dofs.restrict(excitation.static_force)));
  }
  if (amplitude.cwiseAbs().maxCoeff() > 0.0) {
    // (K_t − Ω²M + iΩC) X = F,   C = a M + b K_t
    const SpMat re = dofs.restrict(SpMat(kt - omega * omega * m));
    const SpMat im = dofs.restrict(SpMat(omega * (options.mass_damping * m +
                                                  options.stiffness_damping * kt)));
    ComplexSparse z = re.cast<Complex>() + Complex(0.0, 1.0) * im.cast<Complex>();
    z.makeCompressed();
    Eigen::SparseLU<ComplexSparse> lu(z);
    if (lu.info() != Eigen::Success) return std::nullopt;
    const Eigen::VectorXcd rhs = dofs.restrict(amplitude).cast<Complex>();
    const Eigen::VectorXcd x = lu.solve(rhs);
    if (!x.allFinite() || (z * x - rhs).norm() > 1e-8 * rhs.norm()) return std::nullopt;
    const Eigen::VectorXcd xp = x * std::polar(1.0, omega * time);
    s.displacement += dofs.expand(xp.real());
    s.velocity += dofs.expand((Complex(0.0, omega) * xp).real());
  }
  // Tractions: the exact increment from the preloaded state to the gaps of w.
  const auto laws = fe_point_laws(model, preload, options);
  for (std::size_t i = 0; i < model.interfaces.size(); ++i) {
    const auto& ci = model.interfaces[i];
    const Vec g = preload.interfaces[i].state.gap + fe::gaps(ci.geometry, s.displacement);
    for (int p = 0; p < ci.geometry.num_points(); ++p) {
      const Eigen::Index k = 3 * p;
      s.traction[i].segment<3>(k) =
          laws[i][static_cast<std::size_t>(p)]
              .step(s.traction[i].segment<2>(k), s.gap[i].segment<3>(k), g.segment<3>(k))
              .traction;
    }
    s.gap[i] = g;
  }
  return s;
}

FeTransientResult integrate_fe(const preload::PreloadModel& model,
                               const preload::PreloadResult& preload,
                               const FeExcitation& excitation, double omega, FeState initial,
                               int steps, const FeNewmarkOptions& options,
                               const std::function<void(const FeState&)>& on_step) {
  const auto start = Clock::now();
  if (const std::string msg = options.validate(); !msg.empty())
    throw std::invalid_argument("fe newmark options: " + msg);
  if (steps < 0) throw std::invalid_argument(fmt::format("integrate_fe: steps: must be >= 0, got {}", steps));
  if (!std::isfinite(omega)) throw std::invalid_argument("integrate_fe: omega: must be finite");
  check_inputs(model, preload, excitation);
  check_state(initial, model);
  FeStepper stepper(model, preload, excitation, omega, options);
  stepper.complete(initial);

  FeTransientResult result;
  result.contact_dissipation.assign(model.interfaces.size(), 0.0);
  const double t0 = initial.time;
  FeState current = std::move(initial);
  FeState next;
  for (int i = 0; i < steps; ++i) {
    const double t = t0 + static_cast<double>(i + 1) * options.time_step;
    const auto o = stepper.step(current, t, next, result);
    result.newton_iterations += o.iterations;
    result.max_step_iterations = std::max(result.max_step_iterations, o.iterations);
    result.line_search_cuts += o.line_search_cuts;
    if (!o.converged) {
      result.termination = Termination::failed;
      result.message = newton_failure(o, i + 1, t, options.max_newton_iterations);
      break;
    }
    std::swap(current, next);
    ++result.steps;
    if (on_step) on_step(current);
  }
  result.factorizations = stepper.factorizations();
  result.final_state = std::move(current);
  result.seconds = seconds_since(start);
  return result;
}

FeSteadyStateResult fe_forced_steady_state(const preload::PreloadModel& model,
                                           const preload::PreloadResult& preload,
                                           const FeExcitation& excitation, double omega,
                                           const FeSteadyStateOptions& options,
                                           std::optional<FeState> initial) {
  const auto start = Clock::now();
  if (const std::string msg = options.validate(); !msg.empty())
    throw std::invalid_argument("fe steady state options: " + msg);
  if (!(omega > 0.0) || !std::isfinite(omega))
    throw std::invalid_argument(fmt::format("fe steady state: omega: must be finite and > 0, got {}", omega));
  check_inputs(model, preload, excitation);
  const int n = model.mesh->num_dofs();
  for (std::size_t j = 0; j < options.output_dofs.size(); ++j) {
    const int d = options.output_dofs[j];
    if (d < 0 || d >= n)
      throw std::invalid_argument(fmt::format(
          "fe steady state options: output_dofs[{}]: must lie in [0, {}], got {}", j, n - 1, d));
  }
  const int steps = options.steps_per_period;
  const auto outputs = static_cast<Eigen::Index>(options.output_dofs.size());

  FeSteadyStateResult result;
  result.period = 2.0 * std::numbers::pi / omega;
  result.time_step = result.period / steps;
  FeNewmarkOptions scheme = options.integrator;
  scheme.time_step = result.time_step;

  FeState state = initial ? std::move(*initial)
                          : stuck_linear_fe_state(model, preload, excitation, omega, scheme)
                                .value_or(preloaded_state(model, preload));
  check_state(state, model);
  FeStepper stepper(model, preload, excitation, omega, scheme);
  stepper.complete(state);
  const double t0 = state.time;

  result.samples.resize(outputs, steps);
  FeTransientResult ledger;
  FeState next;
  for (int p = 0; p < options.max_periods; ++p) {
    const FeState period_start = state;
    ledger = FeTransientResult{};
    ledger.contact_dissipation.assign(model.interfaces.size(), 0.0);
    double w_max = 0.0, v_max = 0.0;
    for (int j = 0; j < steps; ++j) {
      for (Eigen::Index k = 0; k < outputs; ++k)
        result.samples(k, j) = state.displacement[options.output_dofs[static_cast<std::size_t>(k)]];
      w_max = std::max(w_max, state.displacement.cwiseAbs().maxCoeff());
      v_max = std::max(v_max, state.velocity.cwiseAbs().maxCoeff());
      const long index = static_cast<long>(p) * steps + j + 1;
      const double t = t0 + static_cast<double>(index) * result.time_step;
      const auto o = stepper.step(state, t, next, ledger);
      ++result.steps;
      result.newton_iterations += o.iterations;
      result.max_step_iterations = std::max(result.max_step_iterations, o.iterations);
      result.line_search_cuts += o.line_search_cuts;
      if (!o.converged) {
        result.termination = Termination::failed;
        result.message = newton_failure(o, index, t, scheme.max_newton_iterations);
        result.periods = p;
        result.samples.resize(0, 0);
        result.final_state = std::move(state);
        result.factorizations = stepper.factorizations();
        result.seconds = seconds_since(start);
        result.seconds_per_step = result.seconds / static_cast<double>(result.steps);
        return result;
      }
      std::swap(state, next);
    }
    result.periods = p + 1;
    result.start_time = period_start.time;
    result.stored_energy_change = stepper.stored_energy(state) - stepper.stored_energy(period_start);
    const auto relative = [](double d, double scale) {
      return scale > 0.0 ? d / scale : (d > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
    };
    result.change = std::max(
        relative((state.displacement - period_start.displacement).cwiseAbs().maxCoeff(), w_max),
        relative((state.velocity - period_start.velocity).cwiseAbs().maxCoeff(), v_max));
    if (options.progress) options.progress(result.periods, result.change);
    if (result.change <= options.tolerance) {
      result.termination = Termination::converged;
      break;
    }
  }

  // Harmonics of the last period (absolute-time phase), as newmark.cpp.
  result.coefficients = period_harmonics(result.samples, omega, result.start_time, options.harmonics);
  result.external_work = ledger.external_work;
  result.viscous_dissipation = ledger.viscous_dissipation;
  result.contact_work = ledger.contact_work;
  result.contact_dissipation = ledger.contact_dissipation;
  result.final_state = std::move(state);
  result.factorizations = stepper.factorizations();
  result.message = result.termination == Termination::converged
                       ? fmt::format("steady state after {} periods (relative change {:.2e})",
                                     result.periods, result.change)
                       : fmt::format("no steady state after {} periods: relative change {:.2e} > "
                                     "tolerance {:.2e}",
                                     result.periods, result.change, options.tolerance);
  result.seconds = seconds_since(start);
  result.seconds_per_step = result.seconds / static_cast<double>(result.steps);
  return result;
}

}  // namespace jointhb::timeint
