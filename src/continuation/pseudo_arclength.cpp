// Pseudo-arclength continuation of R(x, λ) = 0 (pseudo_arclength.hpp; the method in
// docs/continuation.md).
//
// Every Newton iteration here, at fixed λ or on the arclength hyperplane, solves one bordered
// system in the scaled unknowns y = (x ./ x_scale, λ / λ_scale):
//   [ J_y ] Δy = - [ R / r_s   ],    J_y = [R_x D_x, R_λ λ_scale] / r_s,  r_s = residual_scale,
//   [ cᵀ  ]        [ cᵀ y - d  ]
// closed by the linear constraint cᵀ y = d:
//   λ = λ_fixed (start, final point on a bound):  c = e_λ,  d = λ_fixed / λ_scale;
//   τ_kᵀ (y - y_k) = s (arclength, Keller 1977):  c = τ_k,  d = τ_kᵀ y_k + s.
#include "jointhb/continuation/pseudo_arclength.hpp"

#include "../support/gmres.hpp"
#include "../support/lapack_lu.hpp"
#include "../support/stopwatch.hpp"
#include "bordered_preconditioner.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "../support/numeric_constants.hpp"

namespace jointhb::continuation {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using support::Clock;
using support::seconds_since;

using support::kEps;

// A small Newton step alone does not prove convergence (a stagnating iteration also makes small
// steps); it is accepted only when the residual is within three decades of the tolerance, which
// lets a run whose residual is floored by round-off (ε ‖R_x‖ ‖x‖ > tolerance · r_s) converge
// without ever accepting a point far from the branch.
constexpr double kSmallStepResidualFactor = 1.0e3;
// Newton steps after which a stagnating residual within kSmallStepResidualFactor of the tolerance
// is taken as the round-off floor of the evaluation (Tracer::correct).
constexpr int kStagnationIterations = 3;

// Halvings of the damped Newton step at the start point before giving up (α ≥ 2⁻¹⁰).
constexpr int kMaxHalvings = 20;
// Largest turn of the unit tangent accepted in one step (cos 60°), and the step (relative to
// max_step) below which a larger turn is taken as a corner of the branch and accepted.
constexpr double kMaxTurnCosine = 0.5;
constexpr double kCornerStepFactor = 0.05;
// At a corner the corrector on the hyperplane τ_kᵀ(y − y_k) = s lands s·tan θ from the predictor
// (θ: the turn of the branch), however short the step: a lightly damped friction FRF turns by
// about 80° (measured: correctors 4.7–12 steps from the predictor) where the stuck response
// reaches slip and the amplitude is held at the slip limit while the phase turns. Steps at or below kCornerStepFactor · max_step accept a corrector that moved up
// to this many steps (turns up to atan 10 = 84°; the tangent test above still guards longer steps).
constexpr double kCornerMoveFactor = 10.0;
// Least cosine between the tangent at a corner landing and the jump y_f − y_k (cos 84°, the
// largest turn kCornerMoveFactor admits).
constexpr double kCornerMinAlignment = 0.1;
// A landing must be new branch: one nearer than this fraction of its jump |y_f − y_k| to the part
// of the branch traced before (the polyline of all accepted points but y_k) has landed back on
// it, and the run would then trace that part again — around and around a sharp superharmonic
// loop, or back to λ_start (seen on a 10-DOF Gaul–Mayer chain at ζ = 1e-4:
// steps as long as the loop landed near its beginning; a corner landing at Ω = 0.183 landed back
// on the branch at 0.158). Rejected like a failed corrector: the halved step lands on the local
// branch, while a genuine close approach of two parts of the branch passes once the step is
// shorter than twice their distance. A forward step that turns by less than 90° lands farther than
// |y_f − y_k| from the point before y_k. The whole branch, not a window of the last points: on
// the 30-DOF chain's damping curve a returning crossing (cross_corner) was followed by 64 points
// that crept up to a point traced 64 points before, outside the window of 64 the test had then,
// and the run went on back along the whole branch and ended at λ_start, 398 points, as if it were
// a curve that turned back (the polyline costs one scaled copy of each point, (n + 1) doubles).
constexpr double kRetraceFraction = 0.5;
// A run whose last kCrawlPoints accepted points each came only after a landing back on the branch
// already traced creeps towards that branch: each step is halved because the distance to it
// shrinks, and the run would spend ~1 point per halving down to min_step (23 from max_step). It
// stops there as at min_step, and the FRF driver's crossing or the damping curve's run from its far
// end takes over. Where two parts of the branch only pass close to each other, the distance
// stops shrinking and a step of the same length passes without a landing on them (no growth
// right after a rejection). On the 10-DOF chain's undamped FRF (F = μF_N), whose stuck branch
// crosses the free families of the stuck system's superharmonic resonances (Ω = ω₆/5 = 0.3795,
// ω₃/3 = 0.4085 rad/s), such creeping took 16–240 points at a time (docs/continuation.md, "Safeguard
// against landing on the branch already traced").
constexpr int kCrawlPoints = 4;
// Crossing a corner: the step from y_k along the tangent at a point past the corner (trace()) is
// tried at steps at or below kCornerStepFactor · max_step; its landing is accepted within this many
// steps of its predictor (the branch is smooth past the corner) and when it does not go back along
// the branch: (y − y_k)·τ_k ≥ −kCornerMinAlignment |y − y_k| (at most 96° from the old direction),
// unless the orientation sign sent it back along −τ_f (a fold at a kink, trace()).
constexpr double kCrossingMoveFactor = 1.0;
// Natural-parameter fallback: tried once the arclength step has shrunk below this fraction of
// max_step, where the branch advances in λ (|dλ/ds| of the unit tangent above the second value).
constexpr double kNaturalStepFactor = 1e-3;
constexpr double kNaturalMinSlope = 1e-3;
constexpr double kNaturalMaxSlope = 1.0 / kNaturalMinSlope;
// Options::max_output_change is enforced down to this fraction of max_step (then accepted).
constexpr double kOutputMinStepFactor = 1e-3;
// Matrix-free Newton–Krylov: GMRES cycles (each of krylov_max_iterations) per linear solve.
constexpr int kMaxRestarts = 4;

// Distance from y to the polyline through the scaled points ys[0..m) (0 segments: infinity).
double distance_to_polyline(const std::vector<VectorXd>& ys, const VectorXd& y) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
    const VectorXd d = ys[j + 1] - ys[j];
    const double dd = d.squaredNorm();
    const double t = dd > 0.0 ? std::clamp((y - ys[j]).dot(d) / dd, 0.0, 1.0) : 0.0;
    best = std::min(best, (y - ys[j] - t * d).norm());
  }
  return best;
}

// Messages are one line: the residual function's own message may not be.
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  return text;
}

