#pragma once
// What the commands of the jointhb program share: exit codes, the reading of numeric options as
// text (so that "nan", "abc" and "-1" are reported in the same words as in case files), and the
// tests on results before anything is printed.

#include <string>

#include "jointhb/io/input_error.hpp"

namespace jointhb::cli {

enum ExitCode : int {
  exit_ok = 0,
  exit_failure = 1,    ///< runtime failure: a computation failed or produced a non-finite value
  exit_bad_input = 2,  ///< invalid options, unreadable or invalid case file
};

/// Bad input that is not tied to one option or one key (e.g. rejected by the library's own
/// validation); reported as one line with exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws io::InputError(command line, option, constraint) when `constraint` is not empty.
void require_option(const std::string& option, const std::string& constraint);

/// The text of a numeric option as a double; throws io::InputError naming the option when it is
/// not a number. Range checks follow with require_option and io::check_*.
double number_option(const std::string& option, const std::string& text);
/// The text of an integer option, which must lie in [min, max].
int integer_option(const std::string& option, const std::string& text, long long min,
                   long long max);

/// Throws std::runtime_error("result 'NAME' is " + describe_result(value) + ...) unless value is
/// finite: no NaN or infinity is ever printed or written, not even in the message.
void require_finite_result(const std::string& name, double value);

/// A computed value for a message: the number when finite, else what went wrong in words
/// ("beyond the double range (overflow)", "undefined (an intermediate value overflowed ...)"), so
/// that no message shows "nan" or "inf".
std::string describe_result(double value);

/// Progress lines are for people watching: only when stderr is a terminal.
bool stderr_is_terminal();

/// When a long run reports progress: on a terminal at every event (one line rewritten in place);
/// otherwise (a pipe, a log file, CI) a plain line at most every `interval` seconds, so that a
/// minute-long run is not silent in a log.
class ProgressPacer {
 public:
  explicit ProgressPacer(double interval_seconds = 10.0);
  [[nodiscard]] bool terminal() const { return terminal_; }
  /// Whether this event is shown (always on a terminal; else when the interval has passed).
  bool due();
  /// "\r" on a terminal (rewrite the line), "" otherwise.
  [[nodiscard]] const char* start() const { return terminal_ ? "\r" : ""; }
  /// "   " on a terminal (the line is rewritten), "\n" otherwise.
  [[nodiscard]] const char* end() const { return terminal_ ? "   " : "\n"; }

 private:
  bool terminal_;
  double interval_;
  double last_ = -1e300;
};

}  // namespace jointhb::cli
