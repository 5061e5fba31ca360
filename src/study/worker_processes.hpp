#pragma once
// Worker processes of a study (private to src/study): rank 0 evaluates its samples in child
// processes when it runs more than one local worker. Not threads: the BLAS the setup installs
// (Debian's libopenblas0-serial, built without locking) corrupts its buffers when two threads
// factorise at once — a study on two threads of the lap failed every preload with "not positive
// definite", one thread or the reference BLAS did not (docs/studies.md §5). A child also cannot
// take the coordinator down with it: a crash fails its sample, the others go on.
//
// Protocol on two pipes per child: parent → child a long long sample index (−1: exit); child →
// parent a u64 length and the sample's record (sample_to_json).

#include <sys/types.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace jointhb::study {

class WorkerProcesses {
 public:
  /// What a child evaluates: sample index → its record (sample_to_json). Runs in the child.
  using Evaluate = std::function<std::string(std::size_t sample)>;
  /// Made in the child before its first sample (e.g. the model); may be empty.
  using Setup = std::function<Evaluate()>;

  /// Forks `count` children (OpenMP: one thread each, or this process's thread count when
  /// count is 1). Throws std::runtime_error when fork or pipe fail.
  WorkerProcesses(int count, const Setup& setup);
  ~WorkerProcesses();  ///< tells the children to exit and reaps them
  WorkerProcesses(const WorkerProcesses&) = delete;
  WorkerProcesses& operator=(const WorkerProcesses&) = delete;

  struct Event {
    std::size_t sample = 0;
    std::string record;  ///< the child's record; empty when the child died
    std::string death;   ///< why the child ended while evaluating `sample` (empty otherwise)
  };
  /// Waits up to `timeout_ms` (−1: until something happens) for finished samples and dead children.
  std::vector<Event> wait(int timeout_ms);
  /// Idle children (alive, no sample): their indices.
  [[nodiscard]] std::vector<int> idle() const;
  /// Gives `sample` to idle child `child` (−1: tells it to exit). Returns false when it has died.
  bool assign(int child, long long sample);
  /// Children still running a sample.
  [[nodiscard]] int busy() const;

 private:
  struct Child {
    pid_t pid = -1;
    int to_child = -1, from_child = -1;
    std::optional<std::size_t> sample;  ///< what it is evaluating
    bool alive = false;
  };
  std::string reap(Child& c);
  std::vector<Child> children_;
};

}  // namespace jointhb::study
