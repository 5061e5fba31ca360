// Running a parameter study on local workers and MPI ranks (study/study.hpp, study/distributed.hpp).
//
// Scheduling: the samples still to do form one queue; a worker (rank 0's worker thread or child
// processes, or another rank) takes the next index when it is free, so a slow sample holds up no
// one. Rank 0's main thread coordinates and computes nothing: it collects its workers' results,
// answers the other ranks' requests (each carries the rank's previous result), writes each
// sample's file and calls on_sample. With other ranks it polls (MPI_Iprobe, then a 2 ms wait)
// instead of blocking in MPI, so it takes no core from the workers.
#include <fmt/format.h>
#include <omp.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "../support/stopwatch.hpp"
#include "jointhb/study/distributed.hpp"
#include "jointhb/study/study.hpp"
#include "worker_processes.hpp"

namespace jointhb::study {
namespace {

namespace fs = std::filesystem;

// How long rank 0's coordinator waits between polls of the other ranks' requests.
constexpr auto kPollInterval = std::chrono::milliseconds(2);
// How often the coordinator looks at RunOptions::interrupt when nothing else wakes it.
constexpr auto kInterruptInterval = std::chrono::milliseconds(100);

fs::path sample_file(const fs::path& dir, std::size_t sample) {
  return dir / fmt::format("sample_{:06d}.json", sample);
}

// Bitwise equality of two parameter vectors (a restart reuses a sample only for exactly its values).
bool same_values(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(&a[i], &b[i], sizeof(double)) != 0) return false;
  }
  return true;
}

// A model that fails every sample with the reason its factory failed.
SampleModel failing_model(std::string reason) {
  return [reason](const std::vector<double>&) -> fit::ModelPrediction { throw std::runtime_error(reason); };
}

SampleModel make_model(const SampleModelFactory& factory) {
  try {
    return factory();
  } catch (const std::exception& e) {
    return failing_model(std::string("the case's model could not be built: ") + e.what());
  }
}

// Samples the queue hands out, shared by rank 0's worker thread and its coordinator.
struct Queue {
  std::vector<std::size_t> todo;
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};
  /// The next sample to evaluate, or nullopt when none is left (or the study was stopped).
  std::optional<std::size_t> take() {
    if (stop.load()) return std::nullopt;
    const std::size_t k = next.fetch_add(1);
    if (k >= todo.size()) return std::nullopt;
    return todo[k];
  }
};

// Results of rank 0's worker thread, waiting for the coordinator.
struct Mailbox {
  std::mutex mutex;
  std::condition_variable ready;
  std::deque<SampleResult> results;
  int running = 0;  ///< worker threads not yet finished (0 or 1)
};

class Coordinator {
 public:
  Coordinator(const StudySpec& spec, const RunOptions& options, std::vector<std::vector<double>> points)
      : spec_(spec), options_(options), points_(std::move(points)) {
    result_.keys = output_keys(spec.outputs);
    result_.samples.resize(points_.size());
    result_.done.assign(points_.size(), false);
    for (std::size_t i = 0; i < points_.size(); ++i) {
      result_.samples[i].sample = i;
      result_.samples[i].values = points_[i];
      result_.samples[i].status = {Termination::stopped_by_user, "not run"};
    }
  }

