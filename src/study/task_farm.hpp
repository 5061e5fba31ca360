#pragma once
// A farm of numbered tasks on local worker processes and MPI ranks (private to src; used by the
// fit's parallel starts, fit/fitter.hpp). Tasks 0 … count−1 form one queue; rank 0's calling
// thread coordinates and computes nothing: it hands the next index to whichever worker is free —
// one of its `jobs` child processes (study/worker_processes.hpp: processes, not threads, because
// of the BLAS), or another rank, whose request carries its previous task's record — and passes
// each record to `done` in the order they finish. A slow task stalls no other worker. The
// records are the tasks' own business (e.g. JSON); a child that dies fails only its task.
//
// Every rank calls farm_tasks with the same count; the other ranks serve until rank 0 tells them
// there is no task left, then return (their `done` is never called).

#include <cstddef>
#include <functional>
#include <string>

namespace jointhb::study {

class Communicator;

struct TaskFarmOptions {
  int jobs = 1;  ///< child processes of rank 0 (≥ 1)
  const Communicator* communicator = nullptr;  ///< nullptr or size 1: this process alone
};

/// Evaluates task k and returns its record; runs in a child process or on another rank, never on
/// rank 0's coordinating thread. An exception fails the task (rank > 0: with its message).
using TaskRun = std::function<std::string(std::size_t task)>;

struct TaskDone {
  std::size_t task = 0;
  std::string record;   ///< the task's record; empty when it failed
  std::string failure;  ///< why it failed (the worker died or threw); empty otherwise
};

/// Runs tasks 0 … count−1 (see above). Throws std::runtime_error when a child cannot be forked.
void farm_tasks(std::size_t count, const TaskRun& run, const std::function<void(TaskDone)>& done,
                const TaskFarmOptions& options);

}  // namespace jointhb::study
