// Worker processes of a study (worker_processes.hpp).
#include "worker_processes.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <thread>

namespace jointhb::study {
namespace {

bool write_all(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

bool read_all(int fd, void* data, std::size_t size) {
  char* p = static_cast<char*>(data);
  while (size > 0) {
    const ssize_t n = ::read(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

// The child: samples from `in` until −1 or EOF, records to `out`. Never returns.
//
// The work runs on a new thread of the child, not on the thread that forked: libgomp keeps its
// thread pool per master thread, and after fork() the forking thread's pool names threads that
// do not exist in the child — its next parallel region of more than one thread waits for them
// forever (CHOLMOD's supernodal factorisation asks for CHOLMOD_OMP_NUM_THREADS = 4 threads, so
// omp_set_num_threads cannot prevent it). A new thread starts with no pool and gets a fresh one.
// Python's run_study(jobs=2) after a preload in the same interpreter hung so (fit and study from
// the program never compute in the parent before forking).
[[noreturn]] void child_main(int in, int out, const WorkerProcesses::Setup& setup, int threads) {
  int code = 0;
  std::thread worker([&] {
    try {
      omp_set_num_threads(threads);
      const WorkerProcesses::Evaluate evaluate = setup();
      long long sample = -1;
      while (read_all(in, &sample, sizeof sample) && sample >= 0) {
        const std::string record = evaluate(static_cast<std::size_t>(sample));
        const std::uint64_t size = record.size();
        if (!write_all(out, &size, sizeof size) || !write_all(out, record.data(), record.size())) break;
      }
    } catch (...) {
      code = 1;  // the parent sees the pipe close and fails the sample
    }
  });
  worker.join();
  ::_exit(code);  // no atexit handlers, no destructors of the parent's objects
}

}  // namespace

WorkerProcesses::WorkerProcesses(int count, const Setup& setup) {
  ::signal(SIGPIPE, SIG_IGN);  // a write to a dead child returns EPIPE instead of killing us
  // Several children share the cores: one thread each. A lone child (one task, e.g. a fit's
  // polish) takes this process's threads (results do not depend on the thread count).
  const int threads = count > 1 ? 1 : omp_get_max_threads();
  for (int k = 0; k < count; ++k) {
    int down[2], up[2];
    if (::pipe(down) != 0 || ::pipe(up) != 0) throw std::runtime_error(std::string("study: pipe: ") + std::strerror(errno));
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error(std::string("study: fork: ") + std::strerror(errno));
    if (pid == 0) {
      ::close(down[1]);
      ::close(up[0]);
      for (const Child& other : children_) {  // the pipes of the children forked before
        ::close(other.to_child);
        ::close(other.from_child);
      }
      child_main(down[0], up[1], setup, threads);
    }
    ::close(down[0]);
    ::close(up[1]);
    Child c;
    c.pid = pid;
    c.to_child = down[1];
    c.from_child = up[0];
    c.alive = true;
    children_.push_back(c);
  }
}

WorkerProcesses::~WorkerProcesses() {
  for (Child& c : children_) {
    if (c.alive) {
      const long long stop = -1;
      (void)write_all(c.to_child, &stop, sizeof stop);
    }
  }
  for (Child& c : children_) {
    if (c.pid > 0) (void)reap(c);
  }
}

std::string WorkerProcesses::reap(Child& c) {
  if (c.to_child >= 0) ::close(c.to_child);
  if (c.from_child >= 0) ::close(c.from_child);
  c.to_child = c.from_child = -1;
  c.alive = false;
  int status = 0;
  std::string why = "the worker process ended";
  if (c.pid > 0 && ::waitpid(c.pid, &status, 0) == c.pid) {
    if (WIFSIGNALED(status)) why = fmt::format("the worker process was killed by signal {} ({})", WTERMSIG(status), ::strsignal(WTERMSIG(status)));
    else if (WIFEXITED(status)) why = fmt::format("the worker process exited with code {}", WEXITSTATUS(status));
  }
  c.pid = -1;
  return why;
}

std::vector<WorkerProcesses::Event> WorkerProcesses::wait(int timeout_ms) {
  std::vector<pollfd> fds;
  std::vector<std::size_t> which;
  for (std::size_t k = 0; k < children_.size(); ++k) {
    if (children_[k].alive && children_[k].sample) {
      fds.push_back({children_[k].from_child, POLLIN, 0});
      which.push_back(k);
    }
  }
  std::vector<Event> events;
  if (fds.empty()) return events;
  int ready = ::poll(fds.data(), fds.size(), timeout_ms);
  if (ready <= 0) return events;
  for (std::size_t i = 0; i < fds.size(); ++i) {
    if (!(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
    Child& c = children_[which[i]];
    Event e;
    e.sample = *c.sample;
    std::uint64_t size = 0;
    // A child writes its whole record at once: once readable, the rest follows.
    if (read_all(c.from_child, &size, sizeof size)) {
      e.record.resize(size);
      if (read_all(c.from_child, e.record.data(), size)) {
        c.sample.reset();
        events.push_back(std::move(e));
        continue;
      }
      e.record.clear();
    }
    e.death = reap(c);
    events.push_back(std::move(e));
  }
  return events;
}

std::vector<int> WorkerProcesses::idle() const {
  std::vector<int> out;
  for (std::size_t k = 0; k < children_.size(); ++k) {
    if (children_[k].alive && !children_[k].sample) out.push_back(static_cast<int>(k));
  }
  return out;
}

bool WorkerProcesses::assign(int child, long long sample) {
  Child& c = children_.at(static_cast<std::size_t>(child));
  if (!write_all(c.to_child, &sample, sizeof sample)) {
    (void)reap(c);
    return false;
  }
  if (sample < 0) {
    (void)reap(c);
    return true;
  }
  c.sample = static_cast<std::size_t>(sample);
  return true;
}

int WorkerProcesses::busy() const {
  int n = 0;
  for (const Child& c : children_) n += c.alive && c.sample ? 1 : 0;
  return n;
}

}  // namespace jointhb::study