  // Reuses the sample files of an earlier run that match (identity, values, output count).
  void resume() {
    if (!options_.resume || options_.sample_directory.empty()) return;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const fs::path file = sample_file(options_.sample_directory, i);
      std::error_code ec;
      if (!fs::exists(file, ec)) continue;
      std::ifstream in(file);
      std::stringstream text;
      text << in.rdbuf();
      try {
        std::string identity;
        SampleResult s = sample_from_json(text.str(), identity);
        if (identity != options_.identity || s.sample != i || !same_values(s.values, points_[i]) ||
            s.outputs.size() != result_.keys.size()) {
          result_.warnings.push_back(fmt::format("{}: belongs to another study (case, design or outputs differ): recomputed", file.string()));
          continue;
        }
        s.reused = true;
        record(std::move(s), "");
      } catch (const std::exception& e) {
        result_.warnings.push_back(fmt::format("{}: {}: recomputed", file.string(), e.what()));
      }
    }
  }

  // Stores a finished sample, writes its file (payload: its JSON when already made) and reports it.
  void record(SampleResult s, std::string payload, bool keep_file = true) {
    const std::size_t i = s.sample;
    if (i >= result_.samples.size() || result_.done[i]) return;  // a stale or repeated message
    if (keep_file && !s.reused && !options_.sample_directory.empty()) {
      if (payload.empty()) payload = sample_to_json(s, options_.identity);
      write_file(i, payload);
    }
    (s.reused ? result_.reused : result_.computed) += 1;
    if (!s.status.ok()) ++result_.failed;
    result_.samples[i] = std::move(s);
    result_.done[i] = true;
    ++finished_;
    if (options_.on_sample && !options_.on_sample(result_.samples[i], finished_, points_.size())) queue_.stop = true;
  }

  StudyResult run(const SampleModelFactory& factory) {
    const auto start = support::Clock::now();
    resume();
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (!result_.done[i]) queue_.todo.push_back(i);
    }
    const Communicator* comm = options_.communicator;
    int remote = comm ? comm->size() - 1 : 0;  // other ranks not yet told to stop
    // One local worker: a thread (the coordinator itself computes nothing). More: child processes
    // (worker_processes.hpp says why not threads).
    std::optional<WorkerProcesses> processes;
    std::optional<std::thread> thread;
    if (queue_.todo.empty()) {
      // nothing to compute locally
    } else if (options_.jobs > 1) {
      processes.emplace(options_.jobs, [&]() -> WorkerProcesses::Evaluate {
        SampleModel model = make_model(factory);
        return [this, model](std::size_t i) {
          return sample_to_json(evaluate_sample(model, spec_.outputs, i, points_[i]), options_.identity);
        };
      });
    } else {
      mailbox_.running = 1;
      thread.emplace([&] { work(factory); });
    }
    const auto interval = remote > 0 ? kPollInterval : kInterruptInterval;
    while (true) {
      if (options_.interrupt && options_.interrupt->load()) queue_.stop = true;
      const bool waiting_for_ranks = remote > 0;
      if (thread) {
        std::deque<SampleResult> ready;
        {
          std::unique_lock lock(mailbox_.mutex);
          const auto woken = [&] { return !mailbox_.results.empty() || (mailbox_.running == 0 && !waiting_for_ranks); };
          if (!waiting_for_ranks && !processes && !options_.interrupt) {
            mailbox_.ready.wait(lock, woken);
          } else {
            mailbox_.ready.wait_for(lock, interval, woken);
          }
          ready.swap(mailbox_.results);
        }
        for (auto& s : ready) record(std::move(s), "");
      }
      if (processes) serve_processes(*processes, waiting_for_ranks || options_.interrupt != nullptr, interval);
      while (remote > 0) {
        std::optional<Communicator::Request> request = comm->poll();
        if (!request) break;
        if (!request->payload.empty()) {
          std::string identity;
          record(sample_from_json(request->payload, identity), request->payload);
        }
        const std::optional<std::size_t> next = take();
        comm->assign(request->source, next ? static_cast<long long>(*next) : -1LL);
        if (!next) --remote;
      }
      bool local_done = !processes || (processes->busy() == 0 && processes->idle().empty());
      if (thread) {
        const std::lock_guard lock(mailbox_.mutex);
        local_done = local_done && mailbox_.running == 0 && mailbox_.results.empty();
      }
      if (local_done && remote == 0) break;
      if (!thread && !processes && remote > 0) std::this_thread::sleep_for(kPollInterval);
    }
    if (thread) thread->join();
    processes.reset();
    result_.ranks = comm ? comm->size() : 1;
    result_.jobs = options_.jobs;
    for (bool d : result_.done) result_.not_run += d ? 0 : 1;
    std::vector<SampleResult> done;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (result_.done[i]) done.push_back(result_.samples[i]);
    }
    result_.statistics = output_statistics(result_.keys, done, spec_.quantiles);
    result_.seconds = support::seconds_since(start);
    return std::move(result_);
  }

 private:
  // The next sample: one given back by a child that died before taking it, else the queue's next.
  std::optional<std::size_t> take() {
    if (!requeued_.empty() && !queue_.stop.load()) {
      const std::size_t i = requeued_.front();
      requeued_.pop_front();
      return i;
    }
    return queue_.take();
  }

  // Hands samples to idle children, then waits up to `interval` (or, with no other ranks to serve
  // and no interrupt to watch, until a child finishes) and records what came back. A child that
  // died fails its sample (not written to a sample file: a restart tries it again).
  void serve_processes(WorkerProcesses& processes, bool bounded_wait, std::chrono::milliseconds interval) {
    for (int k : processes.idle()) {
      const std::optional<std::size_t> next = take();
      if (!processes.assign(k, next ? static_cast<long long>(*next) : -1LL) && next) requeued_.push_back(*next);
    }
    for (WorkerProcesses::Event& e : processes.wait(bounded_wait ? static_cast<int>(interval.count()) : -1)) {
      if (e.death.empty()) {
        std::string identity;
        SampleResult s = sample_from_json(e.record, identity);
        record(std::move(s), std::move(e.record));
        continue;
      }
      SampleResult s;
      s.sample = e.sample;
      s.values = points_[e.sample];
      s.status = {Termination::failed, e.death + " while evaluating this sample"};
      s.outputs.assign(result_.keys.size(), std::nullopt);
      result_.warnings.push_back(fmt::format("sample {}: {}", e.sample, s.status.message));
      record(std::move(s), "", false);
    }
  }

  // A worker thread of rank 0: one model, one OpenMP thread (the sample's result must not depend
  // on the thread count), samples from the queue until it is empty.
  void work(const SampleModelFactory& factory) {
    omp_set_num_threads(1);
    const SampleModel model = make_model(factory);
    while (const std::optional<std::size_t> i = queue_.take()) {
      SampleResult s = evaluate_sample(model, spec_.outputs, *i, points_[*i]);
      const std::lock_guard lock(mailbox_.mutex);
      mailbox_.results.push_back(std::move(s));
      mailbox_.ready.notify_one();
    }
    const std::lock_guard lock(mailbox_.mutex);
    --mailbox_.running;
    mailbox_.ready.notify_one();
  }

  void write_file(std::size_t i, const std::string& payload) {
    const fs::path file = sample_file(options_.sample_directory, i);
    const fs::path partial = file.string() + ".partial";
    {
      std::ofstream out(partial, std::ios::trunc);
      out << payload << '\n';
      if (!out.flush()) {
        result_.warnings.push_back(fmt::format("{}: could not be written (a restart will recompute sample {})", file.string(), i));
        return;
      }
    }
    std::error_code ec;
    fs::rename(partial, file, ec);
    if (ec) result_.warnings.push_back(fmt::format("{}: {} (a restart will recompute sample {})", file.string(), ec.message(), i));
  }

  const StudySpec& spec_;
  const RunOptions& options_;
  std::vector<std::vector<double>> points_;
  StudyResult result_;
  Queue queue_;
  std::deque<std::size_t> requeued_;
  Mailbox mailbox_;
  std::size_t finished_ = 0;
};

