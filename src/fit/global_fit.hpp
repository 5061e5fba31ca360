#pragma once
// A fit's direct or mlsl search (private to src/fit; fit/fitter.hpp, docs/identification.md §2
// "Parallel global searches"): the batch global phase (global_search.hpp) with start 0's
// evaluations, then the local searches — MLSL's, or DIRECT's polish from the best point — each a
// start of its own (1, 2, … in the order made). Every rank calls run_global: rank 0 evaluates each
// batch on the workers (its `jobs` children and the other ranks, study::farm_tasks) and sends the
// S values and local minima to every rank (Communicator::broadcast), so that every rank knows the
// next batch and serves it. Rank 0 alone keeps start 0's StartSearch (replayed rows, penalty,
// history rows to the sink, numbered in the order made) and the outcomes. With workers, rank 0's
// process computes nothing (a process that ran OpenMP regions and then forks leaves libgomp
// deadlocked in the child: CHOLMOD's factorisation hung so).

#include <optional>
#include <vector>

#include "jointhb/fit/fitter.hpp"
#include "start_search.hpp"

namespace jointhb::fit::detail {

struct GlobalProblem {
  const Model& model;
  const std::vector<FitParameter>& parameters;
  const FitOptions& options;  ///< algorithm direct or mlsl
  const std::vector<HistoryRow>& replay;
  std::vector<double> start;  ///< the user's start (unit box): the `from` of the global phase
};

/// The outcomes in the order start 0, then the local searches; nullopt on ranks > 0.
[[nodiscard]] std::optional<std::vector<StartOutcome>> run_global(const GlobalProblem& problem,
                                                                  const ParallelOptions& parallel,
                                                                  const HistorySink& sink);

}  // namespace jointhb::fit::detail
