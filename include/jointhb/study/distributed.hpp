#pragma once
// The MPI world of a study (docs/studies.md §5). Built with MPI (cmake -DJOINTHB_WITH_MPI=ON, on
// by default when Open MPI is found) and started by mpirun/mpiexec, a Communicator initialises MPI
// and a study runs on every rank: rank 0 hands out sample indices on request and gathers the
// results (each rank's request carries the result of its previous sample), so a rank that is
// free takes the next sample and a slow or failed sample stalls no other rank. Otherwise (no MPI
// in the build, or not started by a launcher) it is a world of one process and MPI is never
// touched: a plain `jointhb study` needs no MPI runtime.
//
// Only the thread that made the Communicator calls MPI (MPI_THREAD_FUNNELED): rank 0 serves the
// requests from its main thread while its local worker (a thread, or child processes) computes.

#include <optional>
#include <string>

namespace jointhb::study {

class Communicator {
 public:
  /// Initialises MPI when the build has it and the environment shows an MPI launcher
  /// (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK). Throws std::runtime_error when MPI_Init fails.
  Communicator(int* argc, char*** argv);
  ~Communicator();  ///< MPI_Finalize when this object initialised MPI
  Communicator(const Communicator&) = delete;
  Communicator& operator=(const Communicator&) = delete;

  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }
  /// Whether this build can run on several ranks at all.
  [[nodiscard]] static bool built_with_mpi();
  /// Whether MPI will be initialised: the build has it and a launcher started the program.
  [[nodiscard]] static bool launched_by_mpi();

  // ---- the study's protocol (study/runner.cpp) -------------------------------------------------
  struct Request {
    int source = 0;
    std::string payload;  ///< the previous sample's result (sample_to_json), empty on the first request
  };
  /// Rank 0: a request that has arrived, without waiting; nullopt when none.
  [[nodiscard]] std::optional<Request> poll() const;
  /// Rank 0: answers a request with the next sample index (−1: no more samples).
  void assign(int rank, long long sample) const;
  /// Other ranks: sends `payload` to rank 0 and waits for the next sample index (−1: done).
  [[nodiscard]] long long request(const std::string& payload) const;
  /// Every rank: `text` becomes rank 0's (a collective call: every rank must make it, in the
  /// same order). Used by the fit's global searches, which every rank follows (fit/fitter.hpp).
  void broadcast(std::string& text) const;
  /// Aborts every rank (an error on one rank that the others would wait for forever).
  [[noreturn]] void abort(int code) const;

 private:
  int rank_ = 0;
  int size_ = 1;
  [[maybe_unused]] bool initialised_ = false;  ///< (unused in a build without MPI)
};

}  // namespace jointhb::study
