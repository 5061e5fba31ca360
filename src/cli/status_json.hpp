#pragma once
// The JSON form of the status convention (contact/termination.hpp) in summary.json and fit.json.
//
// Here and not in include/jointhb/io/: the library links nlohmann_json PRIVATE, and no installed
// header of it includes <nlohmann/json.hpp> (a program using the library need not have it). The
// command-line program, which writes summary.json, links it itself.

#include <nlohmann/json.hpp>

#include "jointhb/contact/termination.hpp"

namespace jointhb::cli {

/// {"termination": "converged", "ok": true, "message": "..."}.
[[nodiscard]] nlohmann::ordered_json to_json(const Status& status);

/// Writes to_json(status)'s three keys into a block of summary.json (replacing any it has; new keys
/// go at the end, so a block built in order gets them where this is called). Every status block —
/// a stage, a curve, the run, the fit — is written by this function and nothing else. Throws
/// std::invalid_argument when `block` is neither an object nor null.
void put_status(nlohmann::ordered_json& block, const Status& status);

/// The run's status at the top level of summary.json: "status" — "ok" when
/// run.ok(), else "failed", as the exit code 0 or 1 — followed by put_status(run)'s keys. `run`
/// is the worst of the run's stages and curves (jointhb::worst, contact/termination.hpp). Keeps
/// the block's other keys in their places ("status" where it was, else first).
void put_run_status(nlohmann::ordered_json& summary, const Status& run);

/// The same with the word of "status" given: "interrupted" for a run ended by SIGINT/SIGTERM,
/// "failed" for one ended by an error (run_support.hpp; "running" is written while it goes on).
void put_run_status(nlohmann::ordered_json& summary, const Status& run, const char* status_word);

}  // namespace jointhb::cli
