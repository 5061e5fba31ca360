#pragma once
// How a computation ended: one convention for every stage result (design: "one status convention
// for results — a termination enum, a message, brief(), and JSON serialisation used by
// summary.json — instead of six enums, bools and hand-built JSON blocks"), after Ceres Solver's
// TerminationType (CONVERGENCE, NO_CONVERGENCE, FAILURE, USER_SUCCESS/USER_FAILURE), with
// `reached_end` added for runs over a range (continuation, sweeps) whose goal is to cover it.
//
// It lives in the contact folder only because contact is the lowest layer (contact → fe → preload
// → modal → reduction → hb → continuation → fit → pipeline → io → cli; a layer includes only lower
// ones): every result of every layer can return a Status. It depends on nothing of contact.
//
// Every result reads the same way: `result.status()` returns a Status (`.termination`,
// `.message`, `.ok()`, `.brief()`). A result with nothing more to say than a Termination stores
// `Termination termination` and `std::string message` and status() returns them (PreloadResult,
// ModalResult, PeriodicStateResult, the time integrations' results); a result whose detail says
// more keeps that detail (a continuation's StopReason, a ring-down's RingDownReason, the fit's
// NLopt stop reason) and its status() is the one place where the detail is translated. The JSON
// form ({"termination", "ok", "message"}) is written by the command-line program (src/cli/
// status_json.hpp), since the library keeps its JSON library private.
//
// The enumerators' values are stored in the stage cache (io/stage_cache.cpp): append, never
// reorder; their order is also the order of severity used by worst().

#include <span>
#include <string>
#include <string_view>

namespace jointhb {

/// How a computation ended. The first two are success (`succeeded`); the results computed up to
/// the end are valid in every case except `failed`, and even then a continuation keeps the points
/// it accepted before the failure.
enum class Termination {
  /// An iterative solve met its tolerance (Newton, Lanczos, a periodic state, an optimiser's
  /// xtol/ftol). Not used by a continuation, whose goal is a range, not a tolerance.
  converged,
  /// A run over a range covered it: a continuation accepted a point on its end parameter, a
  /// time integration took all its steps, or the run stopped at a goal it was given (a damping
  /// curve's frequency drop, a ring-down's decay).
  reached_end,
  /// A callback of the caller (an accept/point callback returning false, Ctrl-C) stopped it: the
  /// results so far are valid, the run is incomplete by request. Not a success.
  stopped_by_user,
  /// The budget ran out before the goal: an iterative solve used its max_iterations (or
  /// max_periods, max_evaluations) without meeting the tolerance, or a continuation its
  /// max_points before the end. More iterations (or points) may well succeed.
  no_convergence,
  /// A numerical breakdown that more iterations would not cure: a singular factorisation, a line
  /// search without decrease, a continuation whose step fell below min_step, whose start point
  /// did not converge or whose branch turned back, a non-finite value, every evaluation failed.
  failed,
};

/// The enumerator's name ("converged", "reached_end", "stopped_by_user", "no_convergence",
/// "failed"), as written to summary.json.
[[nodiscard]] std::string_view to_string(Termination termination);

/// converged or reached_end: the computation did what it was asked.
[[nodiscard]] bool succeeded(Termination termination);

/// How a computation ended, and why, in one line.
struct Status {
  Termination termination = Termination::failed;
  std::string message;  ///< one line: what happened (may be empty)

  [[nodiscard]] bool ok() const { return succeeded(termination); }
  /// "converged: <message>", or just "converged" when the message is empty.
  [[nodiscard]] std::string brief() const;
};

/// One part of a run (a stage, a curve) and how it ended, for worst().
struct NamedStatus {
  std::string name;  ///< e.g. "preload", "backbone mode 1", "curve level 2"
  Status status;
};

/// The status of a run made of parts (its stages and curves): the worst part, in the enumerators'
/// order (converged < reached_end < stopped_by_user < no_convergence < failed), the first such on
/// a tie, with the part's name before its message ("preload: …"). No parts: converged with an empty
/// message. The one definition of a run's overall status (summary.json's top level).
[[nodiscard]] Status worst(std::span<const NamedStatus> parts);

}  // namespace jointhb
