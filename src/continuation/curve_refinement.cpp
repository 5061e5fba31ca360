// Extrema along a traced branch: folds and resonance peaks (curve_refinement.hpp).
#include "curve_refinement.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <string>

#include "../support/gmres.hpp"
#include "bordered_preconditioner.hpp"

namespace jointhb::continuation::detail {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Scales {
  Eigen::VectorXd state;  // x_scale
  double parameter = 1.0;

  Scales(const Options& o, Eigen::Index n)
      : state(o.state_scale.size() == n ? o.state_scale : Eigen::VectorXd::Ones(n)),
        parameter(o.parameter_scale) {}

  [[nodiscard]] Eigen::VectorXd scaled(const Eigen::VectorXd& x, double lambda) const {
    Eigen::VectorXd y(x.size() + 1);
    y.head(x.size()) = x.cwiseQuotient(state);
    y[x.size()] = lambda / parameter;
    return y;
  }
};

// A corrected point at σ with its tangent (scaled, oriented along d).
struct BranchPoint {
  Eigen::VectorXd x;
  double lambda = 0.0;
  Eigen::VectorXd tangent;
  double sigma = 0.0;
  double derivative = 0.0;  // q'(σ)
};

// The bordered matrix [R_x D_x, R_λ λ_scale; dᵀ] of the current Jacobian.
Eigen::MatrixXd bordered(const Evaluation& e, const Scales& s, const Eigen::VectorXd& d) {
  const Eigen::Index n = e.residual.size();
  Eigen::MatrixXd a(n + 1, n + 1);
  a.topLeftCorner(n, n) = e.d_state * s.state.asDiagonal();
  a.topRightCorner(n, 1) = e.d_parameter * s.parameter;
  a.row(n) = d.transpose();
  return a;
}

double q_derivative(const CurveQuantity& q, const Scales& s, const Eigen::VectorXd& x,
                    double lambda, const Eigen::VectorXd& tangent, const Eigen::VectorXd& d) {
  const double along = tangent.dot(d);
  if (!(along > 0.0)) return kNaN;
  const Eigen::Index n = x.size();
  if (q.slope) return q.slope(x, lambda, tangent.head(n).cwiseProduct(s.state), tangent[n] * s.parameter) / along;
  const auto [gx, gl] = q.gradient(x, lambda);
  double dq = gl * tangent[n] * s.parameter;
  if (gx.size() == n) dq += gx.dot(tangent.head(n).cwiseProduct(s.state));
  return dq / along;
}

// The bordered matrix A = [R_x D_x, R_λ λ_scale; dᵀ] of one evaluation, to solve with: by LU when the
// Jacobian is dense; matrix-free (Evaluation::d_state_product) by restarted GMRES preconditioned
// with the block elimination of [K̃, j_λ; dᵀ], K̃⁻¹ = D_x⁻¹ Ã⁻¹ (Ã⁻¹ the evaluation's approximate
// inverse of R_x, built once per evaluation), as the continuation's own matrix-free solves
// (pseudo_arclength.cpp, docs/continuation.md §2).
class BorderedSolver {
 public:
  BorderedSolver(const Evaluation& e, const Scales& s, const Eigen::VectorXd& d, const Options& o)
      : e_(e), s_(s), d_(d), o_(o), n_(d.size() - 1) {
    if (!e.d_state_product) {
      lu_.compute(bordered(e, s, d));
      return;
    }
    const LinearOperator inverse =
        e.make_preconditioner ? e.make_preconditioner() : LinearOperator([](const Eigen::VectorXd& v) { return v; });
    precondition_.emplace([inverse, &s](const Eigen::VectorXd& v) { return Eigen::VectorXd(inverse(v).cwiseQuotient(s.state)); },
                          e.d_parameter * s.parameter, d);
  }

