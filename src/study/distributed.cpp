// The MPI world of a study (study/distributed.hpp).
#include "jointhb/study/distributed.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#ifdef JOINTHB_WITH_MPI
#include <mpi.h>
#endif

namespace jointhb::study {
#ifdef JOINTHB_WITH_MPI
namespace {

// Message tags of the protocol.
constexpr int kTagRequest = 1;  // worker → rank 0: the previous result (bytes), asks for a sample
constexpr int kTagAssign = 2;   // rank 0 → worker: the sample index (long long, −1: done)

}  // namespace
#endif

bool Communicator::launched_by_mpi() {
#ifdef JOINTHB_WITH_MPI
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(name)) return true;
  }
#endif
  return false;
}

bool Communicator::built_with_mpi() {
#ifdef JOINTHB_WITH_MPI
  return true;
#else
  return false;
#endif
}

Communicator::Communicator([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
#ifdef JOINTHB_WITH_MPI
  if (!launched_by_mpi()) return;
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    throw std::runtime_error("MPI_Init_thread failed");
  initialised_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
#endif
}

Communicator::~Communicator() {
#ifdef JOINTHB_WITH_MPI
  if (initialised_) MPI_Finalize();
#endif
}

std::optional<Communicator::Request> Communicator::poll() const {
#ifdef JOINTHB_WITH_MPI
  if (!initialised_) return std::nullopt;
  int flag = 0;
  MPI_Status status;
  MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, MPI_COMM_WORLD, &flag, &status);
  if (!flag) return std::nullopt;
  int bytes = 0;
  MPI_Get_count(&status, MPI_CHAR, &bytes);
  Request r;
  r.source = status.MPI_SOURCE;
  r.payload.resize(static_cast<std::size_t>(bytes));
  MPI_Recv(r.payload.data(), bytes, MPI_CHAR, status.MPI_SOURCE, kTagRequest, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return r;
#else
  return std::nullopt;
#endif
}

void Communicator::assign([[maybe_unused]] int rank, [[maybe_unused]] long long sample) const {
#ifdef JOINTHB_WITH_MPI
  if (initialised_) MPI_Send(&sample, 1, MPI_LONG_LONG, rank, kTagAssign, MPI_COMM_WORLD);
#endif
}

long long Communicator::request([[maybe_unused]] const std::string& payload) const {
#ifdef JOINTHB_WITH_MPI
  if (!initialised_) return -1;
  MPI_Send(payload.data(), static_cast<int>(payload.size()), MPI_CHAR, 0, kTagRequest, MPI_COMM_WORLD);
  long long sample = -1;
  MPI_Recv(&sample, 1, MPI_LONG_LONG, 0, kTagAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return sample;
#else
  return -1;
#endif
}

void Communicator::broadcast([[maybe_unused]] std::string& text) const {
#ifdef JOINTHB_WITH_MPI
  if (!initialised_ || size_ < 2) return;
  unsigned long long bytes = text.size();
  MPI_Bcast(&bytes, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  text.resize(bytes);
  // In pieces of at most 2^30 bytes (MPI counts are int).
  constexpr unsigned long long piece = 1ull << 30;
  for (unsigned long long at = 0; at < bytes; at += piece) {
    MPI_Bcast(text.data() + at, static_cast<int>(std::min(piece, bytes - at)), MPI_CHAR, 0,
              MPI_COMM_WORLD);
  }
#endif
}

void Communicator::abort([[maybe_unused]] int code) const {
#ifdef JOINTHB_WITH_MPI
  if (initialised_) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

}  // namespace jointhb::study
