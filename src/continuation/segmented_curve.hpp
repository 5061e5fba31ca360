#pragma once
// A damping curve traced in segments of one level (H, N_t) with the level chosen per point from
// the points' error estimates (continuation/accuracy.hpp, docs/theory.md §13 eq. T-44); one driver
// for discrete (backbone.cpp) and finite-element (interface_backbone.cpp) curves. Without an
// active request it is a single continuation run.

#include <fmt/format.h>

#include <Eigen/Core>
#include <algorithm>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "jointhb/continuation/accuracy.hpp"
#include "jointhb/continuation/pseudo_arclength.hpp"
#include "jointhb/hb/fourier.hpp"

namespace jointhb::continuation::segment_detail {

/// Where a segment starts: the linear limit (y empty), or a point of the previous segment at its λ.
struct SegmentStart {
  Eigen::VectorXd y;                ///< the unknowns at level `from`
  Level from;
  double lambda = 0.0;
  double step = 0.0;                ///< arclength step to begin with (0: the options')
  bool repeats_kept_point = false;  ///< the point is already on the curve (after a lowering)
};

/// How the segmented curve ended (the last run's reason and message, or reached_end for a last
/// segment of one point on λ_end).
struct SegmentedOutcome {
  StopReason reason = StopReason::start_failed;
  std::string message;
  int level_changes = 0;
  int short_points = 0;  ///< kept above the request at the largest level allowed
  bool stopped_by_keep = false;  ///< `keep` returned false
};

/// The unknowns y of a point at level `from` in the basis `to` (`dofs` signals, DOF-major; the same
/// harmonic selection): shared harmonics copied, new ones zero; the last `tail` entries (Ω and ξ of
/// an EPMC point) kept as they are.
inline Eigen::VectorXd transfer_unknowns(const Eigen::VectorXd& y, Level from, const hb::FourierBasis& to, int dofs,
                                         int tail = 0) {
  const hb::FourierBasis from_basis(from.harmonics, from.time_samples, to.odd_only());
  const Eigen::Index coefficients = static_cast<Eigen::Index>(dofs) * from_basis.size();
  const Eigen::Index size = static_cast<Eigen::Index>(dofs) * to.size();
  Eigen::VectorXd out(size + tail);
  out.head(size) = hb::transfer_coefficients(from_basis, to, y.head(coefficients), dofs);
  out.tail(tail) = y.tail(tail);
  return out;
}

/// The `keep` of trace_in_segments for a curve whose kept points go to `points` and then to
/// `on_point` (which returns false to end the curve; empty: go on).
template <class PointT>
std::function<bool(PointT&)> append_to(std::vector<PointT>& points, const std::function<bool(const PointT&)>& on_point) {
  return [&points, &on_point](PointT& p) {
    points.push_back(p);
    return on_point ? on_point(points.back()) : true;
  };
}

/// The outcome's record in a curve (reason, message, level_changes, short_of_accuracy).
template <class Curve>
void put_outcome(const SegmentedOutcome& outcome, Curve& curve) {
  curve.reason = outcome.reason;
  curve.message = outcome.message;
  curve.level_changes = outcome.level_changes;
  curve.short_of_accuracy = outcome.short_points;
}

/// A bound on the segments of one curve per allowed point: every restart raises the level, or
/// lowers it after calm_points kept points; this only guards against a rule that would cycle.
constexpr int kMaxSegmentsPerPoint = 4;

/// Traces the curve from λ_start to λ_end (the `base` options' steps and max_points).
/// `make_segment(level)` returns a segment (a unique_ptr to a class with
///   Eigen::VectorXd start_state(const SegmentStart&) — the linear limit when y is empty, else the
///     start's unknowns transferred to the segment's level;
///   Options continuation(double lambda0, double end) — the run's options (scales of its level);
///   Result run(const Eigen::VectorXd& y0, const Options&, const Judge&, const std::function<bool()>&
///     wants_truncation) — the continuation, with Judge = std::function<bool(PointT&, const Point&)>
///     called for every accepted point built with its level and its estimates PointT::error, whose
///     truncation part may be skipped where wants_truncation() is false (LevelController);
/// and optionally void complete(PointT&, const Point&) — called for a point just before it is
///   kept (what is not needed for a point traced again at another level);
/// `keep(point)` appends a kept point and returns false to end the curve; `after_run(segment, r)`
/// adds each run's record.
template <class PointT, class MakeSegment, class AfterRun>
SegmentedOutcome trace_in_segments(const Accuracy& accuracy, Level start, double lambda_start, double end,
                                   const Options& base, const MakeSegment& make_segment,
                                   const std::function<bool(PointT&)>& keep, const AfterRun& after_run) {
  const bool adaptive = accuracy.active();
  const int direction = end > lambda_start ? 1 : -1;
  LevelController control(accuracy, start);
  SegmentedOutcome out;
  SegmentStart from{Eigen::VectorXd(), start, lambda_start, 0.0, false};
  int kept = 0;
  std::optional<Level> raised_from;  // the level before a raise, until the raised segment has started
  const int max_segments = kMaxSegmentsPerPoint * base.max_points + 1;
  for (int segment = 0;; ++segment) {
    auto run = make_segment(control.current());
    const Eigen::VectorXd y0 = run->start_state(from);
    // A segment that starts on λ_end (a point on the end traced again at a finer level) is that
    // one point: the run's end is put beyond it and its budget is one point.
    const bool on_end = direction * (end - from.lambda) <= 0.0;
    Options c = run->continuation(from.lambda, on_end ? end + direction : end);
    if (from.step > 0.0) c.initial_step = std::clamp(from.step, c.min_step, c.max_step);
    c.max_points = on_end ? 1 : std::max(1, base.max_points - kept) + (from.repeats_kept_point ? 1 : 0);

    std::optional<SegmentStart> restart;
    bool first = true, stopped = false, kept_on_end = false;
    const std::function<bool(PointT&, const Point&)> judge = [&](PointT& b, const Point& p) {
      const bool repeat = first && from.repeats_kept_point;
      first = false;
      const auto keep_point = [&]() {
        // What a segment computes only for the points it keeps (the discrete FRF: stability).
        if constexpr (requires { run->complete(b, p); }) run->complete(b, p);
        ++kept;
        if (!keep(b)) {
          stopped = true;
          return false;
        }
        return true;
      };
      if (!adaptive) return keep_point();
      // A new level continues towards λ_end: not from a point where the branch runs back (after a fold).
      const bool onward = p.tangent.size() == 0 || p.tangent[p.tangent.size() - 1] * direction >= 0.0;
      const LevelController::Verdict verdict = control.judge(b.error, repeat);
      if (verdict == LevelController::Verdict::retry_finer && onward && segment < max_segments) {
        restart = SegmentStart{p.x, control.current(), p.lambda, p.step, repeat};
        return false;
      }
      if (repeat) return true;  // the lowered level holds; the point is on the curve already
      if (verdict == LevelController::Verdict::retry_finer) control.count_short();  // kept as it is
      if (!keep_point()) return false;
      const bool at_end = direction * (end - p.lambda) <= 0.0;
      kept_on_end = at_end;
      if (verdict == LevelController::Verdict::keep_then_coarser && onward && !at_end && segment < max_segments) {
        restart = SegmentStart{p.x, control.current(), p.lambda, p.step, true};
        return false;
      }
      return true;
    };
    const std::function<bool()> wants_truncation = [&] { return !adaptive || control.wants_truncation(); };
    const Result r = run->run(y0, c, judge, wants_truncation);
    after_run(*run, r);
    if (restart && !stopped) {
      raised_from = restart->repeats_kept_point ? std::nullopt : std::optional<Level>(control.current());
      control.advance();
      ++out.level_changes;
      from = std::move(*restart);
      continue;
    }
    // A finer level that cannot start from the dropped point (its corrector at fixed λ fails): the
    // curve goes on at the level before from that point, kept short of the request, instead of
    // ending there (a guard: the one such failure seen came from a BLAS race since fixed).
    if (raised_from && r.reason == StopReason::start_failed && !stopped && segment < max_segments) {
      control.fall_back(*raised_from);
      ++out.level_changes;
      raised_from.reset();
      continue;
    }
    out.reason = r.reason;
    out.message = r.message;
    out.stopped_by_keep = stopped;
    if (on_end && kept_on_end && !stopped) {
      out.reason = StopReason::reached_end;
      out.message = fmt::format("reached λ_end = {:.10g} ({} points)", end, kept);
    } else if (segment > 0 && r.reason == StopReason::start_failed) {
      out.message = fmt::format("at λ = {:.6g} the curve could not go on with H = {}, N_t = {}: {}", from.lambda,
                                control.current().harmonics, control.current().time_samples, r.message);
    }
    break;
  }
  out.short_points = control.short_points();
  return out;
}

/// The start of an FRF by a load ramp at fixed Ω: continuation in the load factor s from 0 to 1,
/// R_s(x) = R(x, Ω) + (s − 1) ℓ with ℓ the load's part of R (∂R_s/∂s = ℓ), from x0 (the solution
/// at s = 0), with the steps, tolerances and output limits of `base` but not its point budget
/// (outputs that read λ as Ω must be cleared by the caller).
inline Result trace_load_ramp(const ResidualFunction& residual, double omega, const Eigen::VectorXd& load_part,
                              const Eigen::VectorXd& x0, Options base) {
  const ResidualFunction scaled = [&](const Eigen::VectorXd& x, double s, bool jacobian) {
    Evaluation e = residual(x, omega, jacobian);
    if (e.residual.size() == load_part.size()) e.residual += (s - 1.0) * load_part;
    if (jacobian) e.d_parameter = load_part;
    return e;
  };
  base.parameter_start = 0.0;
  base.parameter_end = 1.0;
  base.direction = 1;
  base.parameter_scale = 1.0;
  base.max_points = 20 * Options{}.max_points;  // not limited by the curve's point budget
  return trace(scaled, x0, base);
}

}  // namespace jointhb::continuation::segment_detail
