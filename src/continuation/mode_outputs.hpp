#pragma once
// The outputs of an EPMC point that Options::max_output_change limits along a damping curve
// (discrete, backbone.cpp, and finite-element, interface_response.cpp): Ω and ζ = ξ/(2Ω) from the
// last two unknowns (…, Ω, ξ).

#include <Eigen/Core>

namespace jointhb::continuation {

inline Eigen::VectorXd mode_outputs(const Eigen::VectorXd& y, double /*lambda*/) {
  const Eigen::Index n = y.size();
  Eigen::VectorXd o(2);
  o << y[n - 2], y[n - 1] / (2.0 * y[n - 2]);
  return o;
}

}  // namespace jointhb::continuation
