// Folds and resonance peaks of FRF runs located between accepted points (frf_extrema.hpp).
#include "frf_extrema.hpp"

#include <cmath>
#include <cstddef>

namespace jointhb::continuation::detail {
namespace {

// An extremum as located (e.ok), else reported at the accepted point `at` with e's message.
FrfExtremum extremum_of(const CurveExtremum& e, const FrfRunPoint& at, const CurveQuantity& amplitude) {
  FrfExtremum f;
  f.refined = e.ok;
  f.message = e.message;
  f.points = e.points;
  if (!e.ok) {
    f.omega = at.omega;
    f.coefficients = *at.unknowns;
    f.amplitude_h1 = at.amplitude_h1;
    return f;
  }
  f.omega = e.lambda;
  f.coefficients = e.x;
  f.amplitude_h1 = amplitude.value ? amplitude.value(e.x, e.lambda) : 0.0;
  f.value_bound = e.value_bound;
  f.omega_bracket = e.lambda_bracket;
  return f;
}

Point branch_point(const FrfRunPoint& r) {
  Point p;
  p.x = *r.unknowns;
  p.lambda = r.omega;
  p.tangent = *r.tangent;
  return p;
}

}  // namespace

FrfExtrema locate_frf_extrema(const ResidualFunction& residual, const Options& scaling,
                              const std::vector<FrfRunPoint>& points, const CurveQuantity& amplitude, bool peak) {
  FrfExtrema out;
  for (std::size_t k = 1; k < points.size(); ++k) {
    const FrfRunPoint& p = points[k];
    if (!p.fold || p.bifurcation == hb::Bifurcation::reversal) continue;
    FrfExtremum f = extremum_of(refine_extremum(residual, scaling, branch_point(points[k - 1]), branch_point(p),
                                                parameter_quantity()),
                                p, amplitude);
    if (!f.refined) f.value_bound = std::abs(p.omega - points[k - 1].omega);
    f.bifurcation = p.bifurcation;
    out.folds.push_back(std::move(f));
  }
  if (!peak || points.empty() || !amplitude.value) return out;
  std::size_t top = 0;
  for (std::size_t k = 1; k < points.size(); ++k)
    if (points[k].amplitude_h1 > points[top].amplitude_h1) top = k;
  CurveExtremum located;
  located.message = "the largest amplitude is at an end of the curve";
  if (top > 0 && top + 1 < points.size()) {
    for (const std::size_t first : {top - 1, top}) {
      located = refine_extremum(residual, scaling, branch_point(points[first]), branch_point(points[first + 1]),
                                amplitude);
      if (located.ok) break;
    }
  }
  out.peak = extremum_of(located, points[top], amplitude);
  return out;
}

}  // namespace jointhb::continuation::detail
