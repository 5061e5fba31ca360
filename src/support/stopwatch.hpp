#pragma once
// Wall-clock timing for the timings that results report (internal to the library).

#include <chrono>

namespace jointhb::support {

using Clock = std::chrono::steady_clock;

/// Seconds elapsed since `start`.
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace jointhb::support