// R and its scaled Jacobian at one point.
struct Sample {
  std::uint64_t id = 0;  // which evaluation (1, 2, ...): a new Jacobian
  VectorXd y;         // scaled unknowns (x ./ D, λ / λ_scale)
  VectorXd x;         // physical state
  double lambda = 0;  // physical parameter (exact where it was fixed)
  VectorXd residual;  // R / r_s
  MatrixXd jacobian;  // J_y = [R_x D, R_λ λ_scale] / r_s, n × (n+1); empty when matrix-free
  double norm = 0;    // ‖R‖_∞ / r_s
  // Matrix-free Jacobian (Evaluation::d_state_product): v ↦ R_x v, R_λ λ_scale / r_s, and the
  // preconditioner factory.
  LinearOperator product;
  LinearOperator product_inner;         // cheaper, inexact (Evaluation::d_state_product_inner)
  double inner_accuracy = 0.0;          // its relative accuracy
  VectorXd d_lambda;
  std::function<LinearOperator()> make_preconditioner;
};

// Outcome of one Newton run.
struct Correction {
  bool converged = false;
  Sample sample;        // the converged point
  int iterations = 0;   // Newton steps (linear solves) taken
  std::string failure;  // why it did not converge
};

// The linear constraint cᵀ y = d that closes the bordered system; `fixed_lambda` is set when the
// constraint is λ = const, so that λ is kept exactly (not as λ_scale · (λ / λ_scale)).
struct Constraint {
  VectorXd c;
  double d = 0.0;
  std::optional<double> fixed_lambda;
};

class Tracer {
 public:
  Tracer(const ResidualFunction& residual, const Options& options, Index n, Result& result)
      : residual_(residual), options_(options), n_(n), result_(result) {
    state_scale_ = options.state_scale.size() ? options.state_scale : VectorXd::Ones(n);
  }

  VectorXd scaled(const VectorXd& x, double lambda) const {
    VectorXd y(n_ + 1);
    y.head(n_) = x.cwiseQuotient(state_scale_);
    y(n_) = lambda / options_.parameter_scale;
    return y;
  }

  Constraint fixed_lambda(double lambda) const {
    Constraint k;
    k.c = VectorXd::Unit(n_ + 1, n_);
    k.d = lambda / options_.parameter_scale;
    k.fixed_lambda = lambda;
    return k;
  }

  // Newton's method on the bordered system from y. Converged when ‖R‖_∞/r_s ≤ tol, or when the
  // last step had ‖Δy‖_∞ ≤ step_tolerance and ‖R‖_∞/r_s ≤ 1e3 tol (the residual is always that of
  // the returned point).
  //   Safeguard::growth_test: a residual that grows in two consecutive iterations is divergence
  //     (arclength steps: the caller retries with a shorter step).
  //   Safeguard::line_search: damped Newton y ← y + α Δy, α = 1, 1/2, … (at most kMaxHalvings
  //     halvings) until ‖R/r_s‖₂ decreases by the Armijo factor (1 − α/4) (the start: there is no
  //     shorter step to retry with, and a poor x0 needs globalisation).
  enum class Safeguard { growth_test, line_search };

  // `converged_before`: y is a point accepted by an earlier run, converged when its residual is within
  // kSmallStepResidualFactor of the tolerance as after a small last step (Options::continued).
  Correction correct(VectorXd y, const Constraint& constraint, int max_iterations,
                     Safeguard safeguard, bool converged_before = false) {
    Correction out;
    if (constraint.fixed_lambda) y(n_) = constraint.d;
    Sample sample;
    if (std::string why = evaluate(y, constraint.fixed_lambda, sample); !why.empty()) {
      out.failure = std::move(why);
      return out;
    }
    double previous = std::numeric_limits<double>::infinity();
    double best = std::numeric_limits<double>::infinity();
    double last_step = converged_before ? 0.0 : std::numeric_limits<double>::infinity();
    int growths = 0;
    for (int it = 0;; ++it) {
      const double tol = options_.residual_tolerance;
      // At the round-off floor of R (e.g. R/q of a damping curve at q ~ 1e-14, where the contact
      // forces are differences of preload-sized tractions) Newton stops making progress and its
      // residual wanders: after kStagnationIterations steps, a residual within three decades of
      // the tolerance that no longer halves is converged as far as the evaluation allows.
      const bool floor_reached = it >= kStagnationIterations &&
                                 sample.norm <= kSmallStepResidualFactor * tol &&
                                 sample.norm > 0.5 * previous;
      if (sample.norm <= tol || floor_reached ||
          (last_step <= options_.step_tolerance && sample.norm <= kSmallStepResidualFactor * tol)) {
        out.converged = true;
        out.iterations = it;
        out.sample = std::move(sample);
        return out;
      }
      best = std::min(best, sample.norm);
      if (it == max_iterations) {
        out.failure =
            fmt::format("no convergence in {} iterations (residual {:.3g}, smallest {:.3g})",
                        max_iterations, sample.norm, best);
        out.sample = std::move(sample);  // the last iterate (a point past a corner: trace())
        return out;
      }
      if (safeguard == Safeguard::growth_test && it > 0) {
        growths = sample.norm > previous && sample.norm > kSmallStepResidualFactor * options_.residual_tolerance
                      ? growths + 1
                      : 0;
        if (growths >= 2) {
          out.failure =
              fmt::format("residual grew in two consecutive iterations (to {:.3g} at iteration {})",
                          sample.norm, it);
          return out;
        }
      }
      previous = sample.norm;

      VectorXd rhs(n_ + 1);
      rhs.head(n_) = -sample.residual;
      rhs(n_) = constraint.d - constraint.c.dot(y);
      VectorXd step;
      if (const std::string why = solve_bordered(sample, constraint.c, rhs, step); !why.empty()) {
        out.failure = fmt::format("{} (residual {:.3g})", why, sample.norm);
        return out;
      }
      ++out.iterations;
      ++result_.corrector_iterations;

      const double merit = sample.residual.norm();
      double alpha = 1.0;
      std::string why;
      for (int halving = 0;; ++halving) {
        VectorXd trial = y + alpha * step;
        if (constraint.fixed_lambda) trial(n_) = constraint.d;
        Sample next;
        why = evaluate(trial, constraint.fixed_lambda, next);
        const bool descent = why.empty() && next.residual.norm() <= (1.0 - 0.25 * alpha) * merit;
        if (safeguard == Safeguard::growth_test || descent) {
          if (!why.empty()) break;
          y = std::move(trial);
          sample = std::move(next);
          break;
        }
        if (halving == kMaxHalvings) {
          if (why.empty()) {
            why = fmt::format(
                "no decrease of the residual {:.3g} along the Newton step after {} halvings "
                "(a minimum of |R| without a root, or a Jacobian inconsistent with R)",
                sample.norm, kMaxHalvings);
          }
          break;
        }
        alpha *= 0.5;
      }
      if (!why.empty()) {
        out.failure = std::move(why);
        return out;
      }
      last_step = alpha * step.lpNorm<Eigen::Infinity>();
    }
  }

