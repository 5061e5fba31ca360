#pragma once
// The interface shared by the tangential (friction) laws of jointhb.
//
// A tangential law maps an increment of the tangential relative displacement (slip) g_T of one
// contact point to the new tangential traction t_T. Its only state is t_T itself. The laws are
// rate-independent; each is integrated *exactly* over a straight increment in 1D (scalar_step), so
// that sampled paths give exact tractions at the samples.
//
// Two tangential directions (docs/theory.md, "2D generalisation"): the new traction is collinear
// with the elastic trial t_T + k Δg_T, and its signed magnitude along that direction follows the
// exact 1D law driven by the projections of t_T and Δg_T on it:
//   e = (t_0 + k Δg)/|t_0 + k Δg|,  f_1 = law1d(e·t_0, e·Δg),  t_1 = f_1 e.
// For Jenkins this is the classical radial return; for any law it reduces exactly to the 1D law on
// a straight path and, as the increments shrink, to the rate form
//   ṫ = k ġ - k (1 - ψ(|t|)) (t̂·ġ)₊ t̂,
// where ψ is the law's loading factor (ψ = (1 - |t|/μp_N)^n for Gaul–Mayer, eq. 10).

#include <Eigen/Core>
#include <string_view>

namespace jointhb::contact {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;

/// Parameters of a tangential law that follow the normal contact state, at the end of an increment.
struct TangentialLimits {
  double slip_limit = 0.0;  ///< μ p_N [Pa] or μ F_N [N], ≥ 0: the Coulomb bound on |t_T|
  double stiffness = 0.0;   ///< k_T0 [Pa/m] or [N/m], > 0: the initial (sticking) stiffness
};

/// One exact 1D increment, with the derivatives of the new force.
struct ScalarStep {
  double force = 0.0;         ///< f_1: tangential force (traction) after the increment
  double d_force = 0.0;       ///< ∂f_1/∂f_0
  double d_slip = 0.0;        ///< ∂f_1/∂Δg
  double d_limit = 0.0;       ///< ∂f_1/∂(slip limit)
  double d_stiffness = 0.0;   ///< ∂f_1/∂k
  double dissipation = 0.0;   ///< energy dissipated in the increment, ≥ 0 (J or J/m²)
  double loading_slip = 0.0;  ///< |Δg| travelled on the non-elastic (loading or sliding) branch
};

/// One increment in the tangential plane, with the derivatives of the new traction.
struct TangentialStep {
  Vec2 traction = Vec2::Zero();        ///< t_1
  Mat2 d_traction = Mat2::Identity();  ///< ∂t_1/∂t_0
  Mat2 d_slip = Mat2::Zero();          ///< ∂t_1/∂Δg
  Vec2 d_limit = Vec2::Zero();         ///< ∂t_1/∂(slip limit at the end)
  Vec2 d_stiffness = Vec2::Zero();     ///< ∂t_1/∂(stiffness at the end)
  double dissipation = 0.0;            ///< ≥ 0
  double loading_slip = 0.0;           ///< slip travelled on the non-elastic branch
  bool elastic = true;                 ///< true when the whole increment was elastic
};

class TangentialLaw {
 public:
  virtual ~TangentialLaw() = default;

  /// Exact 1D increment from force f0 (|f0| ≤ limit) over the slip increment `slip`,
  /// with the limit and stiffness held at their end-of-increment values. With
  /// `dissipation = false` the energy is not evaluated (reported 0): Newton iterations that need
  /// only forces and derivatives skip its cost (~40 % of a Gaul–Mayer loading step).
  [[nodiscard]] ScalarStep scalar_step(double f0, double slip, const TangentialLimits& limits,
                                       bool dissipation = true) const {
    return evaluate(f0, slip, limits, dissipation);
  }
  [[nodiscard]] virtual std::string_view name() const = 0;
  /// True when the law is exactly linear (f = f0 + k Δg) as long as |f| stays below the slip
  /// limit (Jenkins). Lets harmonic balance treat a contact that sticks throughout as a spring.
  /// Gaul–Mayer has no such range: any loading slip is already on the nonlinear branch.
  [[nodiscard]] virtual bool sticks_below_limit() const { return false; }

  /// Increment in the tangential plane (trial-direction generalisation, see above). If |t0| exceeds
  /// the new slip limit (the normal pressure fell), t0 first slips radially onto the limit.
  /// A limit of zero (gapping) returns a zero traction with zero derivatives.
  [[nodiscard]] TangentialStep step(const Vec2& t0, const Vec2& slip,
                                    const TangentialLimits& limits, bool dissipation = true) const;

 protected:
  /// The law itself: what scalar_step returns.
  [[nodiscard]] virtual ScalarStep evaluate(double f0, double slip, const TangentialLimits& limits,
                                            bool dissipation) const = 0;
};

}  // namespace jointhb::contact
