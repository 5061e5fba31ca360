// Contact states from the law's own variables (hb/contact_state.hpp, docs/theory.md §14).
#include "jointhb/hb/contact_state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace jointhb::hb {

std::string_view contact_state_name(ContactState state) {
  switch (state) {
    case ContactState::stuck: return "stuck";
    case ContactState::microslip: return "microslip";
    case ContactState::gross_slip: return "gross_slip";
    case ContactState::gapping: return "gapping";
    case ContactState::open: return "open";
  }
  return "unknown";
}

std::string ContactStateOptions::validate() const {
  if (!(stuck_ratio > 0.0 && stuck_ratio < 1.0))
    return fmt::format("stuck_ratio: must lie in (0, 1), got {}", stuck_ratio);
  if (!(limit_tolerance >= 0.0 && limit_tolerance < 1e-2))
    return fmt::format("limit_tolerance: must lie in [0, 0.01), got {}", limit_tolerance);
  return {};
}

ContactState classify_contact_state(const ContactStateInputs& in, const ContactStateOptions& options) {
  if (in.open_fraction >= 1.0) return ContactState::open;
  if (in.open_fraction > 0.0) return ContactState::gapping;
  if (in.limit_share > 0.0) return ContactState::gross_slip;
  if (in.law_sticks_below_limit || in.limit_ratio < options.stuck_ratio) return ContactState::stuck;
  return ContactState::microslip;
}

int ContactStateCounts::total() const { return std::accumulate(count.begin(), count.end(), 0); }

LimitMeasures limit_measures(std::span<const double> traction_magnitude, std::span<const double> limit,
                             double limit_tolerance) {
  if (traction_magnitude.size() != limit.size()) {
    throw std::invalid_argument(fmt::format("limit_measures: {} traction magnitudes but {} limits",
                                            traction_magnitude.size(), limit.size()));
  }
  LimitMeasures m;
  if (limit.empty()) return m;
  std::size_t at_limit = 0;
  for (std::size_t i = 0; i < limit.size(); ++i) {
    if (!(limit[i] > 0.0)) continue;  // open (or frictionless): no limit to be at
    const double r = traction_magnitude[i] / limit[i];
    m.ratio = std::max(m.ratio, r);
    at_limit += r >= 1.0 - limit_tolerance ? 1 : 0;
  }
  m.share = static_cast<double>(at_limit) / static_cast<double>(limit.size());
  return m;
}

}  // namespace jointhb::hb
