#pragma once
// The JSON form of the status convention (contact/termination.hpp) in summary.json.
//
// Here and not in include/jointhb/io/: the library links nlohmann_json PRIVATE, and no installed
// header of it includes <nlohmann/json.hpp> (a program using the library need not have it). The
// command-line program, which writes summary.json, links it itself.

#include <nlohmann/json.hpp>

#include "jointhb/contact/termination.hpp"

namespace jointhb::cli {

/// {"termination": "converged", "ok": true, "message": "..."}.
[[nodiscard]] nlohmann::ordered_json to_json(const Status& status);

/// Merges to_json(status) into an existing status block of summary.json, keeping every key it has
/// (the older "status", "message", "stop_reason" that tests and users read): "termination" and
/// "ok" go right after "status" (first when there is none), "message" only where the block has
/// none. Throws std::invalid_argument when `block` is not an object.
void merge_status(nlohmann::ordered_json& block, const Status& status);

}  // namespace jointhb::cli
