#pragma once
// Extrema along a traced branch between two accepted points (internal to the continuation layer;
// docs/stability.md §3): the fold of a curve (the extremum of λ, where the tangent's λ component
// vanishes) and the resonance peak of an FRF (the extremum of the response amplitude).
//
// Between accepted points a and b (scaled unknowns y = (x ./ x_scale, λ / λ_scale), see
// pseudo_arclength.hpp) the branch is parametrised by its projection on the chord,
// σ = d·(y − y_a), d = (y_b − y_a)/‖y_b − y_a‖, which stays monotone across a fold where λ does
// not. Points at a given σ are found by Newton's method on the bordered system
//   [ R_x D_x    R_λ λ_scale ] Δy = − [ R                ]
//   [ dᵀ (x)     d (λ)       ]        [ d·(y − y_a) − σ  ]
// and the branch's tangent there from the same matrix (right-hand side (0, 1)). The derivative of
// the quantity q along σ, q'(σ) = (∇q · dy/dσ), dy/dσ = τ / (τ·d), changes sign between a and b;
// its zero is bracketed by the Illinois variant of regula falsi (superlinear, never leaves the
// bracket, tolerant of the kinks of stick/slip). With q' monotone on the final bracket [σ₀, σ₁]
// the extremum q* obeys |q* − q(σ_c)| ≤ (σ₁ − σ₀) max(|q'(σ₀)|, |q'(σ₁)|): the error bound
// reported with the refined value.

#include <Eigen/Core>
#include <functional>
#include <string>

#include "jointhb/continuation/pseudo_arclength.hpp"

namespace jointhb::continuation::detail {

/// A smooth scalar function of a point of the branch and its gradient, or its slope along a
/// direction where the gradient is not at hand.
struct CurveQuantity {
  std::function<double(const Eigen::VectorXd& x, double lambda)> value;
  /// (∂q/∂x, ∂q/∂λ) at (x, λ), unscaled; ∂q/∂x empty means zero
  std::function<std::pair<Eigen::VectorXd, double>(const Eigen::VectorXd& x, double lambda)>
      gradient;
  /// ∂q/∂x·dx + ∂q/∂λ dλ at (x, λ) (unscaled; used instead of `gradient` when set), e.g. by central
  /// differences of `value`
  std::function<double(const Eigen::VectorXd& x, double lambda, const Eigen::VectorXd& dx, double dlambda)>
      slope;
};

/// q = λ: its extremum along the branch is a fold.
CurveQuantity parameter_quantity();

struct CurveExtremum {
  bool ok = false;
  std::string message;        ///< why not, when !ok
  Eigen::VectorXd x;          ///< the refined point
  double lambda = 0.0;
  double value = 0.0;         ///< q at the refined point
  double value_bound = 0.0;   ///< |q* − value| ≤ value_bound (monotone q' on the final bracket)
  double lambda_bracket = 0.0;  ///< |λ(σ₁) − λ(σ₀)| of the final bracket
  int corrector_iterations = 0;
  int points = 0;             ///< points corrected on the way
};

struct RefinementOptions {
  double relative_tolerance = 1e-10;  ///< stop when value_bound ≤ tol · |q|
  int max_points = 40;
};

/// The extremum of q between accepted points a and b, whose tangents give q' of opposite signs.
/// `scaling` supplies state_scale, parameter_scale, residual_scale, residual_tolerance,
/// step_tolerance and max_corrector_iterations. The bordered systems are solved by LU where the
/// residual returns a dense Jacobian, else matrix-free (Evaluation::d_state_product) by GMRES to
/// krylov_tolerance (at most krylov_max_iterations per cycle, four restarts) preconditioned with the
/// block elimination of the evaluation's approximate inverse (make_preconditioner).
CurveExtremum refine_extremum(const ResidualFunction& residual, const Options& scaling,
                              const Point& a, const Point& b, const CurveQuantity& q,
                              const RefinementOptions& options = {});

}  // namespace jointhb::continuation::detail