  // A out = rhs; false with `why` when the solve fails.
  bool solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& out, std::string& why) const {
    if (!e_.d_state_product) {
      out = lu_.solve(rhs);
      if (out.allFinite()) return true;
      why = "singular bordered matrix";
      return false;
    }
    const auto apply = [&](const Eigen::VectorXd& z) {
      Eigen::VectorXd az(n_ + 1);
      az.head(n_) = e_.d_state_product(Eigen::VectorXd(z.head(n_).cwiseProduct(s_.state))) +
                    e_.d_parameter * (s_.parameter * z[n_]);
      az[n_] = d_.dot(z);
      return az;
    };
    const auto precondition = [&](const Eigen::VectorXd& v) { return (*precondition_)(v); };
    // Restarted on the true residual (iterative refinement against the recursive residual's drift).
    out = Eigen::VectorXd::Zero(n_ + 1);
    Eigen::VectorXd residual = rhs;
    const double target = o_.krylov_tolerance * rhs.norm();
    int iterations = 0;
    for (int cycle = 0; cycle < 4 && residual.norm() > target; ++cycle) {
      Eigen::VectorXd dz;
      const double previous = residual.norm();
      const support::GmresOutcome g =
          support::gmres(apply, precondition, residual, o_.krylov_max_iterations, target / previous, dz);
      iterations += g.iterations;
      if (!dz.allFinite()) break;
      out += dz;
      residual = rhs - apply(out);
      if (!g.converged && residual.norm() > 0.5 * previous) break;
    }
    if (residual.norm() <= target) return true;
    why = fmt::format("GMRES on the bordered system: relative residual {:.3g} after {} iterations",
                      residual.norm() / rhs.norm(), iterations);
    return false;
  }

 private:
  const Evaluation& e_;
  const Scales& s_;
  const Eigen::VectorXd& d_;
  const Options& o_;
  Eigen::Index n_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;               // dense
  std::optional<BorderedPreconditioner> precondition_;  // matrix-free, K̃⁻¹ = D_x⁻¹ Ã⁻¹
};

// Newton on the branch at σ from the guess y0; the tangent at the converged point.
std::optional<BranchPoint> correct_at(const ResidualFunction& residual, const Options& o,
                                      const Scales& s, const Eigen::VectorXd& ya,
                                      const Eigen::VectorXd& d, double sigma,
                                      Eigen::VectorXd y, int& iterations, std::string& why) {
  const Eigen::Index n = y.size() - 1;
  for (int it = 0; it <= o.max_corrector_iterations; ++it) {
    const Eigen::VectorXd x = y.head(n).cwiseProduct(s.state);
    const double lambda = y[n] * s.parameter;
    // A residual that throws (e.g. a contact law handed a non-finite state by a diverging
    // iteration) is a failed point, as in the continuation's own corrector: the refinement gives
    // up and the caller keeps the accepted points (found on a 10-DOF damping curve, whose turn
    // refinement threw "periodic path: … non-finite …" and lost the whole curve).
    Evaluation e;
    try {
      e = residual(x, lambda, true);
    } catch (const std::exception& error) {
      why = fmt::format("the residual failed: {}", error.what());
      return std::nullopt;
    }
    if (!e.ok || !e.residual.allFinite() || e.d_parameter.size() != n ||
        (!e.d_state_product && e.d_state.rows() != n)) {
      why = e.ok ? "the residual or its Jacobian is not available" : e.message;
      return std::nullopt;
    }
    const BorderedSolver bordered_system(e, s, d, o);
    Eigen::VectorXd rhs(n + 1);
    rhs.head(n) = -e.residual;
    rhs[n] = sigma - d.dot(y - ya);
    const double r = e.residual.lpNorm<Eigen::Infinity>() / o.residual_scale;
    if (r <= o.residual_tolerance && std::abs(rhs[n]) <= o.step_tolerance && it > 0) {
      Eigen::VectorXd e_last = Eigen::VectorXd::Zero(n + 1);
      e_last[n] = 1.0;
      Eigen::VectorXd t;
      if (!bordered_system.solve(e_last, t, why) || !t.allFinite() || t.norm() == 0.0) {
        why = "the tangent is not defined: " + (why.empty() ? std::string("singular bordered matrix") : why);
        return std::nullopt;
      }
      t /= t.norm();
      return BranchPoint{x, lambda, t, sigma, 0.0};
    }
    if (it == o.max_corrector_iterations) break;
    Eigen::VectorXd dy;
    if (!bordered_system.solve(rhs, dy, why)) return std::nullopt;
    y += dy;
    ++iterations;
  }
  why = fmt::format("no convergence in {} corrector iterations at σ = {:.3g}",
                    o.max_corrector_iterations, sigma);
  return std::nullopt;
}

}  // namespace

CurveQuantity parameter_quantity() {
  CurveQuantity q;
  q.value = [](const Eigen::VectorXd&, double lambda) { return lambda; };
  q.gradient = [](const Eigen::VectorXd&, double) {
    return std::pair<Eigen::VectorXd, double>{Eigen::VectorXd(), 1.0};
  };
  return q;
}

