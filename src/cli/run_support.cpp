#include "run_support.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <atomic>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "cli_support.hpp"
#include "status_json.hpp"

namespace jointhb::cli {

namespace fs = std::filesystem;

namespace {

// The last summary written, for the interrupt handler and mark_summary_failed. Never destroyed:
// the handler's thread may use it while the main thread is already in exit().
struct SummaryState {
  std::mutex mutex;  // held while a summary is written, so an interrupt never tears one
  std::optional<fs::path> path;
  nlohmann::ordered_json last;
};

SummaryState& summary_state() {
  static auto* state = new SummaryState;
  return *state;
}

bool is_running(const nlohmann::ordered_json& summary) {
  return summary.is_object() && summary.contains("status") && summary["status"] == "running";
}

void write_file(const fs::path& path, const nlohmann::ordered_json& summary) {
  std::ofstream out(path, std::ios::out | std::ios::trunc);
  out << summary.dump(2) << '\n';
  out.flush();
  if (!out) throw std::runtime_error(fmt::format("cannot write '{}'", path.string()));
}

// Rewrites the last summary, if it is still "running", with the run status `word` (caller holds
// the mutex). Returns whether it did.
bool finish_running_summary(SummaryState& s, const Status& status, const char* word) {
  if (!s.path || !is_running(s.last)) return false;
  nlohmann::ordered_json summary = s.last;
  put_run_status(summary, status, word);
  write_file(*s.path, summary);
  s.last = std::move(summary);
  return true;
}

const char* signal_name(int sig) {
  switch (sig) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    default:
      return "a signal";
  }
}

// The PID in a lock file, or "" (the owner may not have written it yet).
std::string lock_owner(int fd) {
  char buffer[32] = {};
  const ssize_t n = ::pread(fd, buffer, sizeof buffer - 1, 0);
  std::string pid = n > 0 ? std::string(buffer, static_cast<std::size_t>(n)) : std::string();
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid.find_first_not_of("0123456789") == std::string::npos ? pid : std::string();
}

}  // namespace

void write_summary(const fs::path& path, const nlohmann::ordered_json& summary) {
  SummaryState& s = summary_state();
  const std::lock_guard lock(s.mutex);
  nlohmann::ordered_json written = summary;
  if (summary.is_object() && (!summary.contains("status") || summary["status"].is_null())) {
    // A run that has not ended: "status": "running", first (or where the placeholder is).
    nlohmann::ordered_json out = nlohmann::ordered_json::object();
    if (!summary.contains("status")) out["status"] = "running";
    for (auto it = summary.begin(); it != summary.end(); ++it)
      out[it.key()] = it.key() == "status" ? nlohmann::ordered_json("running") : it.value();
    written = std::move(out);
  }
  write_file(path, written);
  s.path = path;
  s.last = std::move(written);
}

void mark_summary_failed(const std::string& message) {
  SummaryState& s = summary_state();
  const std::lock_guard lock(s.mutex);
  try {
    finish_running_summary(s, {Termination::failed, message}, "failed");
  } catch (const std::exception&) {
    // The error that ended the run is the one to report.
  }
}

// Blocks SIGINT and SIGTERM in the calling thread (and so in every thread and child it starts
// afterwards) for a thread that sigwait()s on `set`. A signal ignored by whoever started the
// program (nohup, a background job of a script) stays ignored and is left out. Returns false when
// nothing could be blocked: then the default actions apply.
bool block_termination_signals(sigset_t& set) {
  sigemptyset(&set);
  for (int sig : {SIGINT, SIGTERM}) {
    struct sigaction current {};
    if (::sigaction(sig, nullptr, &current) == 0 && current.sa_handler == SIG_IGN) continue;
    sigaddset(&set, sig);
  }
  return ::pthread_sigmask(SIG_BLOCK, &set, nullptr) == 0;
}

void defer_termination_signals() {
  sigset_t set;
  block_termination_signals(set);
}

void allow_termination_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  ::pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
}

void install_interrupt_handler(const std::string& command) {
  sigset_t set;
  if (!block_termination_signals(set)) return;
  std::thread([set, command] {
    int sig = 0;
    while (::sigwait(&set, &sig) != 0) {
    }
    SummaryState& s = summary_state();
    s.mutex.lock();  // a summary being written is completed first; kept locked until the exit
    std::string where;
    try {
      if (finish_running_summary(
              s, {Termination::stopped_by_user, fmt::format("interrupted by {}", signal_name(sig))},
              "interrupted"))
        where = fmt::format(" ({}: \"status\": \"interrupted\")", s.path->string());
    } catch (const std::exception& e) {
      where = fmt::format(" ({})", e.what());
    }
    // On a terminal a progress line may be open: end it first. Elsewhere no blank line.
    std::fprintf(stderr, "%s%s: interrupted by %s%s\n", stderr_is_terminal() ? "\n" : "", command.c_str(),
                 signal_name(sig), where.c_str());
    std::fflush(stderr);
    std::_Exit(128 + sig);
  }).detach();
}

void install_stop_request(const std::string& command, std::atomic<bool>& stop, const std::string& what) {
  sigset_t set;
  if (!block_termination_signals(set)) return;
  std::thread([set, command, what, &stop] {
    int sig = 0;
    while (::sigwait(&set, &sig) != 0) {
    }
    stop = true;
    std::fprintf(stderr, "%s%s: interrupted by %s: %s (again to quit at once)\n", stderr_is_terminal() ? "\n" : "",
                 command.c_str(), signal_name(sig), what.c_str());
    std::fflush(stderr);
    while (::sigwait(&set, &sig) != 0) {
    }
    std::fprintf(stderr, "%s: interrupted by %s again: quit\n", command.c_str(), signal_name(sig));
    std::fflush(stderr);
    std::_Exit(128 + sig);
  }).detach();
}

OutputDirectory::OutputDirectory(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) {
    require_option("-o",
                   fmt::format("cannot create directory '{}': {}", dir_.string(), ec.message()));
  }
  if (!fs::is_directory(dir_, ec)) {
    require_option("-o", fmt::format("'{}' exists and is not a directory", dir_.string()));
  }
  const fs::path lock = dir_ / lock_file_name;
  fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    require_option("-o", fmt::format("cannot create the lock file '{}': {}", lock.string(),
                                     std::strerror(errno)));
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    const std::string owner = lock_owner(fd_);
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK) {
      throw UsageError(fmt::format(
          "output directory '{}' is in use by another jointhb run (PID {}; lock {}): wait for it "
          "or choose another -o",
          dir_.string(), owner.empty() ? "unknown" : owner, lock.string()));
    }
    require_option("-o", fmt::format("cannot lock '{}': {}", lock.string(), std::strerror(error)));
  }
  const std::string pid = fmt::format("{}\n", static_cast<long>(::getpid()));
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
    // The PID is for the message of a refused run only; the lock holds without it.
  }
}

OutputDirectory::~OutputDirectory() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

}  // namespace jointhb::cli
