// The linear limits of a discrete friction system near a frequency (linear_limits.hpp).
#include "linear_limits.hpp"

#include <cmath>
#include <exception>

namespace jointhb::continuation::detail {

std::optional<NearResonance> nearest_resonance(const hb::DiscreteSystem& system, double omega,
                                               const std::vector<int>& harmonics, double max_distance,
                                               double max_zeta) {
  const Eigen::MatrixXd c = system.damping.size() > 0 ? Eigen::MatrixXd(system.damping)
                                                       : Eigen::MatrixXd::Zero(system.dofs(), system.dofs());
  std::optional<NearResonance> best;
  for (const bool stuck : {true, false}) {
    if (!stuck && system.contacts.empty()) continue;
    hb::LinearModes modes;
    try {
      modes = hb::linear_modes(system, stuck);
    } catch (const std::exception&) {
      continue;
    }
    for (Eigen::Index j = 0; j < modes.omega.size(); ++j) {
      const double w = modes.omega[j];
      if (!(w > 0.0)) continue;
      const Eigen::VectorXd phi = modes.shapes.col(j);
      const double zeta = phi.dot(c * phi) / (2.0 * w);
      if (!(zeta < max_zeta)) continue;
      for (const int k : harmonics) {
        const double distance = std::abs(k * omega - w) / w;
        if (distance <= max_distance && (!best || distance < best->distance))
          best = NearResonance{stuck, static_cast<int>(j) + 1, k, w, zeta, distance};
      }
    }
  }
  return best;
}

}  // namespace jointhb::continuation::detail