CurveExtremum refine_extremum(const ResidualFunction& residual, const Options& scaling,
                              const Point& a, const Point& b, const CurveQuantity& q,
                              const RefinementOptions& options) {
  CurveExtremum out;
  const Scales s(scaling, a.x.size());
  const Eigen::VectorXd ya = s.scaled(a.x, a.lambda);
  const Eigen::VectorXd chord = s.scaled(b.x, b.lambda) - ya;
  const double length = chord.norm();
  if (!(length > 0.0)) {
    out.message = "the two points coincide";
    return out;
  }
  const Eigen::VectorXd d = chord / length;
  BranchPoint lo{a.x, a.lambda, a.tangent, 0.0, q_derivative(q, s, a.x, a.lambda, a.tangent, d)};
  BranchPoint hi{b.x, b.lambda, b.tangent, length,
                 q_derivative(q, s, b.x, b.lambda, b.tangent, d)};
  if (!std::isfinite(lo.derivative) || !std::isfinite(hi.derivative) ||
      lo.derivative * hi.derivative > 0.0) {
    out.message = "the derivative does not change sign between the points";
    return out;
  }
  BranchPoint best = std::abs(lo.derivative) < std::abs(hi.derivative) ? lo : hi;
  int stale = 0;  // consecutive updates of the same bracket end
  int stale_side = 0;
  double bound = length * std::max(std::abs(lo.derivative), std::abs(hi.derivative));
  for (int k = 0; k < options.max_points; ++k) {
    const double value = q.value(best.x, best.lambda);
    if (bound <= options.relative_tolerance * std::abs(value) || best.derivative == 0.0) break;
    double glo = lo.derivative, ghi = hi.derivative;
    // Illinois: the end that keeps its place has its derivative halved per repeated update.
    if (stale >= 2) (stale_side < 0 ? ghi : glo) *= std::ldexp(1.0, 1 - stale);
    double sigma = (lo.sigma * ghi - hi.sigma * glo) / (ghi - glo);
    const double width = hi.sigma - lo.sigma;
    sigma = std::clamp(sigma, lo.sigma + 1e-3 * width, hi.sigma - 1e-3 * width);
    const double w = (sigma - lo.sigma) / width;
    const Eigen::VectorXd guess =
        (1.0 - w) * s.scaled(lo.x, lo.lambda) + w * s.scaled(hi.x, hi.lambda);
    std::string why;
    std::optional<BranchPoint> c =
        correct_at(residual, scaling, s, ya, d, sigma, guess, out.corrector_iterations, why);
    ++out.points;
    if (!c) {
      out.message = why;
      break;
    }
    c->derivative = q_derivative(q, s, c->x, c->lambda, c->tangent, d);
    if (!std::isfinite(c->derivative)) {
      out.message = "the branch turns back within the bracket";
      break;
    }
    const int side = (c->derivative * lo.derivative > 0.0) ? -1 : +1;  // -1: replaces lo
    stale = side == stale_side ? stale + 1 : 1;
    stale_side = side;
    (side < 0 ? lo : hi) = *c;
    best = std::abs(lo.derivative) < std::abs(hi.derivative) ? lo : hi;
    bound = (hi.sigma - lo.sigma) * std::max(std::abs(lo.derivative), std::abs(hi.derivative));
  }
  out.ok = true;  // the bracket always holds the extremum: the bound says how well it is known
  out.x = best.x;
  out.lambda = best.lambda;
  out.value = q.value(best.x, best.lambda);
  out.value_bound = bound;
  out.lambda_bracket = std::abs(hi.lambda - lo.lambda);
  // Where q' changes sign once between a and b, their extremum lies beyond both q(a) and q(b). A
  // value strictly between them is a stationary point of another kind (q' changes sign several
  // times between the points: several turns, or a smooth fold beside a kink): not the extremum.
  const double qa = q.value(a.x, a.lambda), qb = q.value(b.x, b.lambda);
  if (out.value > std::min(qa, qb) + bound && out.value < std::max(qa, qb) - bound) {
    out.ok = false;
    out.message = fmt::format(
        "the refinement found a stationary point ({:.10g}) between the two points' values ({:.10g}, "
        "{:.10g}), not their extremum (the quantity turns more than once between them)",
        out.value, qa, qb);
  }
  return out;
}

}  // namespace jointhb::continuation::detail
