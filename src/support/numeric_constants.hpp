#pragma once
// Constants shared by the library's sources (internal). One definition here, so that sources
// can be compiled together (unity builds) without clashing local copies.

#include <limits>
#include <numbers>

namespace jointhb::support {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;
inline constexpr double kEps = std::numeric_limits<double>::epsilon();  // machine epsilon

/// A change between two periods relative to the size of what changed (used by the periodicity
/// tests of the time integrators): ∞ when the scale is 0 but the change is not.
inline double group_change(double difference, double scale) {
  if (scale > 0.0) return difference / scale;
  return difference > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
}

}  // namespace jointhb::support
