#pragma once
// The turns in amplitude of a damping curve (internal to the continuation layer; docs/stability.md
// §7), for discrete and finite-element curves alike: every pair of accepted points of a run between
// which the tangent's λ component changed sign (Point::fold) is refined to the extremum of λ along
// the branch (curve_refinement.hpp, q = λ); a turn that cannot be refined is reported at the point
// after it, bounded by the λ between the two.

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "jointhb/continuation/curve_turn.hpp"
#include "jointhb/continuation/pseudo_arclength.hpp"

namespace jointhb::continuation::detail {

/// The turns of run `r` traced with `scaling` (its scales and tolerances), whose unknowns end with
/// (Ω, ξ) as those of both EPMC residuals do (ζ = ξ / 2Ω, hb/nonlinear_mode.hpp,
/// hb/interface_mode.hpp). `residual` returns the dense Jacobian (the refinement's bordered LU);
/// empty `residual`: no refinement, every turn is reported unrefined with `why_unrefined` as its
/// message. Each turn's after_point indexes r.points.
std::vector<BackboneTurn> locate_turns(const ResidualFunction& residual, const Options& scaling, const Result& r,
                                       const std::string& why_unrefined = {});

/// The turns of run `r` (after_point indexing r.points) placed on the curve's kept `points`:
/// after_point becomes the index of the kept point with the same unknowns (`unknowns(point)`), or
/// −1 where the run's point was not kept (a point dropped for a finer level).
template <class PointT, class Unknowns>
std::vector<BackboneTurn> place_turns(std::vector<BackboneTurn> turns, const Result& r,
                                      const std::vector<PointT>& points, const Unknowns& unknowns) {
  for (BackboneTurn& t : turns) {
    const auto k = static_cast<std::size_t>(t.after_point);
    t.after_point = -1;
    if (k >= r.points.size()) continue;
    for (std::size_t i = points.size(); i-- > 0;) {
      if (unknowns(points[i]).size() == r.points[k].x.size() && unknowns(points[i]) == r.points[k].x) {
        t.after_point = static_cast<int>(i);
        break;
      }
    }
  }
  return turns;
}

}  // namespace jointhb::continuation::detail
