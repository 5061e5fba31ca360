#pragma once
// The input checks every Floquet computation on a harmonic-balance solution starts with (the
// monodromy of discrete systems and of FE joints, Hill's method of FE joints; internal header).
#include <fmt/format.h>

#include <Eigen/Core>
#include <cmath>
#include <stdexcept>
#include <string>

namespace jointhb::hb::detail {

/// Throws std::invalid_argument ("<who>: <size> <what>, expected <expected>") when `solution` has
/// the wrong size; returns why Ω or the solution cannot be used (not finite, Ω ≤ 0), empty when
/// they can.
inline std::string floquet_input_problem(const char* who, const char* what, const Eigen::VectorXd& solution,
                                         Eigen::Index expected, double omega) {
  if (solution.size() != expected)
    throw std::invalid_argument(fmt::format("{}: {} {}, expected {}", who, solution.size(), what, expected));
  if (!(omega > 0.0) || !std::isfinite(omega) || !solution.allFinite())
    return fmt::format("Ω or the {} are not finite", what);
  return {};
}

}  // namespace jointhb::hb::detail
