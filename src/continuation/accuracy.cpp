// Harmonics and time samples chosen per point from the error estimates (continuation/accuracy.hpp).
#include "jointhb/continuation/accuracy.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace jointhb::continuation {
namespace {

// A level is lowered where its estimates stay below this share of the request (T-44).
constexpr double kCalmShare = 0.1;
// The aliasing estimate (one doubling of N_t, T-42) counts this many times: near the onset of
// gross slip, where few samples resolve the stick–slip switches, the change to 2 N_t can be 16×
// smaller than the change to N_t = 1024 (1-DOF Gaul–Mayer at H = 7, N_t = 64, test
// AccuracyCurves.DiscreteDampingCurveMeetsTheRequestAgainstTheTrueError; README_error_estimate.md:
// 10–25× at N_t = 2H + 2), while the truncation estimate is within 0.2–5× of its true part.
constexpr double kAliasingSafety = 10.0;

// |estimate| / tolerance of one output (0 where it is not controlled), the aliasing counted
// kAliasingSafety times.
double request_share(const ErrorPair& p, double tolerance, bool truncation) {
  if (!(tolerance > 0.0)) return 0.0;
  return truncation ? std::abs(p.truncation) / tolerance : kAliasingSafety * std::abs(p.aliasing) / tolerance;
}

}  // namespace

std::string Accuracy::validate() const {
  if (!std::isfinite(frequency) || !std::isfinite(damping) || !std::isfinite(amplitude))
    return "accuracy: the tolerances must be finite numbers";
  if (!(amplitude >= 0.0 && amplitude < 1.0))
    return fmt::format("accuracy.amplitude: must be a relative tolerance in [0, 1), got {}", amplitude);
  if (!(frequency >= 0.0 && frequency < 1.0))
    return fmt::format("accuracy.frequency: must be a relative tolerance in [0, 1), got {}", frequency);
  if (!(damping >= 0.0 && damping < 1.0))
    return fmt::format("accuracy.damping: must be a relative tolerance in [0, 1), got {}", damping);
  if (min_harmonics < 1) return fmt::format("accuracy.min_harmonics: must be ≥ 1, got {}", min_harmonics);
  if (max_harmonics < min_harmonics)
    return fmt::format("accuracy.max_harmonics: must be ≥ min_harmonics ({}), got {}", min_harmonics, max_harmonics);
  if (min_time_samples < 4) return fmt::format("accuracy.min_time_samples: must be ≥ 4, got {}", min_time_samples);
  if (max_time_samples < min_time_samples)
    return fmt::format("accuracy.max_time_samples: must be ≥ min_time_samples ({}), got {}", min_time_samples,
                       max_time_samples);
  if (max_time_samples < 2 * max_harmonics + 2)
    return fmt::format("accuracy.max_time_samples: must be ≥ 2 max_harmonics + 2 = {}, got {}",
                       2 * max_harmonics + 2, max_time_samples);
  if (calm_points < 1) return fmt::format("accuracy.calm_points: must be ≥ 1, got {}", calm_points);
  return {};
}

std::string Accuracy::validate(Level start) const {
  if (std::string msg = validate(); !msg.empty()) return msg;
  if (!active()) return {};
  if (start.harmonics < min_harmonics || start.harmonics > max_harmonics)
    return fmt::format("harmonics: the starting H = {} must lie in accuracy's [{}, {}]", start.harmonics,
                       min_harmonics, max_harmonics);
  if (start.time_samples < min_time_samples || start.time_samples > max_time_samples)
    return fmt::format("time_samples: the starting N_t = {} must lie in accuracy's [{}, {}]", start.time_samples,
                       min_time_samples, max_time_samples);
  return {};
}

LevelController::LevelController(const Accuracy& request, Level start)
    : request_(request), current_(start), next_(start),
      calm_needed_harmonics_(request.calm_points), calm_needed_samples_(request.calm_points) {}

LevelController::Verdict LevelController::judge(const BackboneError& e, bool restart) {
  next_ = current_;
  if (!e.known) {  // nothing to judge by: keep the level and start counting again
    calm_truncation_ = calm_aliasing_ = 0;
    return Verdict::keep;
  }
  const auto ratio = [&](bool truncation) {
    return std::max(request_share(e.omega, request_.frequency, truncation), request_share(e.damping, request_.damping, truncation));
  };
  return judge_ratios(truncation_ratio(e.truncation_known, ratio), ratio(false), restart);
}

LevelController::Verdict LevelController::judge(const FrfError& e, bool restart) {
  next_ = current_;
  if (!e.known) {
    calm_truncation_ = calm_aliasing_ = 0;
    return Verdict::keep;
  }
  const auto ratio = [&](bool truncation) {
    return std::max(request_share(e.amplitude_h1, request_.amplitude, truncation),
                    request_share(e.amplitude_max, request_.amplitude, truncation));
  };
  return judge_ratios(truncation_ratio(e.truncation_known, ratio), ratio(false), restart);
}

bool LevelController::wants_truncation() const {
  return current_.harmonics + 2 <= request_.max_harmonics || points_without_truncation_ + 1 >= kTopLevelTruncationStride;
}

LevelController::Verdict LevelController::judge_ratios(double r_t, double r_a, bool restart) {
  if (holding_) {  // the point a finer level could not start from, at the level before (fall_back)
    holding_ = false;
    if (r_t > 1.0 || r_a > 1.0) ++short_points_;
    calm_truncation_ = calm_aliasing_ = 0;
    return Verdict::keep;
  }
  const bool more_harmonics = r_t > 1.0 && current_.harmonics + 2 <= request_.max_harmonics;
  const bool more_samples = r_a > 1.0 && 2 * current_.time_samples <= request_.max_time_samples;
  if (more_harmonics || more_samples) {
    if (more_harmonics) {
      next_.harmonics += 2;
      // The N_t' at which the truncation estimate was computed (error_estimate.hpp).
      next_.time_samples = std::max(next_.time_samples, truncation_time_samples(current_.harmonics, current_.time_samples));
    }
    if (more_samples) next_.time_samples = std::max(next_.time_samples, 2 * current_.time_samples);
    next_.time_samples = std::min(next_.time_samples, request_.max_time_samples);
    // A level that was just lowered and does not hold: twice as many calm points before the next try.
    if (restart) {
      if (more_harmonics) calm_needed_harmonics_ *= 2;
      if (more_samples) calm_needed_samples_ *= 2;
    }
    calm_truncation_ = calm_aliasing_ = 0;
    return Verdict::retry_finer;
  }
  if (restart) return Verdict::keep;  // never kept; the lowered level holds
  if (r_t > 1.0 || r_a > 1.0) ++short_points_;
  calm_truncation_ = r_t < kCalmShare ? calm_truncation_ + 1 : 0;
  calm_aliasing_ = r_a < kCalmShare ? calm_aliasing_ + 1 : 0;
  const bool fewer_harmonics =
      calm_truncation_ >= calm_needed_harmonics_ && current_.harmonics - 2 >= request_.min_harmonics;
  const int halved = current_.time_samples / 2;
  const bool fewer_samples = calm_aliasing_ >= calm_needed_samples_ && halved >= request_.min_time_samples &&
                             halved >= 2 * current_.harmonics + 2 && current_.time_samples % 2 == 0;
  if (!fewer_harmonics && !fewer_samples) return Verdict::keep;
  if (fewer_harmonics) next_.harmonics -= 2;
  if (fewer_samples) next_.time_samples = halved;
  calm_truncation_ = calm_aliasing_ = 0;
  return Verdict::keep_then_coarser;
}

}  // namespace jointhb::continuation
