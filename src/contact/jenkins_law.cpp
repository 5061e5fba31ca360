// Jenkins element: elastic predictor, Coulomb return (exact for a straight increment).
#include "jointhb/contact/jenkins_law.hpp"

#include <cmath>

namespace jointhb::contact {

ScalarStep JenkinsLaw::evaluate(double f0, double slip, const TangentialLimits& limits,
                                bool /*dissipation*/) const {
  const double fs = limits.slip_limit;
  const double k = limits.stiffness;
  ScalarStep r;
  if (fs <= 0.0) return r;  // open contact: no tangential force
  const double trial = f0 + k * slip;
  if (std::abs(trial) <= fs) {
    r.force = trial;
    r.d_force = 1.0;
    r.d_slip = k;
    r.d_stiffness = slip;
    return r;
  }
  const double s = trial > 0.0 ? 1.0 : -1.0;
  r.force = s * fs;
  r.d_limit = s;
  r.loading_slip = (std::abs(trial) - fs) / k;  // slip of the Coulomb slider
  r.dissipation = fs * r.loading_slip;
  return r;
}

}  // namespace jointhb::contact
