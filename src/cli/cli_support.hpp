#pragma once
// What the commands of the jointhb program share: exit codes, the reading of numeric options as
// text (so that "nan", "abc" and "-1" are reported in the same words as in case files), and the
// tests on results before anything is printed.

#include <fmt/format.h>

#include <string>
#include <utility>

#include "jointhb/io/input_error.hpp"

namespace jointhb::cli {

enum ExitCode : int {
  exit_ok = 0,
  exit_failure = 1,    ///< runtime failure: a computation failed or produced a non-finite value
  exit_bad_input = 2,  ///< invalid options, unreadable or invalid case file
  exit_interrupted = 130,  ///< jointhb study stopped by SIGINT/SIGTERM after writing what it computed
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

/// Progress lines rewritten in place are for people watching: only when stderr is a terminal.
bool stderr_is_terminal();

/// Progress when stderr is not a terminal (a pipe, a log file, CI), where the in-place lines are
/// not shown: while this object lives, a background thread prints a plain line
///   COMMAND: running for 20 s: ACTIVITY
/// every `interval_seconds` (progress_interval()), so that a long run, also inside a stage without
/// events (the modes, the condensation), is not silent in a log, and a run shorter than the
/// interval prints nothing more than before. On a terminal it does nothing: the callers' in-place
/// line stays the display. One at a time: a second one while one lives does nothing.
class ProgressHeartbeat {
 public:
  ProgressHeartbeat(std::string command, double interval_seconds);
  ~ProgressHeartbeat();
  ProgressHeartbeat(const ProgressHeartbeat&) = delete;
  ProgressHeartbeat& operator=(const ProgressHeartbeat&) = delete;

 private:
  bool owner_ = false;
};

/// The heartbeat's interval [s]: 10, or the environment variable JOINTHB_PROGRESS_INTERVAL (a log
/// may want fewer lines, a test more). Throws io::InputError naming it when it is set but not a
/// number > 0; read before any output exists, like the options.
double progress_interval();

/// Ends the heartbeat's lines now, before the run's last line ("done in …"), so that no progress
/// line can follow it (its owner still joins the thread). Without a heartbeat: nothing.
void stop_progress_heartbeat();

/// Whether a heartbeat is running (callers skip formatting their activity otherwise).
bool progress_heartbeat_active();
/// What the run is doing now, for the heartbeat's next line.
void set_progress_activity(std::string activity);

/// set_progress_activity(fmt::format(...)), formatted only while a heartbeat runs.
template <class... Args>
void progress_activity(fmt::format_string<Args...> format, Args&&... args) {
  if (progress_heartbeat_active()) set_progress_activity(fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace jointhb::cli
