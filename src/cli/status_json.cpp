#include "status_json.hpp"

#include <stdexcept>
#include <string>

namespace jointhb::cli {

nlohmann::ordered_json to_json(const Status& status) {
  return {{"termination", std::string(to_string(status.termination))},
          {"ok", status.ok()},
          {"message", status.message}};
}

void merge_status(nlohmann::ordered_json& block, const Status& status) {
  if (!block.is_object()) throw std::invalid_argument("merge_status: the status block is not a JSON object");
  const nlohmann::ordered_json add = to_json(status);
  // Rebuilt rather than appended: ordered_json keeps insertion order, and a reader of summary.json
  // should find the termination next to the old "status" it refines.
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  const auto put_new = [&] {
    out["termination"] = add["termination"];
    out["ok"] = add["ok"];
  };
  if (!block.contains("status")) put_new();
  for (auto it = block.begin(); it != block.end(); ++it) {
    if (it.key() == "termination" || it.key() == "ok") continue;  // replaced by this status
    out[it.key()] = it.value();
    if (it.key() == "status") put_new();
  }
  if (!out.contains("message")) out["message"] = add["message"];
  block = std::move(out);
}

}  // namespace jointhb::cli
