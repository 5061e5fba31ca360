#pragma once
// A damping curve completed from its far end (docs/continuation.md, "A curve traced from both
// ends"). Where the run from λ_start stops short of λ_end — at an internal resonance the branch
// folds many times at kinks of the friction laws, and at a junction of sheets the run can take a
// side loop that closes on itself — a second run traced from λ_end back towards λ_start is kept
// up to the first of its points that lies within one continuation step of a point of the first
// run, where one branch joins the two (branch_between). The curve is then the first run up to
// that point and the second run from there back to λ_end: a connected path of converged points
// from end to end, like the points of one run.
// Shared by discrete (backbone.cpp) and finite-element (interface_backbone.cpp) damping curves.

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <exception>
#include <limits>
#include <optional>
#include <vector>

#include "jointhb/continuation/curve_turn.hpp"
#include "jointhb/continuation/pseudo_arclength.hpp"

namespace jointhb::continuation::detail {

/// The continuation's arclength norm of a curve, ‖(Δy ./ y_scale, Δλ / λ_scale)‖₂ (the scales of
/// pseudo_arclength.hpp's Options), for points of the same level (unknowns of one size).
struct CurveMetric {
  Eigen::VectorXd state_scale;
  double parameter_scale = 1.0;
  /// ∞ for points of different levels.
  [[nodiscard]] double distance(const Eigen::VectorXd& ya, double la, const Eigen::VectorXd& yb, double lb) const {
    if (ya.size() != yb.size() || ya.size() != state_scale.size()) return std::numeric_limits<double>::infinity();
    const double dl = (la - lb) / parameter_scale;
    return std::sqrt((ya - yb).cwiseQuotient(state_scale).squaredNorm() + dl * dl);
  }
};

/// Where the second run meets the first: the index in `first` of the point nearest to `p` when it
/// lies within one step of it — the smaller of p's own step and the longer of the two steps beside
/// that point on the first run (a point there is as close as the next point of either run would
/// be); empty otherwise. `unknowns(q)`, `lambda(q)` and `step(q)` read a point.
template <class PointT, class Unknowns, class Lambda, class Step>
std::optional<std::size_t> meeting_point(const std::vector<PointT>& first, const PointT& p, const CurveMetric& metric,
                                         const Unknowns& unknowns, const Lambda& lambda, const Step& step) {
  double nearest = std::numeric_limits<double>::infinity();
  std::size_t k = first.size();
  for (std::size_t i = 0; i < first.size(); ++i) {
    const double d = metric.distance(unknowns(p), lambda(p), unknowns(first[i]), lambda(first[i]));
    if (d < nearest) {
      nearest = d;
      k = i;
    }
  }
  if (k == first.size()) return std::nullopt;
  const double beside = std::max(step(first[k]), k + 1 < first.size() ? step(first[k + 1]) : 0.0);
  if (nearest <= std::min(step(p), beside)) return k;
  return std::nullopt;
}

/// Whether one branch joins the nearby points (x_a, λ_a) and (x_b, λ_b): Newton's method on
/// R(x, λ) = 0 and the hyperplane through their midpoint normal to their chord (both scaled by
/// `metric`), started at the midpoint, converges (‖R‖_∞ ≤ `tolerance`) to a point within half the
/// chord of it. A branch that runs from one point to the other crosses that hyperplane near the
/// midpoint; two distinct sheets side by side run along it and hold no solution on it between them.
/// `residual` gives the dense Jacobian (the discrete EPMC's); an evaluation that throws or is not
/// ok counts as no branch.
inline bool branch_between(const ResidualFunction& residual, const CurveMetric& metric, const Eigen::VectorXd& xa,
                           double la, const Eigen::VectorXd& xb, double lb, double tolerance) {
  const Eigen::Index n = xa.size();
  if (xb.size() != n || metric.state_scale.size() != n) return false;
  const auto scaled = [&](const Eigen::VectorXd& x, double l) {
    Eigen::VectorXd z(n + 1);
    z << x.cwiseQuotient(metric.state_scale), l / metric.parameter_scale;
    return z;
  };
  const Eigen::VectorXd za = scaled(xa, la), zb = scaled(xb, lb);
  const Eigen::VectorXd chord = zb - za, mid = 0.5 * (za + zb);
  const double length = chord.norm();
  if (!(length > 0.0)) return true;
  Eigen::VectorXd z = mid;
  constexpr int kIterations = 12;
  for (int it = 0; it <= kIterations; ++it) {
    Evaluation e;
    try {  // an iterate the laws cannot evaluate (e.g. a negative slip of Gaul–Mayer) joins nothing
      e = residual(z.head(n).cwiseProduct(metric.state_scale), z[n] * metric.parameter_scale, true);
    } catch (const std::exception&) {
      return false;
    }
    if (!e.ok || e.d_state.rows() != n || e.d_parameter.size() != n) return false;
    const double off_plane = chord.dot(z - mid);
    if (e.residual.lpNorm<Eigen::Infinity>() <= tolerance && std::abs(off_plane) <= 1e-12 * length * length)
      return (z - mid).norm() <= 0.5 * length;
    if (it == kIterations) break;
    Eigen::MatrixXd j(n + 1, n + 1);
    j.topLeftCorner(n, n) = e.d_state * metric.state_scale.asDiagonal();
    j.topRightCorner(n, 1) = e.d_parameter * metric.parameter_scale;
    j.row(n) = chord.transpose();
    Eigen::VectorXd f(n + 1);
    f << e.residual, off_plane;
    z -= j.partialPivLu().solve(f);
    if (!z.allFinite()) return false;
  }
  return false;
}

/// The turns of a run whose `after_point` indexes `points_before` .. of one run, kept when they lie
/// before `end` (exclusive) and re-indexed by `place(after_point)`; the others (on a part of the run
/// that the joined curve drops) removed.
template <class Place>
std::vector<BackboneTurn> turns_within(const std::vector<BackboneTurn>& turns, std::size_t end, const Place& place) {
  std::vector<BackboneTurn> out;
  for (const BackboneTurn& t : turns) {
    if (t.after_point < 0 || static_cast<std::size_t>(t.after_point) >= end) continue;
    BackboneTurn placed = t;
    placed.after_point = place(static_cast<std::size_t>(t.after_point));
    out.push_back(std::move(placed));
  }
  return out;
}

/// The joined curve: first[0..k], then second[j], second[j − 1], …, second[0] (second's points in
/// the direction λ_start → λ_end), with the turns of both on those parts (second's reversed in
/// order and placed after their point in the joined order). Each joined point's `step` is the
/// arclength from the point before it in the joined order: `joint_step` (the metric distance from
/// first[k] to second[j]) for second[j], second[i + 1].step for second[i].
template <class PointT>
void join_from_both_ends(std::vector<PointT>& first, std::vector<BackboneTurn>& first_turns, std::size_t k,
                         const std::vector<PointT>& second, const std::vector<BackboneTurn>& second_turns,
                         std::size_t j, double joint_step) {
  first.resize(k + 1);
  std::vector<BackboneTurn> turns = turns_within(first_turns, k + 1, [](std::size_t i) { return static_cast<int>(i); });
  // A turn between second[i − 1] and second[i] lies before second[i − 1], which is joined point
  // k + 1 + (j − (i − 1)).
  std::vector<BackboneTurn> back =
      turns_within(second_turns, j + 1, [&](std::size_t i) { return static_cast<int>(k + 2 + j - i); });
  std::reverse(back.begin(), back.end());
  for (std::size_t i = j + 1; i-- > 0;) {
    first.push_back(second[i]);
    first.back().step = i == j ? joint_step : second[i + 1].step;
  }
  turns.insert(turns.end(), back.begin(), back.end());
  first_turns = std::move(turns);
}

}  // namespace jointhb::continuation::detail