  // Unit tangent at `sample`: the null vector of J_y, from the bordered system
  //   [ J_y ; τ_refᵀ ] τ = [ 0 ; 1 ],   τ ← τ / ‖τ‖,
  // which orients it with τ · τ_ref > 0. Where that matrix is singular (τ_ref ⟂ null(J_y), e.g. a
  // start exactly on a fold, or rank J_y < n), τ is the projection of τ_ref onto the numerical
  // kernel of J_y (FullPivLU), or its first basis vector when the projection vanishes.
  std::optional<VectorXd> tangent(const Sample& sample, const VectorXd& reference,
                                  std::string& why) {
    const VectorXd rhs = VectorXd::Unit(n_ + 1, n_);
    VectorXd t;
    std::string failure = solve_bordered(sample, reference, rhs, t);
    if (failure.empty() && t.norm() > 0.0 && std::isfinite(t.norm())) {
      // τ·τ_ref > 0, and det [J ; wᵀ] = wᵀ c(J) with c(J) ∥ τ (docs/continuation.md):
      // sign det [J ; τᵀ] = sign det [J ; τ_refᵀ], the matrix just factorised.
      tangent_sign_ = last_sign_;
      return VectorXd(t / t.norm());
    }
    tangent_sign_ = 0;
    if (sample.jacobian.size() == 0) {  // matrix-free: no kernel to fall back on
      why = "tangent: " + (failure.empty() ? std::string("zero or non-finite solution") : failure);
      return std::nullopt;
    }
    const auto start = Clock::now();
    const Eigen::FullPivLU<MatrixXd> lu(sample.jacobian);
    const MatrixXd kernel = lu.kernel();
    result_.linear_solve_seconds += seconds_since(start);
    if (kernel.cols() == 0 || !kernel.allFinite()) {
      why = "tangent: no null vector of the Jacobian";
      return std::nullopt;
    }
    const Eigen::HouseholderQR<MatrixXd> qr(kernel);
    const MatrixXd basis = qr.householderQ() * MatrixXd::Identity(n_ + 1, kernel.cols());
    VectorXd projected = basis * (basis.transpose() * reference);
    if (!(projected.norm() > kEps * reference.norm())) projected = basis.col(0);
    if (!projected.allFinite() || projected.norm() == 0.0) {
      why = "tangent: no null vector of the Jacobian";
      return std::nullopt;
    }
    return VectorXd(projected / projected.norm());
  }

  // sign det [J_y ; τᵀ] of the tangent last returned by tangent(), 0 when unknown (matrix-free,
  // a GMRES solve, or the kernel fallback): the orientation of Allgower & Georg (2003, §2.1),
  // constant along a smooth branch traversed one way and kept across a kink crossed
  // transversally (docs/continuation.md, "Crossing a corner").
  [[nodiscard]] int tangent_orientation() const { return tangent_sign_; }

 private:
  // Evaluates R and its Jacobian at y (λ = fixed_lambda when given); empty string when usable.
  std::string evaluate(const VectorXd& y, const std::optional<double>& fixed_lambda,
                       Sample& sample) {
    sample.id = ++samples_;
    sample.y = y;
    sample.x = y.head(n_).cwiseProduct(state_scale_);
    sample.lambda = fixed_lambda ? *fixed_lambda : y(n_) * options_.parameter_scale;
    if (!sample.x.allFinite() || !std::isfinite(sample.lambda)) return "non-finite iterate";
    // The Jacobian is always requested: the corrector needs it unless converged, and a converged
    // point needs it for its tangent.
    const auto start = Clock::now();
    Evaluation e;
    try {
      e = residual_(sample.x, sample.lambda, true);
    } catch (const std::exception& error) {
      // A point the model cannot evaluate (e.g. a contact law refusing a path from a diverging
      // corrector) is a failed evaluation like ok = false: the step is rejected, the run goes on.
      e.ok = false;
      e.message = error.what();
    }
    result_.evaluation_seconds += seconds_since(start);
    ++result_.evaluations;
    if (!e.ok) {
      return e.message.empty() ? std::string("evaluation failed")
                               : "evaluation failed: " + one_line(e.message);
    }
    const bool matrix_free = static_cast<bool>(e.d_state_product);
    if (matrix_free && options_.linear_solver != LinearSolver::newton_krylov) {
      throw std::logic_error(
          "continuation: a matrix-free Jacobian (d_state_product) needs linear_solver = newton_krylov");
    }
    if (e.residual.size() != n_ || e.d_parameter.size() != n_ ||
        (!matrix_free && (e.d_state.rows() != n_ || e.d_state.cols() != n_))) {
      throw std::logic_error(fmt::format(
          "continuation: the residual function returned R ({}), ∂R/∂x ({} x {}), ∂R/∂λ ({}); "
          "expected n = {} (with the Jacobian requested)",
          e.residual.size(), e.d_state.rows(), e.d_state.cols(), e.d_parameter.size(), n_));
    }
    if (!e.residual.allFinite()) return "non-finite residual";
    if (!e.d_state.allFinite() || !e.d_parameter.allFinite()) return "non-finite Jacobian";
    const double rs = options_.residual_scale;
    sample.residual = e.residual / rs;
    sample.norm = sample.residual.lpNorm<Eigen::Infinity>();
    if (matrix_free) {
      sample.jacobian.resize(0, 0);
      sample.product = std::move(e.d_state_product);
      sample.product_inner = std::move(e.d_state_product_inner);
      sample.inner_accuracy = e.inner_product_accuracy;
      sample.make_preconditioner = std::move(e.make_preconditioner);
      sample.d_lambda = e.d_parameter * (options_.parameter_scale / rs);
      return {};
    }
    sample.jacobian.resize(n_, n_ + 1);
    sample.jacobian.leftCols(n_) = e.d_state * state_scale_.asDiagonal() / rs;
    sample.jacobian.col(n_) = e.d_parameter * (options_.parameter_scale / rs);
    return {};
  }

  // [J_y; cᵀ] out = b, from the dense J_y (solve) or matrix-free (solve_matrix_free).
  std::string solve_bordered(const Sample& sample, const VectorXd& c, const VectorXd& b,
                             VectorXd& out) {
    last_sign_ = 0;
    if (sample.jacobian.size() == 0 && sample.product) return solve_matrix_free(sample, c, b, out);
    MatrixXd bordered(n_ + 1, n_ + 1);
    bordered.topRows(n_) = sample.jacobian;
    bordered.row(n_) = c.transpose();
    return solve(bordered, b, out);
  }

