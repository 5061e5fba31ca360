// Periodic steady state of a tangential law on a sampled path (periodic_state.hpp).
#include "jointhb/contact/periodic_state.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "../support/numeric_constants.hpp"

namespace jointhb::contact {
namespace {

using support::kEps;

// Minimum-norm solution of (I - M) x = b; directions with singular value below the threshold are
// those in which the periodicity condition does not fix the state (sticking throughout).
struct PeriodicSolve {
  Mat2 pseudo_inverse;  // (I - M)^+
  Mat2 null_projector;  // projector onto the null space of I - M
};

PeriodicSolve periodic_solve(const Mat2& monodromy) {
  const Mat2 a = Mat2::Identity() - monodromy;
  Eigen::JacobiSVD<Mat2> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vec2 sigma = svd.singularValues();
  const double threshold = kPeriodicSingular;
  PeriodicSolve r;
  r.pseudo_inverse.setZero();
  r.null_projector.setZero();
  for (int j = 0; j < 2; ++j) {
    const Vec2 v = svd.matrixV().col(j);
    if (sigma(j) > threshold) {
      r.pseudo_inverse += v * svd.matrixU().col(j).transpose() / sigma(j);
    } else {
      r.null_projector += v * v.transpose();
    }
  }
  return r;
}

Vec2 clamp_to(const Vec2& t, double limit) {
  const double norm = t.norm();
  return norm > limit && norm > 0.0 ? Vec2(t * (limit / norm)) : t;
}

struct Sweep {
  Vec2 end = Vec2::Zero();
  Mat2 monodromy = Mat2::Identity();
  double scale = 0.0;  // max |t_i| over the sweep
};

// One period of steps from t_0; fills `out` (tractions, derivatives, energy) when given.
Sweep sweep(const TangentialLaw& law, const PeriodicPath& path, const Vec2& t0,
            PeriodicStateResult* out) {
  const std::size_t n = path.slip.size();
  Sweep s;
  Vec2 t = t0;
  if (out) {
    out->traction.assign(n, Vec2::Zero());
    out->dissipation = 0.0;
    out->loading_slip = 0.0;
    out->stuck = true;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t next = (i + 1) % n;
    if (out) out->traction[i] = t;
    // Newton sweeps (out == nullptr) need forces and derivatives only, not the energy.
    const TangentialStep step =
        law.step(t, path.slip[next] - path.slip[i], path.limits[next], out != nullptr);
    t = step.traction;
    s.monodromy = step.d_traction * s.monodromy;
    s.scale = std::max(s.scale, t.norm());
    if (out) {
      out->dissipation += step.dissipation;
      out->loading_slip += step.loading_slip;
      out->stuck = out->stuck && step.elastic;
      if (!out->d_traction.empty()) {
        out->d_traction[i] = step.d_traction;
        out->d_slip[i] = step.d_slip;
        out->d_limit[i] = step.d_limit;
        out->d_stiffness[i] = step.d_stiffness;
      }
    }
  }
  s.end = t;
  return s;
}

}  // namespace

Status PeriodicStateResult::status() const {
  if (!message.empty()) return {termination, message};
  char line[96];
  std::snprintf(line, sizeof line, "%d iterations, residual %.3g", iterations, residual);
  return {termination, line};
}

std::string PeriodicStateOptions::validate() const {
  if (!(tolerance > 0.0 && tolerance <= 1.0e-3)) return "tolerance must lie in (0, 1e-3]";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (!reference_traction.allFinite()) return "reference_traction must be finite";
  if (!reference_slip.allFinite()) return "reference_slip must be finite";
  return {};
}

PeriodicStateResult solve_periodic_state(const TangentialLaw& law, const PeriodicPath& path,
                                         const PeriodicStateOptions& options) {
  if (const std::string msg = options.validate(); !msg.empty()) {
    throw std::invalid_argument("periodic state options: " + msg);
  }
  const std::size_t n = path.slip.size();
  if (n < 2 || path.limits.size() != n) {
    throw std::invalid_argument("periodic path: need N >= 2 samples with one limit per sample");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const auto& l = path.limits[i];
    if (!path.slip[i].allFinite() || !std::isfinite(l.slip_limit) || !std::isfinite(l.stiffness) ||
        l.slip_limit < 0.0 || l.stiffness < 0.0) {
      throw std::invalid_argument("periodic path: sample " + std::to_string(i) +
                                  " has a non-finite or negative slip, limit or stiffness");
    }
  }

  PeriodicStateResult result;
  result.anchor_offset = path.slip[0] - options.reference_slip;
  result.anchor_stiffness = path.limits[0].stiffness;
  // Anchor: the elastic branch through the reference state, on the limit at most.
  Vec2 t = clamp_to(options.reference_traction + result.anchor_stiffness * result.anchor_offset,
                    path.limits[0].slip_limit);

  // Damped Newton on r(t) = Φ_N(t) − t with the exact monodromy: the full step first, then
  // halved steps while the residual does not fall (the map is only piecewise smooth: a step that
  // crosses a stick/slip change of some sample overshoots), and a fixed-point step t ← Φ_N(t)
  // when no damped step helps. Every trial is one period, counted against max_iterations.
  Sweep s = sweep(law, path, t, nullptr);
  ++result.iterations;
  double residual = (s.end - t).norm();
  double previous_residual = std::numeric_limits<double>::infinity();
  int newton_steps = 0;
  double best_residual = std::numeric_limits<double>::infinity();
  Vec2 best_t = t;
  while (true) {
    // Converged relative to the loop's own traction scale (not the limit: at small amplitude
    // max|t| ≪ F_s), or at the round-off floor of one period of steps. The rounding of one period
    // is measured at 0.1–0.3 ε√N max|t|; a looser floor stops Newton before the conditioning
    // limit (F̂ was then up to 100× less accurate at a ~ 1e-6 g_max).
    const double noise = kEps * std::sqrt(static_cast<double>(n)) * s.scale;
    const bool stagnated =
        newton_steps >= 3 && residual > 0.5 * previous_residual && residual <= 64.0 * noise;
    if (residual <= options.tolerance * s.scale || residual <= 2.0 * noise || stagnated) {
      result.termination = Termination::converged;
      if (stagnated && residual > best_residual) t = best_t;
      break;
    }
    if (residual < best_residual) {
      best_residual = residual;
      best_t = t;
    }
    if (result.iterations >= options.max_iterations) break;
    previous_residual = residual;
    const PeriodicSolve solve = periodic_solve(s.monodromy);
    const Vec2 direction = solve.pseudo_inverse * (s.end - t);
    bool accepted = false;
    // Far from the steady state (residual above 1e-6 of the traction scale), Newton only where the
    // period map contracts locally (spectral radius of M below 1): with an eigenvalue above 1 its
    // linearisation points away from the steady state (a creeping, translation-like map). Close
    // to it, Newton always: its final steps are what reach round-off.
    const Mat2& mono = s.monodromy;
    const double tr = mono.trace(), det = mono(0, 0) * mono(1, 1) - mono(0, 1) * mono(1, 0), disc = 0.25 * tr * tr - det;
    const double radius = disc >= 0.0 ? std::abs(0.5 * tr) + std::sqrt(disc) : std::sqrt(std::max(det, 0.0));
    const bool far = residual > 1e-6 * s.scale;
    const bool newton = radius < 1.0 + 1e-9 || !far;
    if (newton && direction.norm() > 0.0) {
      for (double alpha = 1.0; alpha >= 1.0 / 64.0 && result.iterations < options.max_iterations; alpha *= 0.5) {
        const Vec2 trial = clamp_to(t + alpha * direction, path.limits[0].slip_limit);
        const Sweep st = sweep(law, path, trial, nullptr);
        ++result.iterations;
        const double r = (st.end - trial).norm();
        if (r < (1.0 - 1e-4 * alpha) * residual) {
          t = trial;
          s = st;
          residual = r;
          accepted = true;
          ++newton_steps;
          break;
        }
      }
    }
    if (!accepted && result.iterations < options.max_iterations) {
      // Fixed-point step t ← Φ_N(t), extrapolated along the drift r = Φ_N(t) − t (t + β r,
      // β = 2, 4, 8, …) while the residual grows by less than 2 % a doubling: far from the
      // steady state the period map can be nearly a translation (the state creeps by about the
      // same r every period, and the local monodromy has an eigenvalue slightly above 1, so no
      // Newton step helps). Only far from the steady state: near it the drift is round-off, and
      // a weakly contracting map would let it carry the state along a nearly null direction.
      // Newton is tried again from the point reached, so the final steps stay quadratic.
      const Vec2 drift = s.end - t;
      Vec2 next_t = clamp_to(s.end, path.limits[0].slip_limit);
      Sweep next_s = sweep(law, path, next_t, nullptr);
      ++result.iterations;
      double next_r = (next_s.end - next_t).norm();
      for (double beta = 2.0; far && beta <= 1048576.0 && result.iterations < options.max_iterations; beta *= 2.0) {
        const Vec2 trial = clamp_to(t + beta * drift, path.limits[0].slip_limit);
        const Sweep st = sweep(law, path, trial, nullptr);
        ++result.iterations;
        const double r = (st.end - trial).norm();
        if (!(r <= 1.02 * next_r)) break;  // a translation-like map keeps r nearly constant
        next_t = trial, next_s = st, next_r = r;
      }
      t = next_t;
      s = next_s;
      residual = next_r;
    }
  }
  if (result.termination != Termination::converged) t = best_t;  // the best state found

  if (options.keep_step_derivatives) {
    result.d_traction.assign(n, Mat2::Zero());
    result.d_slip.assign(n, Mat2::Zero());
    result.d_limit.assign(n, Vec2::Zero());
    result.d_stiffness.assign(n, Vec2::Zero());
  }
  const Sweep final_sweep = sweep(law, path, t, &result);
  result.monodromy = final_sweep.monodromy;
  result.residual = (final_sweep.end - t).norm();
  if (result.termination != Termination::converged) {
    result.message = "periodic state not converged after " + std::to_string(result.iterations) +
                     " periods; residual " + std::to_string(result.residual);
  }
  return result;
}

Eigen::MatrixXd periodic_sensitivity(const PeriodicStateResult& state, const Eigen::MatrixXd& slip,
                                     const Eigen::MatrixXd& limit,
                                     const Eigen::MatrixXd& stiffness) {
  const auto n = static_cast<Eigen::Index>(state.traction.size());
  if (static_cast<Eigen::Index>(state.d_traction.size()) != n) {
    throw std::invalid_argument(
        "periodic_sensitivity: the state has no step derivatives "
        "(solve with keep_step_derivatives = true)");
  }
  const Eigen::Index m = slip.cols();
  if (slip.rows() != 2 * n || (limit.size() && (limit.rows() != n || limit.cols() != m)) ||
      (stiffness.size() && (stiffness.rows() != n || stiffness.cols() != m))) {
    throw std::invalid_argument("periodic_sensitivity: perturbations must be 2N x m, N x m, N x m");
  }
  // Particular solution r_i (zero start) and homogeneous propagator Π_i, step by step:
  //   δt_{i+1} = A_i δt_i + B_i (δg_{i+1} - δg_i) + c_i δL_{i+1} + d_i δk_{i+1}.
  Eigen::MatrixXd particular(2 * n, m);
  std::vector<Mat2> propagator(static_cast<std::size_t>(n));
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(2, m);
  Mat2 pi = Mat2::Identity();
  for (Eigen::Index i = 0; i < n; ++i) {
    particular.middleRows(2 * i, 2) = r;
    propagator[static_cast<std::size_t>(i)] = pi;
    const Eigen::Index next = (i + 1) % n;
    const auto k = static_cast<std::size_t>(i);
    Eigen::MatrixXd forcing =
        state.d_slip[k] * (slip.middleRows(2 * next, 2) - slip.middleRows(2 * i, 2));
    if (limit.size()) forcing += state.d_limit[k] * limit.row(next);
    if (stiffness.size()) forcing += state.d_stiffness[k] * stiffness.row(next);
    r = state.d_traction[k] * r + forcing;
    pi = state.d_traction[k] * pi;
  }
  // Periodicity δt_0 = M δt_0 + r_N; the null directions of I - M follow the anchor
  // t_0 = t_ref + k_0 (g_0 - g_ref).
  const PeriodicSolve solve = periodic_solve(pi);
  Eigen::MatrixXd anchor = state.anchor_stiffness * slip.topRows(2);
  if (stiffness.size()) anchor += state.anchor_offset * stiffness.row(0);
  const Eigen::MatrixXd start = solve.pseudo_inverse * r + solve.null_projector * anchor;
  for (Eigen::Index i = 0; i < n; ++i) {
    particular.middleRows(2 * i, 2) += propagator[static_cast<std::size_t>(i)] * start;
  }
  return particular;
}

}  // namespace jointhb::contact
