#pragma once
// The linear limits of a discrete friction system near a frequency (internal to continuation/):
// used by the FRF and damping-curve drivers to name the physical situation where a curve stops.
#include <optional>
#include <vector>

#include "jointhb/hb/discrete_system.hpp"

namespace jointhb::continuation::detail {

/// A natural frequency of one of the two linear limits near k Ω.
struct NearResonance {
  bool stuck = true;     ///< of the stuck system (k_T0 springs), else of the contact-free one
  int mode = 0;          ///< 1-based, ascending frequency
  int harmonic = 1;      ///< k
  double omega = 0.0;    ///< ω_j [rad/s]
  double zeta = 0.0;     ///< φ_jᵀ C φ_j / (2 ω_j), φ_j mass-normalised
  double distance = 0.0; ///< |k Ω − ω_j| / ω_j
};

/// The natural frequency ω_j of the stuck or the contact-free linear system nearest (relatively)
/// to k Ω for k in `harmonics`, among those within `max_distance` whose modal damping ratio is
/// below `max_zeta`; empty when none (or the modes cannot be computed).
std::optional<NearResonance> nearest_resonance(const hb::DiscreteSystem& system, double omega,
                                               const std::vector<int>& harmonics, double max_distance,
                                               double max_zeta);

}  // namespace jointhb::continuation::detail
