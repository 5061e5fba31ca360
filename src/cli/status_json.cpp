#include "status_json.hpp"

#include <stdexcept>
#include <string>

namespace jointhb::cli {

nlohmann::ordered_json to_json(const Status& status) {
  return {{"termination", std::string(to_string(status.termination))},
          {"ok", status.ok()},
          {"message", status.message}};
}

void put_status(nlohmann::ordered_json& block, const Status& status) {
  if (!block.is_object() && !block.is_null())
    throw std::invalid_argument("put_status: the status block is not a JSON object");
  const nlohmann::ordered_json add = to_json(status);
  for (auto it = add.begin(); it != add.end(); ++it) block[it.key()] = it.value();
}

void put_run_status(nlohmann::ordered_json& summary, const Status& run) {
  put_run_status(summary, run, run.ok() ? "ok" : "failed");
}

void put_run_status(nlohmann::ordered_json& summary, const Status& run, const char* status_word) {
  if (!summary.is_object()) throw std::invalid_argument("put_run_status: summary is not a JSON object");
  nlohmann::ordered_json head = {{"status", status_word}};
  put_status(head, run);
  // Rebuilt rather than assigned: ordered_json keeps insertion order, and a reader should find
  // the termination next to "status".
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  if (!summary.contains("status")) out.update(head);
  for (auto it = summary.begin(); it != summary.end(); ++it) {
    if (head.contains(it.key())) {
      if (it.key() == "status") out.update(head);
      continue;
    }
    out[it.key()] = it.value();
  }
  summary = std::move(out);
}

}  // namespace jointhb::cli
