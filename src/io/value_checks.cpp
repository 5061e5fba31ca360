#include "jointhb/io/value_checks.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace jointhb::io {

// A NaN is spelled out: no message jointhb prints contains "nan" (issue 20, item 4).
std::string format_number(double value) {
  return std::isnan(value) ? std::string("not-a-number") : fmt::format("{}", value);
}

std::optional<double> parse_number(std::string_view text) {
  // YAML 1.2 spells the special values with a leading dot; strtod does not know them.
  static constexpr double inf = std::numeric_limits<double>::infinity();
  for (std::string_view nan : {".nan", ".NaN", ".NAN"}) {
    if (text == nan) return std::numeric_limits<double>::quiet_NaN();
  }
  for (std::string_view pos : {".inf", ".Inf", ".INF", "+.inf", "+.Inf", "+.INF"}) {
    if (text == pos) return inf;
  }
  for (std::string_view neg : {"-.inf", "-.Inf", "-.INF"}) {
    if (text == neg) return -inf;
  }
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return std::nullopt;
  const std::string copy(text);  // strtod needs a terminated string
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(copy.c_str(), &end);
  if (end != copy.c_str() + copy.size()) return std::nullopt;
  // Overflow to ±inf is reported by check_finite; underflow to a denormal or zero is harmless.
  return value;
}

std::optional<long long> parse_integer(std::string_view text) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return std::nullopt;
  const std::string copy(text);
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(copy.c_str(), &end, 10);
  if (end != copy.c_str() + copy.size() || errno == ERANGE) return std::nullopt;
  return value;
}

std::string check_finite(double value) {
  if (std::isfinite(value)) return {};
  return "must be finite, got " + format_number(value);
}

std::string check_positive(double value) {
  if (auto error = check_finite(value); !error.empty()) return error;
  if (value > 0.0) return {};
  return "must be > 0, got " + format_number(value);
}

std::string check_magnitude(double value) {
  if (auto error = check_finite(value); !error.empty()) return error;
  const double a = std::abs(value);
  if (a == 0.0 || (a >= kMinMagnitude && a <= kMaxMagnitude)) return {};
  return fmt::format("magnitude must lie in [{:g}, {:g}] (or be 0), got {}: jointhb computes in SI "
                     "doubles, and products of such inputs would leave their range (rescale the units)",
                     kMinMagnitude, kMaxMagnitude, format_number(value));
}

std::string check_non_negative(double value) {
  if (auto error = check_finite(value); !error.empty()) return error;
  if (value >= 0.0) return {};
  return "must be >= 0, got " + format_number(value);
}

std::string check_open_unit(double value) {
  if (auto error = check_finite(value); !error.empty()) return error;
  if (value > 0.0 && value < 1.0) return {};
  return "must be in (0, 1), got " + format_number(value);
}

std::string check_in_range(long long value, long long min, long long max) {
  if (value >= min && value <= max) return {};
  return fmt::format("must be in [{}, {}], got {}", min, max, value);
}

std::string check_one_of(std::string_view value, std::initializer_list<std::string_view> allowed) {
  for (std::string_view candidate : allowed) {
    if (value == candidate) return {};
  }
  std::string names;
  for (std::string_view candidate : allowed) {
    if (!names.empty()) names += ", ";
    names += candidate;
  }
  return fmt::format("must be one of {}, got '{}'", names, value);
}

}  // namespace jointhb::io
