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

}  // namespace jointhb
