// A farm of numbered tasks on local worker processes and MPI ranks (task_farm.hpp).
//
// A rank's request carries its previous task as "TASK\nK" + text, K = 1 when text is the record,
// 0 when it is the failure's message; the first request is empty.
#include "task_farm.hpp"

#include <fmt/format.h>

#include <chrono>
#include <deque>
#include <exception>
#include <optional>
#include <stdexcept>
#include <thread>

#include "jointhb/study/distributed.hpp"
#include "worker_processes.hpp"

namespace jointhb::study {
namespace {

// How long the coordinator waits for its children while other ranks may be asking.
constexpr int kFarmPollMs = 2;

std::string farm_payload(std::size_t task, bool ok, const std::string& text) {
  return fmt::format("{}\n{}", task, ok ? '1' : '0') + text;
}

TaskDone farm_parse(const std::string& payload) {
  const std::size_t eol = payload.find('\n');
  if (eol == std::string::npos || eol + 1 >= payload.size())
    throw std::runtime_error("task farm: a malformed message from a rank");
  TaskDone d;
  d.task = static_cast<std::size_t>(std::stoull(payload.substr(0, eol)));
  (payload[eol + 1] == '1' ? d.record : d.failure) = payload.substr(eol + 2);
  return d;
}

// Another rank: tasks from rank 0 until it says there are none.
void farm_serve(const TaskRun& run, const Communicator& comm) {
  std::string payload;
  for (long long k = comm.request(payload); k >= 0; k = comm.request(payload)) {
    const auto task = static_cast<std::size_t>(k);
    try {
      payload = farm_payload(task, true, run(task));
    } catch (const std::exception& e) {
      payload = farm_payload(task, false, fmt::format("rank {}: {}", comm.rank(), e.what()));
    }
  }
}

// Rank 0's coordinator: the queue, its children, the other ranks' requests.
class Farm {
 public:
  Farm(std::size_t count, const std::function<void(TaskDone)>& done, const Communicator* comm)
      : count_(count), done_(done), comm_(comm), remote_(comm ? comm->size() - 1 : 0) {}

  void run(WorkerProcesses& children) {
    while (true) {
      for (int k : children.idle()) {
        const std::optional<std::size_t> next = take();
        if (!children.assign(k, next ? static_cast<long long>(*next) : -1LL) && next)
          requeued_.push_back(*next);  // the child had died: another worker takes the task
      }
      serve_ranks();
      const bool busy = children.busy() > 0;
      for (WorkerProcesses::Event& e : children.wait(remote_ > 0 ? kFarmPollMs : -1)) {
        done_({e.sample, std::move(e.record), e.death.empty() ? "" : e.death});
      }
      if (!busy && remote_ > 0) std::this_thread::sleep_for(std::chrono::milliseconds(kFarmPollMs));
      if (children.busy() == 0 && children.idle().empty() && remote_ == 0) break;
    }
  }

 private:
  std::optional<std::size_t> take() {
    if (!requeued_.empty()) {
      const std::size_t k = requeued_.front();
      requeued_.pop_front();
      return k;
    }
    if (next_ >= count_) return std::nullopt;
    return next_++;
  }

  void serve_ranks() {
    while (remote_ > 0) {
      std::optional<Communicator::Request> request = comm_->poll();
      if (!request) return;
      if (!request->payload.empty()) done_(farm_parse(request->payload));
      const std::optional<std::size_t> next = take();
      comm_->assign(request->source, next ? static_cast<long long>(*next) : -1LL);
      if (!next) --remote_;
    }
  }

  std::size_t count_;
  const std::function<void(TaskDone)>& done_;
  const Communicator* comm_;
  int remote_;
  std::size_t next_ = 0;
  std::deque<std::size_t> requeued_;
};

}  // namespace

void farm_tasks(std::size_t count, const TaskRun& run, const std::function<void(TaskDone)>& done,
                const TaskFarmOptions& options) {
  if (options.jobs < 1) throw std::invalid_argument(fmt::format("jobs must be >= 1, got {}", options.jobs));
  const Communicator* comm = options.communicator;
  if (comm && comm->rank() != 0) {
    farm_serve(run, *comm);
    return;
  }
  WorkerProcesses children(options.jobs, [&run]() -> WorkerProcesses::Evaluate { return run; });
  Farm(count, done, comm && comm->size() > 1 ? comm : nullptr).run(children);
}

}  // namespace jointhb::study
