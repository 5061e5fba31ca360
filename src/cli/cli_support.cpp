#include "cli_support.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <thread>

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

namespace {

// The heartbeat's state, shared by its thread and the callers. Never destroyed: the thread may
// still run while the process exits through a path that skips the owner's destructor.
struct Heartbeat {
  std::mutex mutex;
  std::condition_variable wake;
  bool stop = false;
  std::string command;
  std::string activity;
  std::thread thread;
};

Heartbeat& heartbeat() {
  static auto* state = new Heartbeat;
  return *state;
}

std::atomic<bool> heartbeat_running{false};

constexpr const char* kIntervalVariable = "JOINTHB_PROGRESS_INTERVAL";

}  // namespace

double progress_interval() {
  const char* text = std::getenv(kIntervalVariable);
  if (text == nullptr || *text == '\0') return 10.0;
  const auto value = io::parse_number(text);
  if (!value || !std::isfinite(*value) || *value <= 0.0)
    throw io::InputError("environment", 0, 0, kIntervalVariable,
                         fmt::format("must be a number of seconds > 0, got '{}'", text));
  return *value;
}

namespace {

void beat(Heartbeat& h, double interval) {
  const auto start = std::chrono::steady_clock::now();
  const auto period = std::chrono::duration<double>(interval);
  std::unique_lock lock(h.mutex);
  for (int k = 1;; ++k) {
    const auto due = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(k * period);
    if (h.wake.wait_until(lock, due, [&] { return h.stop; })) return;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string activity = h.activity.empty() ? "" : ": " + io::printable_one_line(h.activity);
    std::fprintf(stderr, "%s: running for %.*f s%s\n", h.command.c_str(), seconds < 10.0 ? 1 : 0, seconds,
                 activity.c_str());
    std::fflush(stderr);
  }
}

}  // namespace

ProgressHeartbeat::ProgressHeartbeat(std::string command, double interval_seconds) {
  if (stderr_is_terminal() || heartbeat_running.load()) return;
  Heartbeat& h = heartbeat();
  {
    const std::lock_guard lock(h.mutex);
    h.stop = false;
    h.command = std::move(command);
    h.activity.clear();
  }
  h.thread = std::thread(beat, std::ref(h), interval_seconds);
  owner_ = true;
  heartbeat_running.store(true);
}

ProgressHeartbeat::~ProgressHeartbeat() {
  if (!owner_) return;
  Heartbeat& h = heartbeat();
  {
    const std::lock_guard lock(h.mutex);
    h.stop = true;
  }
  h.wake.notify_all();
  h.thread.join();
  heartbeat_running.store(false);
}

void stop_progress_heartbeat() {
  if (!heartbeat_running.load()) return;
  Heartbeat& h = heartbeat();
  {
    // beat() holds the mutex while it prints and tests `stop` when it wakes, so no line starts
    // after this returns.
    const std::lock_guard lock(h.mutex);
    h.stop = true;
  }
  h.wake.notify_all();
}

bool progress_heartbeat_active() { return heartbeat_running.load(std::memory_order_relaxed); }

void set_progress_activity(std::string activity) {
  Heartbeat& h = heartbeat();
  const std::lock_guard lock(h.mutex);
  h.activity = std::move(activity);
}

}  // namespace jointhb::cli