// Another rank: one model, samples from rank 0 until it says there are none.
StudyResult run_worker(const StudySpec& spec, const SampleModelFactory& factory, const RunOptions& options,
                       const std::vector<std::vector<double>>& points) {
  const auto start = support::Clock::now();
  omp_set_num_threads(1);
  const SampleModel model = make_model(factory);
  StudyResult r;
  r.root = false;
  r.keys = output_keys(spec.outputs);
  r.ranks = options.communicator->size();
  std::string payload;  // the previous result
  for (long long i = options.communicator->request(payload); i >= 0; i = options.communicator->request(payload)) {
    const auto k = static_cast<std::size_t>(i);
    const SampleResult s = evaluate_sample(model, spec.outputs, k, points.at(k));
    payload = sample_to_json(s, options.identity);
    ++r.computed;
  }
  r.seconds = support::seconds_since(start);
  return r;
}

}  // namespace

StudyResult run_study(const StudySpec& spec, const SampleModelFactory& factory, const RunOptions& options) {
  if (const std::string e = spec.validate(); !e.empty()) throw std::invalid_argument("study: " + e);
  if (options.jobs < 1) throw std::invalid_argument(fmt::format("study: jobs must be >= 1, got {}", options.jobs));
  std::vector<std::vector<double>> points = sample_points(spec.sampling);
  if (options.communicator && options.communicator->rank() != 0) return run_worker(spec, factory, options, points);
  if (!options.sample_directory.empty()) {
    std::error_code ec;
    fs::create_directories(options.sample_directory, ec);
    if (ec) throw std::invalid_argument(fmt::format("study: cannot create {}: {}", options.sample_directory.string(), ec.message()));
  }
  Coordinator coordinator(spec, options, std::move(points));
  return coordinator.run(factory);
}

}  // namespace jointhb::study
