#include "cli_support.hpp"

#include <chrono>

#include <unistd.h>

#include <cmath>
#include <stdexcept>

#include "jointhb/io/value_checks.hpp"

namespace jointhb::cli {

void require_option(const std::string& option, const std::string& constraint) {
  if (!constraint.empty()) throw io::InputError(io::command_line, 0, 0, option, constraint);
}

double number_option(const std::string& option, const std::string& text) {
  const auto value = io::parse_number(text);
  if (!value) require_option(option, "must be a number, got '" + text + "'");
  return *value;
}

int integer_option(const std::string& option, const std::string& text, long long min,
                   long long max) {
  const auto value = io::parse_integer(text);
  if (!value) require_option(option, "must be an integer, got '" + text + "'");
  require_option(option, io::check_in_range(*value, min, max));
  return static_cast<int>(*value);
}

std::string describe_result(double value) {
  if (std::isfinite(value)) return io::format_number(value);
  // A NaN here comes from an indeterminate form (∞·0, ∞-∞), nearly always after an overflow.
  if (std::isnan(value)) return "undefined (an intermediate value overflowed the double range)";
  return value > 0 ? "beyond the double range (overflow)" : "below minus the double range (overflow)";
}

void require_finite_result(const std::string& name, double value) {
  if (!std::isfinite(value)) {
    throw std::runtime_error("result '" + name + "' is " + describe_result(value) +
                             "; nothing written");
  }
}

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

ProgressPacer::ProgressPacer(double interval_seconds) : terminal_(stderr_is_terminal()), interval_(interval_seconds) {}

bool ProgressPacer::due() {
  if (terminal_) return true;
  const double now = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (now - last_ < interval_) return false;
  last_ = now;
  return true;
}

}  // namespace jointhb::cli
