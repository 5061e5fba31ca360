#pragma once
// A damping curve completed from its far end (docs/continuation.md, "A curve traced from both
// ends"). Where the run from λ_start stops short of λ_end — at an internal resonance the branch
// folds many times at kinks of the friction laws, and at a junction of sheets the run can take a
// side loop that closes on itself — a second run traced from λ_end back towards λ_start is kept
// up to the first of its points that lies within one continuation step of a point of the first
// run. The curve is then the first run up to that point and the second run from there back to
// λ_end: a connected path of converged points from end to end, like the points of one run.
// Shared by discrete (backbone.cpp) and finite-element (interface_backbone.cpp) damping curves.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

#include "jointhb/continuation/curve_turn.hpp"

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
