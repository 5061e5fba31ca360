// The pieces of a curve completed from both ends (continuation/curve_from_both_ends.hpp) on curves
// whose geometry is known: where two runs meet, the joined order of points and turns, and the
// check that one branch joins the meeting points.
#include "../../../src/continuation/curve_from_both_ends.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace jointhb::continuation::detail {
namespace {

struct P {
  Eigen::VectorXd x;
  double lambda = 0.0;
  double step = 0.0;
};

const auto unknowns = [](const P& p) -> const Eigen::VectorXd& { return p.x; };
const auto lambda_of = [](const P& p) { return p.lambda; };
const auto step_of = [](const P& p) { return p.step; };

P point(double x, double lambda, double step) { return P{Eigen::VectorXd::Constant(1, x), lambda, step}; }

CurveMetric unit_metric() { return CurveMetric{Eigen::VectorXd::Ones(1), 1.0}; }

// R(x, λ) = (x² + λ² − 1)(x² + λ² − r²): two concentric circles, radii 1 and r.
ResidualFunction two_circles(double r) {
  return [r](const Eigen::VectorXd& x, double l, bool jacobian) {
    const double a = x[0] * x[0] + l * l - 1.0, b = x[0] * x[0] + l * l - r * r;
    Evaluation e;
    e.residual = Eigen::VectorXd::Constant(1, a * b);
    if (jacobian) {
      e.d_state = Eigen::MatrixXd::Constant(1, 1, 2.0 * x[0] * (a + b));
      e.d_parameter = Eigen::VectorXd::Constant(1, 2.0 * l * (a + b));
    }
    return e;
  };
}

TEST(CurveFromBothEnds, MeetsWithinOneStepOfTheNearestPoint) {
  // The first run along λ = 0 … 1 at x = 0 in steps of 0.1; a point of the second run 0.05 away
  // from its point 5 meets it (steps 0.1), one 0.15 away does not, nor one within 0.05 whose own
  // step was 0.01.
  std::vector<P> first;
  for (int i = 0; i <= 10; ++i) first.push_back(point(0.0, 0.1 * i, i == 0 ? 0.0 : 0.1));
  const CurveMetric m = unit_metric();
  const auto meets = [&](const P& p) { return meeting_point(first, p, m, unknowns, lambda_of, step_of); };
  ASSERT_TRUE(meets(point(0.05, 0.5, 0.1)).has_value());
  EXPECT_EQ(*meets(point(0.05, 0.5, 0.1)), 5U);
  EXPECT_FALSE(meets(point(0.15, 0.5, 0.1)).has_value());
  EXPECT_FALSE(meets(point(0.04, 0.5, 0.01)).has_value());
  // Points of another level (another size) never meet.
  P other{Eigen::VectorXd::Zero(2), 0.5, 0.1};
  EXPECT_FALSE(meets(other).has_value());
}

TEST(CurveFromBothEnds, JoinsInTheCurvesOrderWithTurnsAndSteps) {
  // First run λ = 0, 1, 2, 3 (stopped after looping to 3); second run from λ = 9 down: 9, 8, 7, 6,
  // 5, 4, 2.1 meeting the first at its point 2 (λ = 2). Joined: 0 1 2 | 2.1 4 5 6 7 8 9.
  std::vector<P> first = {point(0, 0, 0), point(0, 1, 1), point(0, 2, 1), point(0, 3, 1)};
  std::vector<P> second = {point(0, 9, 0), point(0, 8, 1), point(0, 7, 1), point(0, 6, 1),
                           point(0, 5, 1), point(0, 4, 1), point(0, 2.1, 1.9)};
  BackboneTurn t1, t_dropped, t2;
  t1.after_point = 2;         // between first[1] and first[2]: kept at 2
  t_dropped.after_point = 3;  // between first[2] and first[3]: beyond the meeting, dropped
  t2.after_point = 2;         // between second[1] (8) and second[2] (7): joined before 8
  t1.log10_amplitude = 1.5;
  t2.log10_amplitude = 7.5;
  std::vector<BackboneTurn> turns = {t1, t_dropped};
  join_from_both_ends(first, turns, 2, second, {t2}, 6, 0.1);
  std::vector<double> lambdas;
  for (const P& p : first) lambdas.push_back(p.lambda);
  EXPECT_EQ(lambdas, (std::vector<double>{0, 1, 2, 2.1, 4, 5, 6, 7, 8, 9}));
  // Each joined step is the arclength from the point before it in the joined order.
  EXPECT_DOUBLE_EQ(first[3].step, 0.1);  // the joint
  EXPECT_DOUBLE_EQ(first[4].step, 1.9);  // 2.1 → 4 was second[6]'s step
  EXPECT_DOUBLE_EQ(first[9].step, 1.0);
  ASSERT_EQ(turns.size(), 2U);
  EXPECT_EQ(turns[0].after_point, 2);
  EXPECT_DOUBLE_EQ(turns[1].log10_amplitude, 7.5);
  EXPECT_DOUBLE_EQ(first[turns[1].after_point].lambda, 8.0);
  EXPECT_DOUBLE_EQ(first[turns[1].after_point - 1].lambda, 7.0);
}

TEST(CurveFromBothEnds, OneBranchJoinsPointsOfOneCircleNotOfTwo) {
  // Two points 0.02 apart on the unit circle: the circle crosses the plane between them.
  const ResidualFunction r = two_circles(1.05);
  const CurveMetric m = unit_metric();
  const double a = 0.3, b = 0.32;
  EXPECT_TRUE(branch_between(r, m, Eigen::VectorXd::Constant(1, std::cos(a)), std::sin(a),
                             Eigen::VectorXd::Constant(1, std::cos(b)), std::sin(b), 1e-12));
  // One point on each circle, 0.02 apart along the radius: the plane between them, normal to the
  // radius, meets neither circle near the midpoint.
  const ResidualFunction close = two_circles(1.02);
  EXPECT_FALSE(branch_between(close, m, Eigen::VectorXd::Constant(1, std::cos(a)), std::sin(a),
                              Eigen::VectorXd::Constant(1, 1.02 * std::cos(a)), 1.02 * std::sin(a), 1e-12));
  // A residual that cannot be evaluated there (a law refusing an iterate) joins nothing.
  const ResidualFunction throws = [](const Eigen::VectorXd&, double, bool) -> Evaluation {
    throw std::invalid_argument("periodic path: a negative slip");
  };
  EXPECT_FALSE(branch_between(throws, m, Eigen::VectorXd::Constant(1, std::cos(a)), std::sin(a),
                              Eigen::VectorXd::Constant(1, std::cos(b)), std::sin(b), 1e-12));
}

}  // namespace
}  // namespace jointhb::continuation::detail
