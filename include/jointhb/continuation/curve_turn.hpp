#pragma once
// A turn of a damping curve in amplitude, shared by discrete (backbone.hpp) and finite-element
// (interface_response.hpp) damping curves.

#include <Eigen/Core>
#include <string>

namespace jointhb::continuation {

/// A turn of the curve in amplitude (an extremum of λ = log10 q between two accepted points, e.g.
/// at an internal resonance), located by continuation/curve_refinement.hpp (docs/stability.md §7).
struct BackboneTurn {
  double log10_amplitude = 0.0;  ///< λ* at the turn
  double omega = 0.0;            ///< Ω there [rad/s]
  double damping_ratio = 0.0;    ///< ζ there
  /// Bound on |λ* − log10_amplitude| (refined), else |Δλ| between the two accepted points
  double log10_amplitude_bound = 0.0;
  bool refined = false;          ///< false: reported at the accepted point after the turn
  std::string message;           ///< why it is not refined
  int points = 0;                ///< points corrected to locate it
  /// Index in the curve's points of the first point after the turn (the turn lies between it and
  /// the point before); −1 where not known
  int after_point = -1;
  /// The curve's unknowns at the turn (X̂, Ω, ξ discrete; ŷ, Ω, ξ finite-element), in the basis
  /// of the points' unknowns
  Eigen::VectorXd unknowns;
};

}  // namespace jointhb::continuation