  // Matrix-free bordered system: A z = [(R_x (D z_x) / r_s + j_λ z_λ); cᵀ z], j_λ = R_λ λ_s / r_s,
  // by GMRES preconditioned with the block elimination of
  //   M = [ K̃   j_λ ],  K̃⁻¹ = r_s D⁻¹ Ã⁻¹,  Ã⁻¹ the lagged approximate inverse of R_x:
  //       [ c_xᵀ c_λ ]
  //   w₁ = K̃⁻¹ v_x,  w₂ = K̃⁻¹ j_λ,  z_λ = (v_λ − c_xᵀ w₁) / (c_λ − c_xᵀ w₂),  z_x = w₁ − w₂ z_λ.
  std::string solve_matrix_free(const Sample& sample, const VectorXd& c, const VectorXd& b,
                                VectorXd& out) {
    const auto start = Clock::now();
    const double rs = options_.residual_scale;
    const auto bordered = [&](const LinearOperator& product, const VectorXd& z) {
      VectorXd az(n_ + 1);
      az.head(n_) = product(VectorXd(z.head(n_).cwiseProduct(state_scale_))) / rs + sample.d_lambda * z(n_);
      az(n_) = c.dot(z);
      return az;
    };
    const auto apply = [&](const VectorXd& z) { return bordered(sample.product, z); };
    // Inside a GMRES cycle the cheaper inexact product when there is one; each cycle ends on the
    // true residual of the exact product, and asks for no more than the inexact product can give.
    const bool inexact = static_cast<bool>(sample.product_inner);
    const LinearOperator& inner_product = inexact ? sample.product_inner : sample.product;
    const auto apply_inner = [&](const VectorXd& z) { return bordered(inner_product, z); };
    bool fresh = false;
    std::string why;
    // every_jacobian: rebuilt from the first solve at a new Jacobian (counted, not timed, so the
    // solves do not depend on the machine's speed or the thread count).
    const bool stale = options_.preconditioner_refresh == PreconditionerRefresh::every_jacobian &&
                       approximate_inverse_ && preconditioner_sample_ != sample.id;
    for (;;) {
      if (!approximate_inverse_ || !why.empty() || (stale && !fresh)) {  // none, stale, or it just failed
        approximate_inverse_ = sample.make_preconditioner
                                   ? sample.make_preconditioner()
                                   : LinearOperator([](const VectorXd& v) { return v; });
        preconditioner_sample_ = sample.id;
        ++result_.factorisations;
        fresh = true;
      }
      const detail::BorderedPreconditioner bordered_inverse(
          [&](const VectorXd& v) { return VectorXd(rs * approximate_inverse_(v).cwiseQuotient(state_scale_)); },
          sample.d_lambda, c);
      const auto precondition = [&](const VectorXd& v) { return bordered_inverse(v); };
      // Restarted GMRES (kMaxRestarts cycles on the true residual b − A z): with an approximate
      // preconditioner of an ill-conditioned matrix the recursive residual of one cycle can drift
      // below the true one; a restart from z corrects that (iterative refinement).
      VectorXd z = VectorXd::Zero(n_ + 1);
      VectorXd residual = b;
      double true_residual = b.norm();
      int iterations = 0;
      bool converged = true_residual == 0.0;
      const int cycles = inexact ? 2 * kMaxRestarts : kMaxRestarts;
      for (int cycle = 0; cycle < cycles && !converged; ++cycle) {
        VectorXd dz;
        double cycle_tolerance = options_.krylov_tolerance * b.norm() / true_residual;
        if (inexact) cycle_tolerance = std::max(cycle_tolerance, 10.0 * sample.inner_accuracy);
        const support::GmresOutcome g = support::gmres(apply_inner, precondition, residual,
                                                       options_.krylov_max_iterations, cycle_tolerance, dz);
        iterations += g.iterations;
        if (!dz.allFinite()) break;
        z += dz;
        residual = b - apply(z);
        const double previous = true_residual;
        true_residual = residual.norm();
        converged = true_residual <= options_.krylov_tolerance * b.norm();
        if (!g.converged && true_residual > 0.5 * previous) break;  // stagnation: not worth a restart
      }
      result_.krylov_iterations += iterations;
      if (converged) {
        out = std::move(z);
        why.clear();
        break;
      }
      why = fmt::format("GMRES: relative residual {:.3g} after {} iterations{}",
                        true_residual / b.norm(), iterations,
                        fresh ? " with a fresh preconditioner" : "");
      if (fresh) break;
    }
    result_.linear_solve_seconds += seconds_since(start);
    return why;
  }

  // The bordered system a · out = b (docs/continuation.md §2).
  //   dense_lu: LU with partial pivoting (LAPACK, support/lapack_lu.hpp); numerically singular
  //     (reciprocal condition estimate below ε: the solution would carry no correct digit) or a
  //     non-finite solution is a failure.
  //   newton_krylov: GMRES (support/gmres.hpp) preconditioned by the LU of the last matrix that
  //     was factorised; accepted when the true residual ‖b − a·out‖₂ ≤ krylov_tolerance ‖b‖₂
  //     within krylov_max_iterations, else `a` itself is factorised (the new preconditioner) and
  //     the system solved by that LU exactly as dense_lu does.
  std::string solve(const MatrixXd& a, const VectorXd& b, VectorXd& out) {
    const auto start = Clock::now();
    std::string why;
    last_sign_ = 0;
    if (options_.linear_solver == LinearSolver::newton_krylov && preconditioner_ &&
        preconditioner_size_ == a.rows()) {
      VectorXd z;
      const support::GmresOutcome g = support::gmres(
          [&](const VectorXd& v) { return VectorXd(a * v); },
          [&](const VectorXd& v) { return preconditioner_->solve(v); }, b,
          options_.krylov_max_iterations, options_.krylov_tolerance, z);
      result_.krylov_iterations += g.iterations;
      if (g.converged && z.allFinite() &&
          (b - a * z).norm() <= options_.krylov_tolerance * b.norm()) {
        out = std::move(z);
        result_.linear_solve_seconds += seconds_since(start);
        return why;
      }
    }
    auto lu = std::make_unique<support::LapackLu>(a);
    ++result_.factorisations;
    const double rcond = lu->rcond();
    if (!(rcond >= kEps)) {
      why = fmt::format("singular bordered matrix (reciprocal condition {:.2g})", rcond);
      preconditioner_.reset();
    } else {
      out = lu->solve(b);
      last_sign_ = lu->determinant_sign();
      if (!out.allFinite()) why = "non-finite solution of the bordered system";
      if (options_.linear_solver == LinearSolver::newton_krylov) {
        preconditioner_ = std::move(lu);
        preconditioner_size_ = a.rows();
      }
    }
    result_.linear_solve_seconds += seconds_since(start);
    return why;
  }

  int last_sign_ = 0;     // sign det of the last bordered matrix factorised by solve() (0: none)
  int tangent_sign_ = 0;  // sign det [J ; τᵀ] of the last tangent() (0: unknown)

  const ResidualFunction& residual_;
  const Options& options_;
  Index n_;
  Result& result_;
  VectorXd state_scale_;
  std::unique_ptr<support::LapackLu> preconditioner_;  // newton_krylov: the lagged LU
  LinearOperator approximate_inverse_;  // matrix-free: the lagged approximate inverse of R_x
  std::uint64_t preconditioner_sample_ = 0;  // Sample::id the approximate inverse was built at
  std::uint64_t samples_ = 0;                 // evaluations so far (Sample::id)
  Index preconditioner_size_ = 0;
};

std::string describe_point(const Point& p, std::size_t count) {
  return fmt::format("λ = {:.10g} (point {})", p.lambda, count);
}

}  // namespace

