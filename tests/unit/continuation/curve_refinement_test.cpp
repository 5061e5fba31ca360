// The refinement of an extremum between two accepted points (continuation/curve_refinement.hpp)
// on the branch λ = f(x) of R(x, λ) = λ − f(x), whose turns are known in closed form.
#include "../../../src/continuation/curve_refinement.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace jointhb::continuation::detail {
namespace {

// λ = x + w sin x: turns where 1 + w cos x = 0.
struct Wiggle {
  double w;
  [[nodiscard]] double f(double x) const { return x + w * std::sin(x); }
  [[nodiscard]] double df(double x) const { return 1.0 + w * std::cos(x); }
  [[nodiscard]] ResidualFunction residual() const {
    return [*this](const Eigen::VectorXd& x, double lambda, bool) {
      Evaluation e;
      e.residual = Eigen::VectorXd::Constant(1, lambda - f(x[0]));
      e.d_state = Eigen::MatrixXd::Constant(1, 1, -df(x[0]));
      e.d_parameter = Eigen::VectorXd::Ones(1);
      return e;
    };
  }
  // The accepted point at x, its unit tangent oriented along increasing x.
  [[nodiscard]] Point point(double x) const {
    Point p;
    p.x = Eigen::VectorXd::Constant(1, x);
    p.lambda = f(x);
    p.tangent = Eigen::Vector2d(1.0, df(x)).normalized();
    return p;
  }
};

TEST(CurveRefinement, LocatesTheOneTurnBetweenTwoPoints) {
  // One turn between x = 2.0 and 3.0 (w = 1.2: cos x* = −1/1.2, x* = 2.5559): λ* = f(x*) to the bound.
  const Wiggle g{1.2};
  const double x_star = std::acos(-1.0 / 1.2);
  const CurveExtremum e = refine_extremum(g.residual(), Options{}, g.point(2.0), g.point(3.0), parameter_quantity());
  ASSERT_TRUE(e.ok) << e.message;
  EXPECT_NEAR(e.lambda, g.f(x_star), std::max(e.value_bound, 1e-12));
  EXPECT_LT(e.value_bound, 1e-8);
}

TEST(CurveRefinement, AStationaryPointBetweenTheEndValuesIsNotReportedAsTheirExtremum) {
  // w = 1.5: turns where cos x = −2/3 (x = 2.3005 + 2πk, max; 3.9827 + 2πk, min). Between x = 5.0
  // (λ 3.5616, rising) and x = 15.25 (λ 15.913, falling) λ turns five times; the bracketing
  // converges (measured without the check) to the maximum at x = 8.5837, λ = 9.7017, strictly
  // between the end values: a turn, but not the extremum between the two points (which lies beyond
  // both, at x = 14.867, λ = 15.985). Refused, with the reason.
  const Wiggle g{1.5};
  const double xa = 5.0, xb = 15.25;
  ASSERT_GT(g.df(xa), 0.0);
  ASSERT_LT(g.df(xb), 0.0);
  const CurveExtremum e = refine_extremum(g.residual(), Options{}, g.point(xa), g.point(xb), parameter_quantity());
  EXPECT_FALSE(e.ok) << e.lambda;
  EXPECT_NE(e.message.find("not their extremum"), std::string::npos) << e.message;
  EXPECT_NEAR(e.lambda, 9.7017, 1e-4);  // the stationary point it found, still reported
}

}  // namespace
}  // namespace jointhb::continuation::detail
