#pragma once
// What the analyses of `jointhb run` share: the output directory and its lock, summary.json and
// its status while the run is going on, the handling of SIGINT/SIGTERM, timing.

#include <atomic>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace jointhb::cli {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The output directory of a run (`run`, `fit`), created with its parents and locked for the
/// lifetime of this object: an exclusive advisory lock (flock) on DIR/.jointhb.lock, which holds
/// the owner's PID. A second run on the same directory while the first holds it is refused with a
/// UsageError (exit code 2) naming the directory and the other run's PID, instead of interleaving
/// rows in the same files. The kernel releases the lock when the process ends in any way (also on
/// SIGKILL or a crash); the file itself stays.
class OutputDirectory {
 public:
  /// Throws io::InputError naming -o when DIR cannot be created, UsageError when it is locked.
  explicit OutputDirectory(std::filesystem::path dir);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  [[nodiscard]] const std::filesystem::path& path() const { return dir_; }

  static constexpr const char* lock_file_name = ".jointhb.lock";

 private:
  std::filesystem::path dir_;
  int fd_ = -1;
};

/// Writes summary.json (2-space indent); std::runtime_error naming the path when it fails.
/// A summary whose "status" is missing or null is written with "status": "running" first: the run
/// that writes it has not ended. The last summary written is kept for the interrupt handler
/// (install_interrupt_handler) and for mark_summary_failed.
void write_summary(const std::filesystem::path& path, const nlohmann::ordered_json& summary);

/// From here to the end of the process, SIGINT and SIGTERM (unless ignored when the program
/// started) end it in an orderly way: a thread waiting for them (no work in a signal handler)
/// rewrites the last summary written, if it still says "running", with "status": "interrupted"
/// (termination stopped_by_user, the signal in its message), says so on stderr in one line
/// prefixed with `command`, and exits with 128 + the signal number (130, 143). Rows already
/// flushed stay. Call before any thread is started: the signals are blocked in the calling thread
/// and in every thread it starts afterwards.
void install_interrupt_handler(const std::string& command);

/// `jointhb study`: from here on, the first SIGINT or SIGTERM (unless ignored at the start) sets
/// `stop` and says on stderr "COMMAND: interrupted by SIGINT: WHAT (again to quit at once)"; the
/// second ends the process with 128 + the signal number. Call before any thread is started (the
/// signals are blocked in the calling thread and in every thread or child process it starts
/// afterwards: a study's worker processes finish their sample). `stop` must outlive the process.
void install_stop_request(const std::string& command, std::atomic<bool>& stop, const std::string& what);
/// Blocks SIGINT and SIGTERM (unless ignored at the start) in the calling thread before a library
/// starts threads of its own (MPI_Init, PETSc): a process-directed signal would otherwise reach one
/// of them and its default action end the process before install_interrupt_handler's thread sees
/// it. allow_termination_signals() undoes it in the calling thread for commands without a handler.
void defer_termination_signals();
void allow_termination_signals();

/// When the last summary written still says "running" (the run ends with an exception), rewrites
/// it with "status": "failed" and the message; does nothing otherwise.
void mark_summary_failed(const std::string& message);

}  // namespace jointhb::cli
