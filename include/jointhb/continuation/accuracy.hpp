#pragma once
// Accuracy on request (docs/theory.md §13, "Harmonics and samples chosen per point", eq. T-44):
// a damping curve traced with the harmonics H and time samples N_t of each point chosen from that
// point's own error estimates (error_estimate.hpp, interface_error_estimate.hpp) instead of fixed.
//
// The curve is traced in segments of one level (H, N_t). After every accepted point the estimates
// are compared with the request, relative to it: r_T = max(|δΩ_T|/tol_Ω, |δζ_T|/tol_ζ) for the
// truncation (the change to H + 2) and r_A likewise for 10× the aliasing (the change to 2 N_t, which
// can be an order of magnitude below the true sampling error near the onset of gross slip).
//   r_T > 1: the point is dropped and traced again at the same λ with H + 2 (N_t raised to the
//            N_t' its estimate used, max(N_t, 2H + 6)) — the segment restarts from it;
//   r_A > 1: likewise with 2 N_t;
//   r_T < 1/10 on `calm_points` points in a row: the point is kept and the next segment starts
//            from it with H − 2 (down to min_harmonics); r_A < 1/10 likewise halves N_t (down to
//            min_time_samples and 2H + 2). A lowered level whose first point exceeds the request
//            is raised back at once and not lowered again for twice as many calm points.
// Where H or N_t would exceed max_harmonics / max_time_samples the point is kept as it is and
// counted as short of the request. Every point reports the level it was computed at.
// At H = max_harmonics, where no raise is possible, the truncation estimate only decides the
// lowering and the count of short points: it is asked for (wants_truncation) at the first point
// of the level and then at every third point; the points between take the r_T of the last point
// that had it (their truncation columns are empty). The aliasing estimate is made at every point.
#include <string>

#include "jointhb/continuation/error_estimate.hpp"

namespace jointhb::continuation {

/// Harmonics and time samples of one segment of a curve.
struct Level {
  int harmonics = 1;
  int time_samples = 32;
  friend bool operator==(const Level&, const Level&) = default;
};

/// The request: relative tolerances of the outputs — Ω and ζ of a damping curve, the amplitudes of
/// an FRF (0: that output is not controlled; one > 0 makes the request active) — and the range of
/// levels the curve may use.
struct Accuracy {
  double frequency = 0.0;      ///< ≥ 0: |δΩ/Ω| per point (damping curves)
  double damping = 0.0;        ///< ≥ 0: |δζ/ζ| per point (damping curves)
  double amplitude = 0.0;      ///< ≥ 0: |δA/A| of amplitude_h1 and amplitude_max per point (FRFs)
  int min_harmonics = 1;       ///< ≥ 1, odd or even as the basis
  int max_harmonics = 15;      ///< ≥ min_harmonics
  int min_time_samples = 16;   ///< ≥ 4
  int max_time_samples = 2048; ///< ≥ min_time_samples
  int calm_points = 3;         ///< ≥ 1: points below 1/10 of the request before a level is lowered
  [[nodiscard]] bool active() const { return frequency > 0.0 || damping > 0.0 || amplitude > 0.0; }
  [[nodiscard]] std::string validate() const;  ///< empty when valid
  /// validate(), and when the request is active, that the curve's starting level lies in its
  /// range (names the field harmonics or time_samples); empty when valid.
  [[nodiscard]] std::string validate(Level start) const;
};

/// The level rule above, fed with the estimates of each accepted point in order.
class LevelController {
 public:
  LevelController(const Accuracy& request, Level start);
  /// What to do with a point computed at current() whose estimates are `e`.
  enum class Verdict {
    keep,             ///< keep the point, same level
    retry_finer,      ///< drop the point, trace it again at next() (> current())
    keep_then_coarser ///< keep the point, go on from it at next() (< current())
  };
  /// `restart`: the point is the first of a segment whose start repeats a kept point (after a
  /// lowering): it is never kept, only judged (a raise sends the level back up).
  Verdict judge(const BackboneError& e, bool restart = false);
  /// The same for an FRF point (amplitude_h1 and amplitude_max against `amplitude`).
  Verdict judge(const FrfError& e, bool restart = false);
  [[nodiscard]] Level current() const { return current_; }
  [[nodiscard]] Level next() const { return next_; }
  /// Back to `level` after a finer level could not start from a dropped point: the next point
  /// judged (that point, traced again at `level`) is kept whatever its estimates, counted short
  /// where it exceeds the request.
  void fall_back(Level level) {
    next_ = level;
    advance();
    holding_ = true;
  }
  /// Whether the next point needs its truncation estimate (see above: false at H = max_harmonics
  /// between every third point).
  [[nodiscard]] bool wants_truncation() const;
  /// Move to next() (after the caller restarted the curve there).
  void advance() {
    current_ = next_;
    points_without_truncation_ = kTopLevelTruncationStride;  // the new level's first point has it
  }
  /// At H = max_harmonics, the truncation estimate of one point in this many.
  static constexpr int kTopLevelTruncationStride = 3;
  /// Points kept although their estimate exceeds the request: at the largest allowed level, or
  /// where the caller could not retry (count_short).
  [[nodiscard]] int short_points() const { return short_points_; }
  /// A point judged retry_finer that the caller keeps as it is (the branch runs back in λ).
  void count_short() {
    next_ = current_;
    ++short_points_;
  }

 private:
  // The rule on r_T and r_A (T-44) of a point with known estimates.
  Verdict judge_ratios(double r_t, double r_a, bool restart);
  // r_T of a point: ratio(true) where its truncation estimate is known, else the last one's.
  template <class Ratio>
  double truncation_ratio(bool known, const Ratio& ratio) {
    if (!known) {
      ++points_without_truncation_;
      return last_truncation_ratio_;
    }
    points_without_truncation_ = 0;
    return last_truncation_ratio_ = ratio(true);
  }
  Accuracy request_;
  Level current_, next_;
  int calm_truncation_ = 0, calm_aliasing_ = 0;
  int calm_needed_harmonics_ = 0, calm_needed_samples_ = 0;
  int short_points_ = 0;
  bool holding_ = false;  // fall_back(): keep the next point judged
  int points_without_truncation_ = kTopLevelTruncationStride;  // judged in a row without r_T
  double last_truncation_ratio_ = 0.0;                         // r_T of the last point that had it
};

}  // namespace jointhb::continuation