std::string Options::validate(Eigen::Index n) const {
  auto positive = [](const char* name, double v) -> std::string {
    if (std::isfinite(v) && v > 0.0) return {};
    return fmt::format("{}: must be finite and > 0, got {}", name, v);
  };
  if (auto m = positive("initial_step", initial_step); !m.empty()) return m;
  if (!(std::isfinite(min_step) && min_step > 0.0 && min_step <= initial_step)) {
    return fmt::format("min_step: must lie in (0, initial_step = {}], got {}", initial_step,
                       min_step);
  }
  if (!(std::isfinite(max_step) && max_step >= initial_step)) {
    return fmt::format("max_step: must be finite and >= initial_step = {}, got {}", initial_step,
                       max_step);
  }
  if (!(std::isfinite(max_output_change) && max_output_change >= 0.0))
    return fmt::format("max_output_change: must be finite and >= 0, got {}", max_output_change);
  if (!(std::isfinite(max_state_turn) && max_state_turn >= 0.0 && max_state_turn <= std::numbers::pi))
    return fmt::format("max_state_turn: must lie in [0, pi], got {}", max_state_turn);
  if (!(std::isfinite(max_parameter_step) && max_parameter_step >= 0.0)) {
    return fmt::format("max_parameter_step: must be finite and >= 0, got {}", max_parameter_step);
  }
  if (max_points < 1) return fmt::format("max_points: must be >= 1, got {}", max_points);
  if (!std::isfinite(parameter_start)) {
    return fmt::format("parameter_start: must be finite, got {}", parameter_start);
  }
  if (!std::isfinite(parameter_end) || parameter_end == parameter_start) {
    return fmt::format("parameter_end: must be finite and differ from parameter_start = {}, got {}",
                       parameter_start, parameter_end);
  }
  const int sign = parameter_end > parameter_start ? 1 : -1;
  if (direction != sign) {
    return fmt::format("direction: must be sign(parameter_end - parameter_start) = {}, got {}",
                       sign, direction);
  }
  if (max_corrector_iterations < 1) {
    return fmt::format("max_corrector_iterations: must be >= 1, got {}", max_corrector_iterations);
  }
  if (max_start_iterations < 1) {
    return fmt::format("max_start_iterations: must be >= 1, got {}", max_start_iterations);
  }
  if (target_corrector_iterations < 1 || target_corrector_iterations > max_corrector_iterations) {
    return fmt::format(
        "target_corrector_iterations: must lie in [1, max_corrector_iterations = {}], got {}",
        max_corrector_iterations, target_corrector_iterations);
  }
  if (!(std::isfinite(step_growth) && step_growth > 1.0)) {
    return fmt::format("step_growth: must be finite and > 1, got {}", step_growth);
  }
  if (auto m = positive("residual_tolerance", residual_tolerance); !m.empty()) return m;
  if (auto m = positive("residual_scale", residual_scale); !m.empty()) return m;
  if (auto m = positive("step_tolerance", step_tolerance); !m.empty()) return m;
  if (state_scale.size() != 0 && state_scale.size() != n) {
    return fmt::format("state_scale: must have size n = {} (or be empty), got {}", n,
                       state_scale.size());
  }
  for (Index i = 0; i < state_scale.size(); ++i) {
    if (!(std::isfinite(state_scale(i)) && state_scale(i) > 0.0)) {
      return fmt::format("state_scale: entry {} must be finite and > 0, got {}", i, state_scale(i));
    }
  }
  if (auto m = positive("parameter_scale", parameter_scale); !m.empty()) return m;
  if (continued) {
    if (!std::isfinite(continued->lambda)) return fmt::format("continued.lambda: must be finite, got {}", continued->lambda);
    if (continued->tangent.size() != n + 1 || !continued->tangent.allFinite() || continued->tangent.norm() == 0.0)
      return fmt::format("continued.tangent: must have size n + 1 = {}, be finite and non-zero", n + 1);
  }
  if (linear_solver != LinearSolver::dense_lu && linear_solver != LinearSolver::newton_krylov) {
    return "linear_solver: must be dense_lu or newton_krylov";
  }
  if (krylov_max_iterations < 1 || krylov_max_iterations > 1000) {
    return fmt::format("krylov_max_iterations: must lie in [1, 1000], got {}", krylov_max_iterations);
  }
  if (!(krylov_tolerance > 0.0 && krylov_tolerance <= 1e-6)) {
    return fmt::format("krylov_tolerance: must lie in (0, 1e-6], got {}", krylov_tolerance);
  }
  return {};
}

std::string_view to_string(StopReason reason) {
  switch (reason) {
    case StopReason::reached_end:
      return "reached_end";
    case StopReason::max_points:
      return "max_points";
    case StopReason::min_step:
      return "min_step";
    case StopReason::start_failed:
      return "start_failed";
    case StopReason::stopped_by_user:
      return "stopped_by_user";
    case StopReason::left_range:
      return "left_range";
    case StopReason::out_of_range:
      return "out_of_range";
    case StopReason::error:
      return "error";
  }
  return "unknown";
}

Termination termination(StopReason reason) {
  switch (reason) {
    case StopReason::reached_end:
      return Termination::reached_end;
    case StopReason::stopped_by_user:
      return Termination::stopped_by_user;
    case StopReason::max_points:
      return Termination::no_convergence;
    case StopReason::min_step:
    case StopReason::start_failed:
    case StopReason::left_range:
    case StopReason::out_of_range:
    case StopReason::error:
      return Termination::failed;
  }
  return Termination::failed;
}

