#pragma once
// The folds and the resonance peak of an FRF run located between its accepted points (internal to
// the continuation layer; docs/stability.md §3), for discrete and finite-element FRFs alike: every
// turn of Ω that is not a reversal is refined to the extremum of Ω along the branch, and the
// largest |fundamental| of the output, when it is not at an end of the run, to the extremum of
// that amplitude (curve_refinement.hpp). An extremum that cannot be refined is reported at its
// accepted point, bounded by the Ω between the two points for a fold.

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "curve_refinement.hpp"
#include "jointhb/continuation/frf.hpp"

namespace jointhb::continuation::detail {

/// An accepted point of one continuation run as the location of its extrema needs it.
struct FrfRunPoint {
  const Eigen::VectorXd* unknowns = nullptr;  ///< x (the run's basis)
  const Eigen::VectorXd* tangent = nullptr;   ///< its unit tangent (scaled, pseudo_arclength.hpp)
  double omega = 0.0;
  double amplitude_h1 = 0.0;
  bool fold = false;  ///< Ω turned between the previous point and this one
  hb::Bifurcation bifurcation = hb::Bifurcation::none;
};

struct FrfExtrema {
  std::vector<FrfExtremum> folds;
  std::optional<FrfExtremum> peak;  ///< at the run's largest amplitude_h1 (none without points)
};

/// The extrema of one run traced with `scaling` (its scales and tolerances) on `residual` (dense
/// or matrix-free Jacobian, refine_extremum), `amplitude` the output's |fundamental| as a CurveQuantity
/// (without a value, e.g. a basis without the fundamental: no peak). `peak` false: the folds only
/// (a run that does not hold the curve's highest point).
FrfExtrema locate_frf_extrema(const ResidualFunction& residual, const Options& scaling,
                              const std::vector<FrfRunPoint>& points, const CurveQuantity& amplitude, bool peak);

/// The run points of the curve's points `kept` (indices) with their `tangents`; `unknowns` the
/// point type's member holding x.
template <class PointT>
std::vector<FrfRunPoint> run_points(const std::vector<PointT>& points, const std::vector<std::size_t>& kept,
                                    const std::vector<Eigen::VectorXd>& tangents,
                                    Eigen::VectorXd PointT::*unknowns) {
  std::vector<FrfRunPoint> run(std::min(kept.size(), tangents.size()));
  for (std::size_t k = 0; k < run.size(); ++k) {
    const PointT& p = points[kept[k]];
    run[k] = {&(p.*unknowns), &tangents[k], p.omega, p.amplitude_h1, p.fold, p.bifurcation};
  }
  return run;
}

/// The folds and the peak of a curve traced in segments (segmented_curve.hpp), each located within
/// its segment: `locate(segment, peak)` returns the FrfExtrema of the segment's kept points
/// (`kept()`: their indices in curve.points), with the peak only where `peak` (the segment holds the
/// curve's largest amplitude_h1). The curve's peak is that point, as its segment located it; one at
/// a segment's end that is not the curve's end is reported at its accepted point.
template <class Curve, class Segment, class Locate>
void locate_in_segments(const std::vector<std::unique_ptr<Segment>>& segments, Curve& curve, const Locate& locate) {
  std::size_t top = 0;
  for (std::size_t k = 1; k < curve.points.size(); ++k)
    if (curve.points[k].amplitude_h1 > curve.points[top].amplitude_h1) top = k;
  for (const auto& segment : segments) {
    const std::vector<std::size_t>& kept = segment->kept();
    if (kept.empty()) continue;
    const bool holds_top = std::find(kept.begin(), kept.end(), top) != kept.end();
    FrfExtrema part = locate(*segment, holds_top);
    for (auto& fold : part.folds) curve.folds.push_back(std::move(fold));
    if (!holds_top || !part.peak) continue;
    curve.peak = std::move(part.peak);
    if (!curve.peak->refined && top != 0 && top + 1 != curve.points.size() && (kept.front() == top || kept.back() == top))
      curve.peak->message = "the largest amplitude is where the curve changes its harmonics (accuracy)";
  }
}

}  // namespace jointhb::continuation::detail
