#pragma once
// What the finite-element damping curves and FRFs share (interface_backbone.cpp,
// interface_response.cpp): the arclength scale of the interface unknowns and the timing record.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/hb/interface_balance.hpp"

namespace jointhb::continuation::interface_detail {

// The arclength counts the interface gaps as if there were at most this many contact points:
// their share of ‖Δy‖ grows like √P (every point's gaps change with the amplitude), so without
// this a fine interface would take steps √(P / 100) times shorter in amplitude or frequency for
// the same accuracy of the predictor (1600 points: 43 instead of ~15 points per damping curve).
// Curves of up to 100 points are unchanged.
constexpr double kArclengthPoints = 100.0;

// unknown_scale() with the gap unknowns weighted for kArclengthPoints (above).
inline Eigen::VectorXd arclength_scale(const hb::InterfaceBalance& balance) {
  Eigen::VectorXd s = balance.unknown_scale();
  const double factor = std::sqrt(std::max(1.0, balance.points() / kArclengthPoints));
  const Eigen::Index gaps = static_cast<Eigen::Index>(3) * balance.points() * balance.basis().size();
  s.tail(gaps) *= factor;
  return s;
}

// Adds one continuation run's record (its balance's timings t, its result r) to c; total is
// the caller's.
inline void add_curve_timings(InterfaceTimings& c, const hb::InterfaceBalanceTimings& t, const Result& r) {
  c.aft += t.aft;
  c.assembly += t.assembly;
  c.linear_solve += r.linear_solve_seconds;
  c.evaluations += t.evaluations;
  c.jacobians += t.jacobians;
  c.factorisations += r.factorisations;
  c.krylov_iterations += r.krylov_iterations;
  c.products += t.products;
  c.preconditioner += t.preconditioner;
  c.preconditioner_apply += t.preconditioner_apply;
  c.product_calls += t.product_calls;
  c.preconditioner_calls += t.preconditioner_calls;
}

}  // namespace jointhb::continuation::interface_detail