Result trace(const ResidualFunction& residual, const Eigen::VectorXd& x0, const Options& options,
             const AcceptCallback& on_accept) {
  const Index n = x0.size();
  if (n < 1) throw std::invalid_argument("continuation: x0 must have at least one entry");
  for (Index i = 0; i < n; ++i) {
    if (!std::isfinite(x0(i))) {
      throw std::invalid_argument(
          fmt::format("continuation: x0 entry {} must be finite, got {}", i, x0(i)));
    }
  }
  if (const std::string m = options.validate(n); !m.empty()) {
    throw std::invalid_argument("continuation options: " + m);
  }
  if (!residual) throw std::invalid_argument("continuation: the residual function is empty");

  Result result;
  Tracer tracer(residual, options, n, result);
  const double sigma = options.parameter_end > options.parameter_start ? 1.0 : -1.0;
  // Beyond the end / behind the start, measured along the direction of travel start → end.
  auto beyond_end = [&](double lambda) { return sigma * (lambda - options.parameter_end) >= 0.0; };
  auto behind_start = [&](double lambda) {
    return sigma * (lambda - options.parameter_start) <= 0.0;
  };

  // Start: damped Newton at fixed λ = parameter_start from x0 (a poor x0 needs globalisation, and
  // there is no shorter step to retry with), or, for a continued run, on the hyperplane through x0
  // normal to its tangent (Options::continued).
  const double lambda0 = options.continued ? options.continued->lambda : options.parameter_start;
  VectorXd e_lambda = options.direction * VectorXd::Unit(n + 1, n);
  Constraint start_constraint = tracer.fixed_lambda(lambda0);
  if (options.continued) {
    e_lambda = tracer.scaled(options.continued->tangent.head(n), options.continued->tangent[n]).normalized();
    start_constraint = Constraint{e_lambda, e_lambda.dot(tracer.scaled(x0, lambda0)), std::nullopt};
  }
  const Correction start = tracer.correct(tracer.scaled(x0, lambda0), start_constraint,
                                          options.max_start_iterations, Tracer::Safeguard::line_search,
                                          options.continued.has_value());
  if (!start.converged) {
    result.reason = StopReason::start_failed;
    result.message = fmt::format("start: the corrector at {} λ = {:.10g} failed: {}",
                                 options.continued ? "the continued point," : "fixed", lambda0, start.failure);
    return result;
  }
  std::string why;
  const std::optional<VectorXd> start_tangent = tracer.tangent(start.sample, e_lambda, why);
  if (!start_tangent) {
    result.reason = StopReason::start_failed;
    result.message = fmt::format("start: at λ = {:.10g}: {}", lambda0, why);
    return result;
  }

  VectorXd y = start.sample.y;  // y_k, the last accepted point (scaled)
  VectorXd tau = *start_tangent;
  int orientation = tracer.tangent_orientation();  // sign det [J ; τᵀ] at y_k (0: unknown)
  // Accepts a point; returns false when the run ends here (reason and message set).
  auto accept = [&](Point point, bool on_bound, StopReason bound_reason) {
    result.points.push_back(std::move(point));
    const Point& p = result.points.back();
    const bool user_continue = on_accept ? on_accept(p) : true;
    const std::string where = describe_point(p, result.points.size());
    if (on_bound) {  // the run is complete whatever the callback says
      result.reason = bound_reason;
      result.message =
          bound_reason == StopReason::reached_end
              ? fmt::format("reached λ_end = {:.10g} ({} points, {} rejected steps)", p.lambda,
                            result.points.size(), result.rejected_steps)
              : fmt::format("the branch turned back across λ_start: last point on it, {}", where);
      return false;
    }
    if (!user_continue) {
      result.reason = StopReason::stopped_by_user;
      result.message = "stopped by the accept callback at " + where;
      return false;
    }
    if (static_cast<int>(result.points.size()) >= options.max_points) {
      result.reason = StopReason::max_points;
      result.message = fmt::format("max_points = {} reached at {}", options.max_points, where);
      return false;
    }
    return true;
  };

  {
    Point p;
    p.x = start.sample.x;
    p.lambda = start.sample.lambda;
    p.tangent = tau;
    p.iterations = start.iterations;
    p.residual = start.sample.norm;
    if (!accept(std::move(p), false, StopReason::reached_end)) return result;
  }

  // The step capped by max_parameter_step along the tangent τ (at least min_step).
  const auto capped = [&](double step, const VectorXd& t) {
    const double slope = std::abs(t(n)) * options.parameter_scale;  // |dλ/ds|
    if (options.max_parameter_step > 0.0 && slope > 0.0)
      step = std::min(step, std::max(options.max_parameter_step / slope, options.min_step));
    return step;
  };
  double s = capped(options.initial_step, tau);
  // The scaled accepted points before y_k, and the test of a landing y_f against their polyline
  // (kRetraceFraction).
  std::vector<VectorXd> traced;
  const auto retraces = [&](const VectorXd& y_f) {
    return distance_to_polyline(traced, y_f) < kRetraceFraction * (y_f - y).norm();
  };
  // A landing on the last step itself (the segment y_{k−1} y_k, which `retraces` leaves out): the
  // run would turn round and go back the way it came (kRetraceFraction).
  const auto reverses = [&](const VectorXd& y_f) {
    return !traced.empty() &&
           distance_to_polyline({traced.back(), y}, y_f) < kRetraceFraction * (y_f - y).norm();
  };
  // The outputs limited by max_output_change at the last accepted point, and the largest relative
  // change of one of them over a step (output_change).
  const bool limit_outputs = options.max_output_change > 0.0 && static_cast<bool>(options.outputs);
  VectorXd last_outputs = limit_outputs ? options.outputs(start.sample.x, start.sample.lambda) : VectorXd();
  VectorXd next_outputs;
  const auto output_change = [&](const VectorXd& o) {
    double worst = 0.0;
    for (Eigen::Index i = 0; i < o.size() && i < last_outputs.size(); ++i) {
      const double base = std::abs(last_outputs[i]);
      if (base > 0.0 && std::isfinite(o[i])) worst = std::max(worst, std::abs(o[i] - last_outputs[i]) / base);
    }
    return worst;
  };
  // Crossing a corner of the branch (docs/continuation.md, "Crossing a corner"). Where the branch
  // turns by ~90° (the stuck response of an undamped friction FRF reaching the slip amplitude:
  // the amplitude stops at X_s and the phase turns), the hyperplane τ_kᵀ(y − y_k) = s is nearly
  // parallel to the branch beyond the corner and cuts it far from the predictor or not at all,
  // however short the step. The tangent τ_f at a point f past the corner — a landing the checks
  // refused, or the last iterate of a corrector that did not converge — oriented along f − y_k,
  // gives the hyperplane τ_fᵀ(y − y_k) = s that cuts the branch beyond the corner about s from y_k.
  struct Crossing {
    Correction correction;
    VectorXd tangent;
    int orientation = 0;  // sign det [J ; τᵀ] there
  };
  // The step along the unit direction t_f from y_k, its corrector on τ_fᵀ(y − y_k) = s, and the
  // checks of its landing; `back`: a step the orientation sign sent back along the branch.
  const auto cross_along = [&](const VectorXd& t_f, double step,
                                bool back) -> std::optional<Crossing> {
    Constraint plane;
    plane.c = t_f;
    plane.d = t_f.dot(y) + step;
    const VectorXd predicted = y + step * t_f;
    Correction k = tracer.correct(predicted, plane, options.max_corrector_iterations,
                                  Tracer::Safeguard::line_search);
    if (!k.converged) return std::nullopt;
    const VectorXd moved = k.sample.y - y;
    if ((k.sample.y - predicted).norm() > kCrossingMoveFactor * step ||
        (!back && moved.dot(tau) < -kCornerMinAlignment * moved.norm()) ||
        retraces(k.sample.y) || beyond_end(k.sample.lambda) || behind_start(k.sample.lambda) ||
        (back && reverses(k.sample.y)))
      return std::nullopt;
    std::string ignored;
    std::optional<VectorXd> t = tracer.tangent(k.sample, t_f, ignored);
    if (!t || t->dot(t_f) < kMaxTurnCosine) return std::nullopt;
    return Crossing{std::move(k), std::move(*t), tracer.tangent_orientation()};
  };
  const auto cross_corner = [&](const Sample& far, double step) -> std::optional<Crossing> {
    if (far.y.size() != n + 1 || (far.jacobian.size() == 0 && !far.product)) return std::nullopt;
    const VectorXd jump = far.y - y;
    if (!(jump.norm() > 0.0) || !jump.allFinite()) return std::nullopt;
    std::string ignored;
    const std::optional<VectorXd> t_far = tracer.tangent(far, jump / jump.norm(), ignored);
    if (!t_far) return std::nullopt;
    // Along the jump first, where τ_f turned by more than 60° from τ_k (a corner). Then, where
    // that found nothing and the orientation sign det [J ; τᵀ] (kept across a kink of the
    // residual, docs/continuation.md, "Crossing a corner") says the other way than the jump, back
    // along −τ_f: the branch comes back on the far sheet (a fold at a kink: the 7:1 internal
    // resonance of the 30-DOF chain's damping curve). The way back is tried whatever the angle
    // between τ_f and τ_k: a fold at a kink that turns the branch by 122° (τ_f · τ_k = 0.526, the
    // chain at log10 q = −0.9137) is no corner by the 60° test of the way ahead, and the curve
    // stopped there until stop 48. Not back first: DiscreteFit.TwoDofRecoversBothJointsFromTwoModes
    // failed (measured in stop 46, with one start; not analysed). A way back that lands on the last
    // step itself (`reverses`) finds no far sheet and only turns the run round: on the 10-DOF
    // chain's damping curve at ζ = 1e-4 (H = 7, light-damping corpus) it landed at log10 q =
    // 2.34595, between the two points before, and the run crept back towards the first of them over
    // 100 points to min_step; refused, the shorter step that follows passes the fold that lies
    // 1.5·10⁻³ (scaled) beyond (measured by solving on spheres about the points: the branch is
    // regular there and turns back within 1–3·10⁻³), and the curve completes at H = 5, 7 and 9.
    const int far_orientation = tracer.tangent_orientation();  // of τ_f, just computed
    const bool returning = orientation != 0 && far_orientation != 0 && orientation != far_orientation;
    if (t_far->dot(tau) <= kMaxTurnCosine)  // a corner
      if (std::optional<Crossing> ahead = cross_along(*t_far, step, false)) return ahead;
    if (!returning) return std::nullopt;
    return cross_along(-*t_far, step, true);
  };
  double observed_change = 0.0;
  bool rejected_since_accept = false;
  bool retraced_since_accept = false;  // a landing back on the traced branch since the last point
  int creeping = 0;                    // accepted points in a row that each came after one (kCrawlPoints)
  std::string last_failure;
  for (;;) {
    // Predictor y_k + s τ_k, corrector on the hyperplane τ_kᵀ (y - y_k) = s.
    const VectorXd predicted = y + s * tau;
    Constraint arclength;
    arclength.c = tau;
    arclength.d = tau.dot(y) + s;
    Correction c = tracer.correct(predicted, arclength, options.max_corrector_iterations,
                                  Tracer::Safeguard::growth_test);
    std::string failure = c.converged ? std::string() : c.failure;
    // A corrector that lands farther from the predictor than the step itself has left the
    // neighbourhood of the predicted point (step too long for the curvature, or a jump to another
    // part of the branch).
    const bool corner_step = s <= kCornerStepFactor * options.max_step;
    const double max_move = corner_step ? kCornerMoveFactor * s : s;
    if (failure.empty() && (c.sample.y - predicted).norm() > max_move) {
      failure = fmt::format("the corrector moved {:.3g} from the predictor, more than {}the step",
                            (c.sample.y - predicted).norm(), corner_step ? "10 times " : "");
    }
    if (failure.empty() && retraces(c.sample.y)) {
      failure = fmt::format("the corrector jumped {:.3g} back onto the branch already traced",
                            (c.sample.y - y).norm());
      retraced_since_accept = true;
    }

    // A point beyond λ_end (or behind λ_start) is replaced by the corrector at fixed λ on that
    // bound, started from the linear interpolation between y_k and the crossing point.
    bool on_bound = false;
    StopReason bound_reason = StopReason::reached_end;
    if (failure.empty() && (beyond_end(c.sample.lambda) || behind_start(c.sample.lambda))) {
      on_bound = true;
      const bool end = beyond_end(c.sample.lambda);
      bound_reason = end ? StopReason::reached_end : StopReason::left_range;
      const double bound = end ? options.parameter_end : options.parameter_start;
      if (c.sample.lambda != bound) {
        const double lambda_k = result.points.back().lambda;
        const double theta = (bound - lambda_k) / (c.sample.lambda - lambda_k);
        const VectorXd guess = y + theta * (c.sample.y - y);
        Correction b =
            tracer.correct(guess, tracer.fixed_lambda(bound), options.max_corrector_iterations,
                           Tracer::Safeguard::growth_test);
        if (!b.converged) {
          failure = fmt::format("corrector at fixed λ = {:.10g} failed: {}", bound, b.failure);
        } else if ((b.sample.y - guess).norm() > s) {
          failure = fmt::format("corrector at fixed λ = {:.10g} moved {:.3g} from its guess", bound,
                                (b.sample.y - guess).norm());
        } else {
          c = std::move(b);
        }
      }
    }

    std::optional<VectorXd> next_tau;
    int next_orientation = 0;  // sign det [J ; τᵀ] with τ = next_tau (0: unknown)
    if (failure.empty()) {
      next_tau = tracer.tangent(c.sample, tau, why);
      next_orientation = tracer.tangent_orientation();
      if (!next_tau) failure = why;
    }
    // After a landing longer than the step, the direction of travel is the secant y_f − y_k, not
    // the old tangent: the landing can lie past two folds of a sharp loop (seen on the 10-DOF
    // chain: the old tangent's orientation sent the run back down the loop and along the whole
    // branch to λ_start). At the slip-onset corners of the unit tests' friction FRFs both agree.
    if (failure.empty() && (c.sample.y - predicted).norm() > s &&
        next_tau->dot(c.sample.y - y) < 0.0) {
      *next_tau = -*next_tau;
      next_orientation = -next_orientation;
    }
    // A corner landing (farther than the step from the predictor) must continue along the jump:
    // past a corner that turns the branch by θ ≤ 84° (kCornerMoveFactor) the tangent there makes
    // less than θ with the secant y_f − y_k. A landing whose tangent is nearly normal to the jump
    // sits on another part of a sharply folded branch (seen on a 10-DOF Gaul–Mayer chain at ζ =
    // 1e-3: a landing 5.3 steps off, tangent at 88° to the jump, from which the run went back
    // along the branch and stalled at a non-smooth point).
    if (failure.empty() && (c.sample.y - predicted).norm() > s) {
      const double along = next_tau->dot(c.sample.y - y) / (c.sample.y - y).norm();
      if (along < kCornerMinAlignment)
        failure = fmt::format(
            "the corrector landed {:.3g} steps from the predictor with the tangent at {:.0f}° to the jump",
            (c.sample.y - predicted).norm() / s,
            std::acos(std::clamp(along, -1.0, 1.0)) * 180.0 / std::numbers::pi);
    }
    // A tangent that turned by more than 60° over one step means the step jumped over a sharp
    // feature (e.g. a jagged peak); its orientation by continuity is then a guess and can send
    // the run back along the branch. Retry shorter, except at a genuine corner of the branch
    // (stick–slip onset), where the turn persists however short the step.
    if (failure.empty() && tau.dot(*next_tau) < kMaxTurnCosine &&
        s > kCornerStepFactor * options.max_step) {
      failure = fmt::format(
          "the tangent turned by {:.0f}° in one step",
          std::acos(std::clamp(tau.dot(*next_tau), -1.0, 1.0)) * 180.0 / std::numbers::pi);
    }
    // The orientation sign det [J ; τᵀ] is kept along a smooth branch and across a kink crossed
    // transversally (docs/continuation.md, "Crossing a corner"). A step over which it changed
    // passed a fold at a kink, where the branch comes back on another sheet and the tangent
    // oriented by τ_k points the wrong way along it, or a point where sheets meet, or a simple
    // bifurcation point: retried shorter until the corner crossing or the natural-parameter
    // fallback below decides (on the 30-DOF chain's damping curve, a step of 5e-3 over a kink at
    // log10 q ≈ −0.8445 landed where the sign had changed, and the next corner crossing took
    // the run back along the sheet it had come on).
    if (failure.empty() && orientation != 0 && next_orientation != 0 &&
        next_orientation != orientation) {
      failure = fmt::format(
          "the orientation sign det [J; τ] changed over the step (tangent turned by {:.0f}°)",
          std::acos(std::clamp(tau.dot(*next_tau), -1.0, 1.0)) * 180.0 / std::numbers::pi);
    }

    // A short step that failed at a corner: cross it along the tangent beyond it.
    if (!failure.empty() && corner_step && c.sample.y.size() == n + 1) {
      if (std::optional<Crossing> crossed = cross_corner(c.sample, s)) {
        c = std::move(crossed->correction);
        next_tau = std::move(crossed->tangent);
        next_orientation = crossed->orientation;
        failure.clear();
        on_bound = false;
      }
    }

    // Natural-parameter fallback at a corner of the branch (e.g. the onset of slip of a Jenkins
    // contact): where short arclength steps keep failing although the branch advances in λ, a
    // corrector at fixed λ_k + Δλ from the last point crosses the corner.
    if (!failure.empty() && s <= kNaturalStepFactor * options.max_step &&
        std::abs(tau(n)) > kNaturalMinSlope) {
      const double lambda_k = result.points.back().lambda;
      const double dl = (tau(n) > 0.0 ? 1.0 : -1.0) * 4.0 * s * options.parameter_scale;
      double target = lambda_k + dl;
      if (beyond_end(target)) target = options.parameter_end;
      Correction b =
          tracer.correct(y, tracer.fixed_lambda(target), options.max_corrector_iterations,
                         Tracer::Safeguard::growth_test);
      // Accepted where the state moved by at most kNaturalMaxSlope times the λ move (both scaled):
      // past the slip onset of a Jenkins contact the EPMC's ξ rises linearly (W_D = 4 μF_N
      // (a − a_s)) with a scaled slope of ~290 (k_T0/k = 100); the earlier bound 1e3 s + |Δλ|
      // (mixing scaled and unscaled units) admitted slopes up to ~250 only, and the six 1-DOF
      // Jenkins damping curves whose point fell exactly on the onset stopped there.
      const double scaled_dl = std::abs(dl) / options.parameter_scale;
      if (b.converged && (b.sample.y - y).norm() <= (1.0 + kNaturalMaxSlope) * scaled_dl &&
          !retraces(b.sample.y)) {
        // Oriented along τ_k (τ·τ_k > 0), unless its λ component then goes against the Δλ just
        // taken: past a fold at a kink the tangent at the landing turns by more than 90° from τ_k,
        // and oriented by τ_k it sends the run back along the sheet it crossed (a 2-DOF chain
        // grounded through a Jenkins contact, k2 = 2: its damping curve crept back from a 3:1
        // internal resonance until min_step). It is then oriented by the secant y_b − y_k, the
        // direction in which the corner was crossed (docs/continuation.md, "Natural-parameter
        // fallback at corners").
        std::string tangent_failure;
        next_tau = tracer.tangent(b.sample, tau, tangent_failure);
        if (next_tau && (*next_tau)(n) * dl < 0.0)
          next_tau = tracer.tangent(b.sample, (b.sample.y - y).normalized(), tangent_failure);
        next_orientation = tracer.tangent_orientation();
        if (next_tau) {
          c = std::move(b);
          failure.clear();
          on_bound = c.sample.lambda == options.parameter_end;
          bound_reason = StopReason::reached_end;
        }
      }
    }

    // max_output_change: a step that changed an output by more is retried shorter, down to
    // 10⁻³ max_step (below it the change is accepted: an output that jumps must not end the curve).
    observed_change = 0.0;
    if (failure.empty() && limit_outputs) {
      next_outputs = options.outputs(c.sample.x, c.sample.lambda);
      observed_change = output_change(next_outputs);
      if (observed_change > options.max_output_change && s > kOutputMinStepFactor * options.max_step)
        failure = fmt::format("an output changed by {:.3g} > max_output_change {:.3g}", observed_change,
                              options.max_output_change);
    }

    // max_state_turn: a step that turned the state by more is retried shorter, down to the same
    // 10⁻³ max_step (a jump over a peak is resolved; a state that turns that fast is accepted).
    if (failure.empty() && options.max_state_turn > 0.0 && s > kOutputMinStepFactor * options.max_step) {
      const auto x_k = y.head(n);  // scaled states
      const auto x_f = c.sample.y.head(n);
      const double norms = x_k.norm() * x_f.norm();
      if (norms > 0.0) {
        const double turn = std::acos(std::clamp(x_k.dot(x_f) / norms, -1.0, 1.0));
        if (turn > options.max_state_turn)
          failure = fmt::format("the state turned by {:.0f}° > max_state_turn {:.0f}° in one step",
                                turn * 180.0 / std::numbers::pi,
                                options.max_state_turn * 180.0 / std::numbers::pi);
      }
    }

    if (!failure.empty()) {
      ++result.rejected_steps;
      rejected_since_accept = true;
      last_failure = failure;
      s *= 0.5;
      if (s < options.min_step) {
        result.reason = StopReason::min_step;
        result.message = fmt::format(
            "step {:.3g} below min_step {:.3g} after the point at λ = {:.10g} (point {}): {}", s,
            options.min_step, result.points.back().lambda, result.points.size(), last_failure);
        return result;
      }
      continue;
    }

    creeping = retraced_since_accept ? creeping + 1 : 0;
    retraced_since_accept = false;
    if (creeping >= kCrawlPoints) {
      result.reason = StopReason::min_step;
      result.message = fmt::format(
          "the run crept towards the branch already traced after the point at λ = {:.10g} (point {}): "
          "{} points in a row, each only after the corrector had jumped back onto that branch, the last at "
          "step {:.3g}",
          result.points.back().lambda, result.points.size(), kCrawlPoints, s);
      return result;
    }
    Point p;
    p.x = c.sample.x;
    p.lambda = c.sample.lambda;
    p.tangent = *next_tau;
    // A point moved onto a bound lies short of the hyperplane: its step is its own projection.
    p.step = on_bound ? tau.dot(c.sample.y - y) : s;
    p.iterations = c.iterations;
    p.residual = c.sample.norm;
    p.fold = tau(n) * (*next_tau)(n) < 0.0;
    traced.push_back(y);
    y = c.sample.y;
    tau = *next_tau;
    orientation = next_orientation;
    if (limit_outputs) last_outputs = next_outputs;
    if (!accept(std::move(p), on_bound, bound_reason)) return result;

    // s ← s · clamp(target / iterations, 1/2, step_growth), no growth right after a rejection.
    const double ratio = static_cast<double>(options.target_corrector_iterations) /
                         static_cast<double>(std::max(c.iterations, 1));
    double growth = rejected_since_accept ? 1.0 : options.step_growth;
    // The outputs change about linearly with the step: aim at 0.8 of max_output_change.
    if (limit_outputs && observed_change > 0.0)
      growth = std::max(0.5, std::min(growth, 0.8 * options.max_output_change / observed_change));
    s = capped(std::clamp(s * std::clamp(ratio, 0.5, growth), options.min_step, options.max_step), tau);
    rejected_since_accept = false;
  }
}

}  // namespace jointhb::continuation
