// The status convention of stage results (contact/termination.hpp).
#include "jointhb/contact/termination.hpp"

namespace jointhb {

std::string_view to_string(Termination termination) {
  switch (termination) {
    case Termination::converged:
      return "converged";
    case Termination::reached_end:
      return "reached_end";
    case Termination::stopped_by_user:
      return "stopped_by_user";
    case Termination::no_convergence:
      return "no_convergence";
    case Termination::failed:
      return "failed";
  }
  return "unknown";
}

bool succeeded(Termination termination) {
  return termination == Termination::converged || termination == Termination::reached_end;
}

std::string Status::brief() const {
  std::string out(to_string(termination));
  if (!message.empty()) out += ": " + message;
  return out;
}

Status worst(std::span<const NamedStatus> parts) {
  const NamedStatus* worst_part = nullptr;
  for (const NamedStatus& part : parts)
    if (worst_part == nullptr || part.status.termination > worst_part->status.termination) worst_part = &part;
  if (worst_part == nullptr) return {Termination::converged, {}};
  const Status& s = worst_part->status;
  if (worst_part->name.empty()) return s;
  return {s.termination, s.message.empty() ? worst_part->name : worst_part->name + ": " + s.message};
}

}  // namespace jointhb
