// Trial-direction generalisation of a 1D tangential law to the tangential plane
// (tangential_law.hpp; docs/theory.md §3):
//   e = (t_0 + k Δg)/|t_0 + k Δg|,  f_1 = law1d(e·t_0, e·Δg),  t_1 = f_1 e.
// The component of t_0 normal to e equals -k times that of Δg, so it unloads elastically to zero
// within the step: t_1 is exactly collinear with e and |t_1| ≤ limit holds by the 1D law.
#include <cmath>
#include <limits>

#include "jointhb/contact/tangential_law.hpp"

namespace jointhb::contact {

TangentialStep TangentialLaw::step(const Vec2& t0, const Vec2& slip, const TangentialLimits& limits,
                                   bool dissipation) const {
  TangentialStep r;
  const double fs = limits.slip_limit;
  const double k = limits.stiffness;
  if (!(fs > 0.0) || !(k > 0.0)) {  // open contact (gapping): no tangential traction or stiffness
    r.traction.setZero();
    r.d_traction.setZero();
    r.elastic = false;
    return r;
  }

  // If the limit fell below |t_0| (the normal pressure dropped), t_0 slips radially onto it.
  Vec2 start = t0;
  Mat2 d_start = Mat2::Identity();    // ∂start/∂t_0
  Vec2 d_start_limit = Vec2::Zero();  // ∂start/∂limit
  double clamp_dissipation = 0.0;
  const double norm0 = t0.norm();
  if (norm0 > fs) {
    const Vec2 dir = t0 / norm0;
    start = fs * dir;
    d_start = (fs / norm0) * (Mat2::Identity() - dir * dir.transpose());
    d_start_limit = dir;
    clamp_dissipation = (norm0 * norm0 - fs * fs) / (2.0 * k);
  }

  const Vec2 trial = start + k * slip;
  const double q = trial.norm();
  if (q <= std::numeric_limits<double>::min() * 1.0e4 * fs) {
    // The trial vanishes: the increment unloads the traction exactly to zero (elastic).
    r.traction = trial;
    r.d_traction = d_start;
    r.d_slip = k * Mat2::Identity();
    r.d_limit = d_start_limit;
    r.d_stiffness = slip;
    r.dissipation = clamp_dissipation;
    r.elastic = clamp_dissipation == 0.0;
    return r;
  }
  const Vec2 e = trial / q;
  const ScalarStep s = scalar_step(e.dot(start), e.dot(slip), limits, dissipation);
  r.traction = s.force * e;

  // Derivatives: with P = (I - e eᵀ)/q and d(trial) = d start + k dΔg + Δg dk,
  //   df_1 = a eᵀd start + b eᵀdΔg + wᵀ d(trial) + c dL + d dk,  w = P (a start + b Δg),
  //   dt_1 = e df_1 + f_1 P d(trial).
  const Mat2 P = (Mat2::Identity() - e * e.transpose()) / q;
  const Vec2 w = P * (s.d_force * start + s.d_slip * slip);
  const Mat2 d_by_start = e * (s.d_force * e + w).transpose() + s.force * P;
  r.d_traction = d_by_start * d_start;
  r.d_slip = e * (s.d_slip * e + k * w).transpose() + (k * s.force) * P;
  r.d_stiffness = e * (w.dot(slip) + s.d_stiffness) + s.force * (P * slip);
  r.d_limit = e * s.d_limit + d_by_start * d_start_limit;
  r.dissipation = s.dissipation + clamp_dissipation;
  r.loading_slip = s.loading_slip;
  r.elastic = s.loading_slip == 0.0 && clamp_dissipation == 0.0;
  return r;
}

}  // namespace jointhb::contact
