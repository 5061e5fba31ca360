#pragma once
// Constants shared by the unit tests (one definition, so that tests compile together in unity
// batches without clashing local copies).

#include <numbers>

namespace test_constants {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

}  // namespace test_constants
