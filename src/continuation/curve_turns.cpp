// The turns in amplitude of a damping curve (curve_turns.hpp).
#include "curve_turns.hpp"

#include <cmath>

#include "curve_refinement.hpp"

namespace jointhb::continuation::detail {
namespace {

// log10 q of a turn to 1e-8 of its value (|λ| ~ 1: q to ~2e-8 relative) in at most 40 corrected
// points: the ten turns of the 30-DOF chain of issue 18 took 9–40 points each at 1e-10, 7–40 at
// 1e-8 (docs/stability.md §7 for the time).
constexpr RefinementOptions kTurnRefinement{1e-8, 40};

}  // namespace

std::vector<BackboneTurn> locate_turns(const ResidualFunction& residual, const Options& scaling, const Result& r,
                                       const std::string& why_unrefined) {
  std::vector<BackboneTurn> turns;
  for (std::size_t k = 1; k < r.points.size(); ++k) {
    const Point& b = r.points[k];
    if (!b.fold) continue;
    const Point& a = r.points[k - 1];
    CurveExtremum e;
    if (residual) e = refine_extremum(residual, scaling, a, b, parameter_quantity(), kTurnRefinement);
    else e.message = why_unrefined;
    BackboneTurn t;
    t.refined = e.ok;
    t.message = e.message;
    t.points = e.points;
    t.after_point = static_cast<int>(k);  // in r.points; placed on the curve by place_turns
    t.log10_amplitude = e.ok ? e.lambda : b.lambda;
    t.unknowns = e.ok ? e.x : b.x;
    t.log10_amplitude_bound = e.ok ? e.value_bound : std::abs(b.lambda - a.lambda);
    const Eigen::Index n = t.unknowns.size();
    t.omega = t.unknowns[n - 2];
    t.damping_ratio = t.unknowns[n - 1] / (2.0 * t.omega);
    turns.push_back(std::move(t));
  }
  return turns;
}

}  // namespace jointhb::continuation::detail
