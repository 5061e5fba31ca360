// Pseudo-arclength continuation (pseudo_arclength.hpp): branches with folds against their closed
// forms (S-curve, single-harmonic Duffing frequency response), a linear branch, failure handling
// (failed evaluations, NaN, no root at the start), the accept callback, the step rule, option
// validation, and the scaling of the unknowns.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "jointhb/continuation/pseudo_arclength.hpp"

namespace jcont = jointhb::continuation;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// R(x, λ) = x³ − 3x − λ, scaled in x by `x_unit` (x = x_unit · z): the branch λ = z³ − 3z has
// folds at (z, λ) = (−1, 2) and (1, −2).
jcont::ResidualFunction s_curve(double x_unit = 1.0) {
  return [x_unit](const VectorXd& x, double lambda, bool jacobian) {
    const double z = x(0) / x_unit;
    jcont::Evaluation e;
    e.residual = VectorXd::Constant(1, z * z * z - 3.0 * z - lambda);
    if (jacobian) {
      e.d_state = MatrixXd::Constant(1, 1, (3.0 * z * z - 3.0) / x_unit);
      e.d_parameter = VectorXd::Constant(1, -1.0);
    }
    return e;
  };
}

double s_curve_residual(double x, double lambda) { return x * x * x - 3.0 * x - lambda; }

// Duffing oscillator q̈ + 2ζq̇ + q + γq³ = F cos Ωt at one harmonic, q = a cos Ωt + b sin Ωt:
//   cos: (1 − Ω²) a + 2ζΩ b + (3/4) γ A² a − F = 0
//   sin: (1 − Ω²) b − 2ζΩ a + (3/4) γ A² b     = 0,      A² = a² + b²,   λ = Ω.
struct Duffing {
  double zeta = 0.05;
  double gamma = 1.0;
  double force = 0.1;

  jcont::ResidualFunction residual() const {
    return [d = *this](const VectorXd& x, double omega, bool jacobian) {
      const double a = x(0), b = x(1);
      const double a2 = a * a + b * b;
      const double k = 1.0 - omega * omega + 0.75 * d.gamma * a2;
      const double c = 2.0 * d.zeta * omega;
      jcont::Evaluation e;
      e.residual = VectorXd(2);
      e.residual << k * a + c * b - d.force, k * b - c * a;
      if (jacobian) {
        e.d_state = MatrixXd(2, 2);
        e.d_state << k + 1.5 * d.gamma * a * a, c + 1.5 * d.gamma * a * b,  //
            1.5 * d.gamma * a * b - c, k + 1.5 * d.gamma * b * b;
        e.d_parameter = VectorXd(2);
        e.d_parameter << -2.0 * omega * a + 2.0 * d.zeta * b, -2.0 * omega * b - 2.0 * d.zeta * a;
      }
      return e;
    };
  }

  // The linear response, as start guess.
  VectorXd linear(double omega) const {
    const double k = 1.0 - omega * omega, c = 2.0 * zeta * omega;
    return VectorXd{{force * k / (k * k + c * c), force * c / (k * k + c * c)}};
  }

  // Closed-form frequency-response relation g(A, Ω) = [(1 − Ω² + ¾γA²)² + (2ζΩ)²] A² − F² and its
  // gradient.
  double g(double amp, double omega) const {
    const double k = 1.0 - omega * omega + 0.75 * gamma * amp * amp, c = 2.0 * zeta * omega;
    return (k * k + c * c) * amp * amp - force * force;
  }
  double g_amplitude(double amp, double omega) const {
    const double k = 1.0 - omega * omega + 0.75 * gamma * amp * amp, c = 2.0 * zeta * omega;
    return 2.0 * amp * (k * k + c * c) + 3.0 * gamma * k * amp * amp * amp;
  }
  double g_omega(double amp, double omega) const {
    const double k = 1.0 - omega * omega + 0.75 * gamma * amp * amp;
    return amp * amp * (-4.0 * k * omega + 8.0 * zeta * zeta * omega);
  }
};

// R = A x − b λ: the branch x = A⁻¹ b λ is a straight line.
struct LinearProblem {
  MatrixXd a{{4.0, 1.0, 0.0}, {1.0, 3.0, -1.0}, {0.5, 0.0, 2.0}};
  VectorXd b{{1.0, -2.0, 0.5}};

  jcont::ResidualFunction residual() const {
    return [p = *this](const VectorXd& x, double lambda, bool jacobian) {
      jcont::Evaluation e;
      e.residual = p.a * x - p.b * lambda;
      if (jacobian) {
        e.d_state = p.a;
        e.d_parameter = -p.b;
      }
      return e;
    };
  }
};

int count_folds(const jcont::Result& r) {
  int folds = 0;
  for (const auto& p : r.points) folds += p.fold ? 1 : 0;
  return folds;
}

std::string describe(const jcont::Result& r) {
  return "reason " + std::to_string(static_cast<int>(r.reason)) + ", " +
         std::to_string(r.points.size()) + " points, " + std::to_string(r.evaluations) +
         " evaluations, " + std::to_string(r.rejected_steps) + " rejected: " + r.message;
}

}  // namespace

TEST(ContinuationArclength, SCurvePassesBothFoldsAndEndsOnLambdaEnd) {
  jcont::Options o;
  o.parameter_start = -4.0;
  o.parameter_end = 4.0;
  const auto wall_start = std::chrono::steady_clock::now();
  const auto r = jcont::trace(s_curve(), VectorXd::Constant(1, -2.2), o);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  ASSERT_EQ(r.reason, jcont::StopReason::reached_end) << describe(r);
  ASSERT_GE(r.points.size(), 3u);
  EXPECT_EQ(r.points.front().lambda, -4.0);
  EXPECT_EQ(r.points.back().lambda, 4.0);  // exactly: placed by the corrector at fixed λ
  EXPECT_NEAR(r.points.back().x(0), 2.1958233454456, 1e-10);  // real root of x³ − 3x − 4

  std::vector<const jcont::Point*> folds;
  for (const auto& p : r.points) {
    EXPECT_LE(std::abs(s_curve_residual(p.x(0), p.lambda)), o.residual_tolerance);
    EXPECT_LE(p.residual, o.residual_tolerance);
    EXPECT_NEAR(p.tangent.norm(), 1.0, 1e-12);
    EXPECT_GE(p.lambda, -4.0);
    EXPECT_LE(p.lambda, 4.0);
    EXPECT_LE(p.step, o.max_step);
    if (p.fold) folds.push_back(&p);
  }
  ASSERT_EQ(folds.size(), 2u) << describe(r);
  // The flag sits on the first point past the fold: within one step (|Δλ| ≈ 3 Δx² there).
  EXPECT_NEAR(folds[0]->lambda, 2.0, 0.05);
  EXPECT_NEAR(folds[0]->x(0), -1.0, 0.15);
  EXPECT_NEAR(folds[1]->lambda, -2.0, 0.05);
  EXPECT_NEAR(folds[1]->x(0), 1.0, 0.15);
  // The branch is traced in order: x increases monotonically along it.
  for (std::size_t k = 1; k < r.points.size(); ++k) {
    EXPECT_GT(r.points[k].x(0), r.points[k - 1].x(0)) << "point " << k;
  }
  EXPECT_TRUE(r.completed());
  EXPECT_FALSE(r.message.empty());
  EXPECT_GT(r.evaluations, static_cast<int>(r.points.size()));
  // The timings are parts of the call's wall time: positive (evaluations ran) and within it.
  EXPECT_GT(r.evaluation_seconds, 0.0);
  EXPECT_LE(r.evaluation_seconds, wall);
  EXPECT_GT(r.linear_solve_seconds, 0.0);
  EXPECT_LE(r.evaluation_seconds + r.linear_solve_seconds, wall);
  std::printf("[ S-curve ] %zu points, %d evaluations, %d corrector iterations, %d rejected\n",
              r.points.size(), r.evaluations, r.corrector_iterations, r.rejected_steps);
}

TEST(ContinuationArclength, LinearBranchIsExactWithFewPointsAndMaxStepRespected) {
  const LinearProblem lp;
  jcont::Options o;
  o.parameter_start = 0.0;
  o.parameter_end = 1.0;
  o.initial_step = 0.01;
  o.max_step = 0.1;
  const auto r = jcont::trace(lp.residual(), VectorXd::Constant(3, 1.0), o);
  ASSERT_EQ(r.reason, jcont::StopReason::reached_end) << describe(r);

  const VectorXd direction = lp.a.partialPivLu().solve(lp.b);  // dx/dλ
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    const auto& p = r.points[k];
    EXPECT_LE((p.x - direction * p.lambda).lpNorm<Eigen::Infinity>(), 1e-13) << "point " << k;
    EXPECT_LE(p.step, o.max_step * (1.0 + 1e-14));
    if (k > 0 && k + 1 < r.points.size()) {
      EXPECT_EQ(p.iterations, 0) << "point " << k << ": the predictor is exact on a line";
    }
  }
  EXPECT_EQ(r.points.back().lambda, 1.0);

  // Expected count: the steps 0.01, 0.02, 0.04, 0.08, 0.1, 0.1, ... (doubling: no corrector
  // iteration) along a line of length L = ‖(dx/dλ, 1)‖ in the (unscaled) unknowns.
  const double length = std::sqrt(direction.squaredNorm() + 1.0);
  double travelled = 0.0, step = o.initial_step;
  std::size_t expected = 1;
  while (travelled < length) {
    travelled += step;
    ++expected;
    step = std::min(2.0 * step, o.max_step);
  }
  EXPECT_EQ(r.points.size(), expected) << describe(r);
  EXPECT_EQ(r.rejected_steps, 0);
}

// max_parameter_step (a damping curve's points_per_decade) caps the step so that the predictor
// advances λ by at most that much: exactly on a line (the predictor is the point), and within the
// corrector's small overshoot on the S-curve where it advances in λ (|τ_λ| ≥ 0.5 at the step's
// start; at the folds, τ_λ → 0, the cap lifts), whose uncapped steps there are many times longer.
TEST(ContinuationArclength, MaxParameterStepBoundsTheParameterIncrement) {
  const auto largest_increment = [](const jcont::Result& r) {
    double d = 0.0;
    for (std::size_t k = 1; k < r.points.size(); ++k) {
      const auto& from = r.points[k - 1];
      if (std::abs(from.tangent(from.tangent.size() - 1)) >= 0.5)
        d = std::max(d, std::abs(r.points[k].lambda - from.lambda));
    }
    return d;
  };
  const LinearProblem lp;
  jcont::Options o;
  o.parameter_start = 0.0;
  o.parameter_end = 1.0;
  o.initial_step = 0.01;
  o.max_step = 0.5;
  const auto free_line = jcont::trace(lp.residual(), VectorXd::Constant(3, 1.0), o);
  o.max_parameter_step = 0.03;
  const auto line = jcont::trace(lp.residual(), VectorXd::Constant(3, 1.0), o);
  ASSERT_EQ(line.reason, jcont::StopReason::reached_end) << describe(line);
  EXPECT_GT(largest_increment(free_line), 3.0 * o.max_parameter_step);
  EXPECT_LE(largest_increment(line), o.max_parameter_step * (1.0 + 1e-12));
  EXPECT_GE(line.points.size(), 34u);  // ⌈1/0.03⌉ steps and the start

  jcont::Options so;
  so.parameter_start = -2.2;
  so.parameter_end = 2.2;
  so.max_step = 0.5;
  const auto free_curve = jcont::trace(s_curve(), VectorXd::Constant(1, -2.2), so);
  so.max_parameter_step = 0.02;
  const auto curve = jcont::trace(s_curve(), VectorXd::Constant(1, -2.2), so);
  ASSERT_EQ(curve.reason, jcont::StopReason::reached_end) << describe(curve);
  EXPECT_GT(largest_increment(free_curve), 3.0 * so.max_parameter_step);
  EXPECT_LE(largest_increment(curve), 1.1 * so.max_parameter_step);
  std::printf("[ cap ] line: %zu points (%zu free), S-curve: %zu points (%zu free), largest dλ %.4f (cap %.2f)\n",
              line.points.size(), free_line.points.size(), curve.points.size(), free_curve.points.size(),
              largest_increment(curve), so.max_parameter_step);
  so.max_parameter_step = -1.0;
  EXPECT_NE(so.validate(1).find("max_parameter_step"), std::string::npos);
}

// max_output_change: x(λ) = 2 + tanh(40(λ − 1/2)) rises by a factor 3 within a few hundredths of
// λ; with the state weighted lightly in the arclength (state_scale 100) the steps stride across
// it. With the limit every step changes the output x by at most 5 % (relative), the curve still
// reaches its end, and an output that jumps (a step function) is resolved down to the floor of
// 10⁻³ max_step instead of ending the curve.
TEST(ContinuationArclength, MaxOutputChangeBoundsTheOutputChangeBetweenPoints) {
  const auto steep = [](double sharpness) -> jcont::ResidualFunction {
    return [sharpness](const VectorXd& x, double lambda, bool jacobian) {
      const double t = std::tanh(sharpness * (lambda - 0.5));
      jcont::Evaluation e;
      e.residual = VectorXd::Constant(1, x(0) - 2.0 - t);
      if (jacobian) {
        e.d_state = MatrixXd::Constant(1, 1, 1.0);
        e.d_parameter = VectorXd::Constant(1, -sharpness * (1.0 - t * t));
      }
      return e;
    };
  };
  const auto largest_change = [](const jcont::Result& r) {
    double d = 0.0;
    for (std::size_t k = 1; k < r.points.size(); ++k)
      d = std::max(d, std::abs(r.points[k].x(0) / r.points[k - 1].x(0) - 1.0));
    return d;
  };
  jcont::Options o;
  o.parameter_start = 0.0;
  o.parameter_end = 1.0;
  o.max_step = 0.2;
  o.state_scale = VectorXd::Constant(1, 100.0);
  o.outputs = [](const VectorXd& x, double) { return x; };
  const VectorXd x0 = VectorXd::Constant(1, 2.0 + std::tanh(-20.0));
  const auto free_curve = jcont::trace(steep(40.0), x0, o);
  o.max_output_change = 0.05;
  const auto curve = jcont::trace(steep(40.0), x0, o);
  ASSERT_EQ(curve.reason, jcont::StopReason::reached_end) << describe(curve);
  EXPECT_GT(largest_change(free_curve), 0.2);
  EXPECT_LE(largest_change(curve), 0.05);
  EXPECT_GT(curve.points.size(), free_curve.points.size());
  // A near-jump (tanh of 10⁶ (λ − 1/2)): the limit gives way at the step floor, the curve goes on.
  const auto jump = jcont::trace(steep(1e6), x0, o);
  EXPECT_EQ(jump.reason, jcont::StopReason::reached_end) << describe(jump);
  std::printf("[ output change ] free: %zu points, largest change %.3f; limited to 0.05: %zu points, largest %.4f; "
              "jump: %zu points, largest %.3f\n",
              free_curve.points.size(), largest_change(free_curve), curve.points.size(), largest_change(curve),
              jump.points.size(), largest_change(jump));
  o.max_output_change = -1.0;
  EXPECT_NE(o.validate(1).find("max_output_change"), std::string::npos);
}

TEST(ContinuationArclength, DuffingFrequencyResponseMatchesClosedFormThroughFolds) {
  const Duffing d;
  jcont::Options o;
  o.parameter_start = 0.5;
  o.parameter_end = 2.0;
  o.initial_step = 0.02;
  o.max_step = 0.05;
  const auto r = jcont::trace(d.residual(), d.linear(0.5), o);
  ASSERT_EQ(r.reason, jcont::StopReason::reached_end) << describe(r);
  EXPECT_EQ(r.points.back().lambda, 2.0);

  // Every point lies on the closed-form curve g(A, Ω) = 0: distance |g| / ‖∇g‖ in the (A, Ω)
  // plane. Folds (dΩ/ds = 0) are where ∂g/∂A = 0 on the curve: its sign changes between two
  // points exactly where the solver flags a fold.
  double amplitude_max = 0.0;
  int closed_form_folds = 0;
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    const auto& p = r.points[k];
    const double amp = p.x.norm(), omega = p.lambda;
    amplitude_max = std::max(amplitude_max, amp);
    const double distance =
        std::abs(d.g(amp, omega)) / std::hypot(d.g_amplitude(amp, omega), d.g_omega(amp, omega));
    EXPECT_LE(distance, 1e-8) << "point " << k << " at Ω = " << omega;
    if (k == 0) continue;
    const auto& q = r.points[k - 1];
    const bool sign_change = d.g_amplitude(amp, omega) * d.g_amplitude(q.x.norm(), q.lambda) < 0.0;
    closed_form_folds += sign_change ? 1 : 0;
    EXPECT_EQ(p.fold, sign_change) << "point " << k << " at Ω = " << omega;
  }
  EXPECT_EQ(count_folds(r), 2) << describe(r);
  EXPECT_EQ(closed_form_folds, 2);
  // Peak amplitude: ∂g/∂Ω = 0 gives 1 − Ω² + ¾γA² = 2ζ², and then g = 0 gives
  // A² (1 − ζ² + ¾γA²) = (F/2ζ)².
  const double f2z = d.force / (2.0 * d.zeta), b = 1.0 - d.zeta * d.zeta;
  const double peak =
      std::sqrt((-b + std::sqrt(b * b + 3.0 * d.gamma * f2z * f2z)) / (1.5 * d.gamma));
  EXPECT_LE(amplitude_max, peak * (1.0 + 1e-12));
  EXPECT_GE(amplitude_max, peak * 0.99);
  std::printf("[ Duffing ] %zu points, %d evaluations, %d corrector iterations, %d rejected\n",
              r.points.size(), r.evaluations, r.corrector_iterations, r.rejected_steps);
}

TEST(ContinuationArclength, FailedEvaluationsStopAtMinStepKeepingThePoints) {
  const auto base = LinearProblem().residual();
  jcont::Options o;
  o.parameter_start = 0.0;
  o.parameter_end = 1.0;
  o.min_step = 1e-6;
  const auto failing = [&](const VectorXd& x, double lambda, bool jacobian) {
    if (lambda > 0.5) {
      jcont::Evaluation e;
      e.ok = false;
      e.message = "beyond the valid range";
      return e;
    }
    return base(x, lambda, jacobian);
  };
  const auto r = jcont::trace(failing, VectorXd::Zero(3), o);
  ASSERT_EQ(r.reason, jcont::StopReason::min_step) << describe(r);
  EXPECT_FALSE(r.message.empty());
  EXPECT_NE(r.message.find("beyond the valid range"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("λ = "), std::string::npos) << r.message;
  EXPECT_EQ(r.message.find('\n'), std::string::npos);
  ASSERT_GE(r.points.size(), 2u);
  for (const auto& p : r.points) EXPECT_LE(p.lambda, 0.5);
  EXPECT_GT(r.points.back().lambda, 0.49);  // halving brought the branch up to the boundary
  EXPECT_GT(r.rejected_steps, 0);
}

TEST(ContinuationArclength, ThrowingResidualIsAFailedEvaluationNotAnAbort) {
  const auto base = LinearProblem().residual();
  jcont::Options o;
  o.parameter_start = 0.0;
  o.parameter_end = 1.0;
  o.min_step = 1e-6;
  const auto throwing = [&](const VectorXd& x, double lambda, bool jacobian) {
    if (lambda > 0.5) throw std::invalid_argument("path outside the law's domain");
    return base(x, lambda, jacobian);
  };
  jcont::Result r;
  ASSERT_NO_THROW(r = jcont::trace(throwing, VectorXd::Zero(3), o));
  ASSERT_EQ(r.reason, jcont::StopReason::min_step) << describe(r);
  EXPECT_NE(r.message.find("path outside the law's domain"), std::string::npos) << r.message;
  ASSERT_GE(r.points.size(), 2u);
  for (const auto& p : r.points) EXPECT_LE(p.lambda, 0.5);
}

TEST(ContinuationArclength, NonFiniteResidualIsAFailedStepNeverAnAcceptedPoint) {
  const auto base = s_curve();
  jcont::Options o;
  o.parameter_start = -4.0;
  o.parameter_end = 4.0;
  const auto nan_beyond = [&](const VectorXd& x, double lambda, bool jacobian) {
    auto e = base(x, lambda, jacobian);
    if (lambda > 1.0) e.residual(0) = std::numeric_limits<double>::quiet_NaN();
    return e;
  };
  const auto r = jcont::trace(nan_beyond, VectorXd::Constant(1, -2.2), o);
  ASSERT_EQ(r.reason, jcont::StopReason::min_step) << describe(r);
  EXPECT_NE(r.message.find("non-finite"), std::string::npos) << r.message;
  ASSERT_GE(r.points.size(), 1u);
  for (const auto& p : r.points) {
    EXPECT_TRUE(p.x.allFinite());
    EXPECT_TRUE(p.tangent.allFinite());
    EXPECT_TRUE(std::isfinite(p.lambda));
    EXPECT_LE(p.lambda, 1.0);
  }

  // A NaN Jacobian is the same failure.
  const auto nan_jacobian = [&](const VectorXd& x, double lambda, bool jacobian) {
    auto e = base(x, lambda, jacobian);
    if (lambda > 1.0 && jacobian) e.d_state(0, 0) = std::numeric_limits<double>::infinity();
    return e;
  };
  const auto rj = jcont::trace(nan_jacobian, VectorXd::Constant(1, -2.2), o);
  EXPECT_EQ(rj.reason, jcont::StopReason::min_step) << describe(rj);
  for (const auto& p : rj.points) EXPECT_LE(p.lambda, 1.0);
}

TEST(ContinuationArclength, CallbackStopsTheRunKeepingThePoint) {
  jcont::Options o;
  o.parameter_start = -4.0;
  o.parameter_end = 4.0;
  int calls = 0;
  std::vector<double> seen;
  const auto r =
      jcont::trace(s_curve(), VectorXd::Constant(1, -2.2), o, [&](const jcont::Point& p) {
        seen.push_back(p.lambda);
        return ++calls < 3;
      });
  EXPECT_EQ(r.reason, jcont::StopReason::stopped_by_user) << describe(r);
  ASSERT_EQ(r.points.size(), 3u);
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(seen.front(), -4.0);  // the start is reported too
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(seen[k], r.points[k].lambda);
}

TEST(ContinuationArclength, MaxPointsStops) {
  jcont::Options o;
  o.parameter_start = -4.0;
  o.parameter_end = 4.0;
  o.max_points = 5;
  const auto r = jcont::trace(s_curve(), VectorXd::Constant(1, -2.2), o);
  EXPECT_EQ(r.reason, jcont::StopReason::max_points) << describe(r);
  EXPECT_EQ(r.points.size(), 5u);
  EXPECT_FALSE(r.completed());
}

// The status convention (contact/termination.hpp) on real traces of the S-curve: to the end, stopped
// by the callback, out of points, turned back across the start; and the full translation table.
TEST(ContinuationArclength, StatusMapsTheStopReason) {
  using jointhb::Termination;
  jcont::Options o;
  o.parameter_start = -4.0;
  o.parameter_end = 4.0;
  const auto full = jcont::trace(s_curve(), VectorXd::Constant(1, -2.2), o);
  ASSERT_EQ(full.reason, jcont::StopReason::reached_end) << describe(full);
  EXPECT_EQ(full.status().termination, Termination::reached_end);
  EXPECT_TRUE(full.status().ok());
  EXPECT_EQ(full.status().brief(), "reached_end: " + full.message);

  int calls = 0;
  const auto stop_at_three = [&](const jcont::Point&) { return ++calls < 3; };
  const auto stopped = jcont::trace(s_curve(), VectorXd::Constant(1, -2.2), o, stop_at_three);
  ASSERT_EQ(stopped.reason, jcont::StopReason::stopped_by_user) << describe(stopped);
  EXPECT_EQ(stopped.status().termination, Termination::stopped_by_user);
  EXPECT_FALSE(stopped.status().ok());
  EXPECT_EQ(stopped.status().message, stopped.message);

  o.max_points = 5;
  const auto short_run = jcont::trace(s_curve(), VectorXd::Constant(1, -2.2), o);
  ASSERT_EQ(short_run.reason, jcont::StopReason::max_points) << describe(short_run);
  EXPECT_EQ(short_run.status().termination, Termination::no_convergence);

  o = jcont::Options{};
  o.parameter_start = -1.5;
  o.parameter_end = 4.0;
  const auto back = jcont::trace(s_curve(), VectorXd::Constant(1, -1.9), o);
  ASSERT_EQ(back.reason, jcont::StopReason::left_range) << describe(back);
  EXPECT_EQ(back.status().termination, Termination::failed);

  EXPECT_EQ(jcont::termination(jcont::StopReason::reached_end), Termination::reached_end);
  EXPECT_EQ(jcont::termination(jcont::StopReason::stopped_by_user), Termination::stopped_by_user);
  EXPECT_EQ(jcont::termination(jcont::StopReason::max_points), Termination::no_convergence);
  EXPECT_EQ(jcont::termination(jcont::StopReason::min_step), Termination::failed);
  EXPECT_EQ(jcont::termination(jcont::StopReason::start_failed), Termination::failed);
  EXPECT_EQ(jcont::termination(jcont::StopReason::left_range), Termination::failed);
  // Every curve of the layer uses the same translation.
  jcont::Result r;
  r.reason = jcont::StopReason::min_step;
  r.message = "step below min_step";
  EXPECT_EQ(r.status().brief(), "failed: step below min_step");
}

TEST(ContinuationArclength, StartWithoutRootFails) {
  const auto no_root = [](const VectorXd& x, double lambda, bool jacobian) {
    jcont::Evaluation e;  // x² + 1 + λ² > 0
    e.residual = VectorXd::Constant(1, x(0) * x(0) + 1.0 + lambda * lambda);
    if (jacobian) {
      e.d_state = MatrixXd::Constant(1, 1, 2.0 * x(0));
      e.d_parameter = VectorXd::Constant(1, 2.0 * lambda);
    }
    return e;
  };
  jcont::Options o;
  const auto r = jcont::trace(no_root, VectorXd::Constant(1, 0.3), o);
  EXPECT_EQ(r.reason, jcont::StopReason::start_failed) << describe(r);
  EXPECT_TRUE(r.points.empty());
  EXPECT_NE(r.message.find("residual"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("start"), std::string::npos) << r.message;
  // Newton iterations plus the damping of its line searches (up to 20 halvings): bounded, and the
  // failure is reported rather than iterated forever.
  EXPECT_LE(r.evaluations, 2 * (o.max_start_iterations + 1));
}

TEST(ContinuationArclength, StartNewtonIsDampedFromAPoorGuess) {
  // atan x = λ at λ = 0 from x0 = 3: undamped Newton diverges for |x0| > 1.39 (each step
  // overshoots further); the damped start converges to x = 0, and the branch x = tan λ follows.
  const auto arctan = [](const VectorXd& x, double lambda, bool jacobian) {
    jcont::Evaluation e;
    e.residual = VectorXd::Constant(1, std::atan(x(0)) - lambda);
    if (jacobian) {
      e.d_state = MatrixXd::Constant(1, 1, 1.0 / (1.0 + x(0) * x(0)));
      e.d_parameter = VectorXd::Constant(1, -1.0);
    }
    return e;
  };
  jcont::Options o;
  o.parameter_end = 1.0;
  const auto r = jcont::trace(arctan, VectorXd::Constant(1, 3.0), o);
  ASSERT_EQ(r.reason, jcont::StopReason::reached_end) << describe(r);
  EXPECT_NEAR(r.points.front().x(0), 0.0, 1e-10);
  for (const auto& p : r.points) EXPECT_NEAR(p.x(0), std::tan(p.lambda), 1e-9);
}

TEST(ContinuationArclength, BranchTurningBackAcrossTheStartLeavesTheRange) {
  // From λ = −1.5 on the lower branch of the S-curve, the branch folds at λ = 2 (before the end,
  // 4) and comes back down the middle branch across λ = −1.5: the last point is placed there.
  jcont::Options o;
  o.parameter_start = -1.5;
  o.parameter_end = 4.0;
  const auto r = jcont::trace(s_curve(), VectorXd::Constant(1, -1.9), o);
  ASSERT_EQ(r.reason, jcont::StopReason::left_range) << describe(r);
  EXPECT_FALSE(r.completed());
  EXPECT_EQ(r.points.back().lambda, -1.5);
  EXPECT_EQ(count_folds(r), 1);
  const double x = r.points.back().x(0);
  EXPECT_GT(x, -1.0);  // on the middle branch
  EXPECT_LT(x, 1.0);
  EXPECT_LE(std::abs(s_curve_residual(x, -1.5)), 1e-10);
}

TEST(ContinuationArclength, DecreasingParameterIsTracedDownwards) {
  jcont::Options o;
  o.parameter_start = 4.0;
  o.parameter_end = -4.0;
  o.direction = -1;
  const auto r = jcont::trace(s_curve(), VectorXd::Constant(1, 2.2), o);
  ASSERT_EQ(r.reason, jcont::StopReason::reached_end) << describe(r);
  EXPECT_EQ(r.points.back().lambda, -4.0);
  EXPECT_EQ(count_folds(r), 2);
  EXPECT_NEAR(r.points.back().x(0), -2.1958233454456, 1e-10);
}

TEST(ContinuationArclength, StepsGrowToMaxStepAndNeverExceedIt) {
  // Mildly nonlinear: x + 0.1 sin x = λ.
  const auto mild = [](const VectorXd& x, double lambda, bool jacobian) {
    jcont::Evaluation e;
    e.residual = VectorXd::Constant(1, x(0) + 0.1 * std::sin(x(0)) - lambda);
    if (jacobian) {
      e.d_state = MatrixXd::Constant(1, 1, 1.0 + 0.1 * std::cos(x(0)));
      e.d_parameter = VectorXd::Constant(1, -1.0);
    }
    return e;
  };
  jcont::Options o;
  o.parameter_start = 0.0;
  o.parameter_end = 20.0;
  o.initial_step = 0.01;
  o.max_step = 0.25;
  const auto r = jcont::trace(mild, VectorXd::Zero(1), o);
  ASSERT_EQ(r.reason, jcont::StopReason::reached_end) << describe(r);
  int at_max = 0;
  for (std::size_t k = 1; k < r.points.size(); ++k) {
    const double step = r.points[k].step;
    EXPECT_LE(step, o.max_step * (1.0 + 1e-12)) << "point " << k;
    at_max += std::abs(step - o.max_step) <= 1e-12 ? 1 : 0;
    if (k >= 2) {
      EXPECT_LE(step, o.step_growth * r.points[k - 1].step * (1.0 + 1e-12));
    }
  }
  EXPECT_EQ(r.points[1].step, o.initial_step);
  EXPECT_GT(at_max, static_cast<int>(r.points.size()) / 2) << describe(r);
}

TEST(ContinuationArclength, StepFollowsTheIterationRule) {
  // s_{k+1} = s_k · clamp(target / iterations_k, 1/2, step_growth), within [min_step, max_step],
  // on a run without rejected steps (the last point, moved onto λ_end, excluded).
  jcont::Options o;
  o.parameter_start = -4.0;
  o.parameter_end = 4.0;
  o.target_corrector_iterations = 2;
  o.max_step = 0.3;
  const auto r = jcont::trace(s_curve(), VectorXd::Constant(1, -2.2), o);
  ASSERT_EQ(r.reason, jcont::StopReason::reached_end) << describe(r);
  ASSERT_EQ(r.rejected_steps, 0) << describe(r);
  bool shrank = false;
  for (std::size_t k = 2; k + 1 < r.points.size(); ++k) {
    const auto& prev = r.points[k - 1];
    const double ratio = 2.0 / std::max(prev.iterations, 1);
    const double expected =
        std::clamp(prev.step * std::clamp(ratio, 0.5, o.step_growth), o.min_step, o.max_step);
    EXPECT_NEAR(r.points[k].step, expected, 1e-14 * expected) << "point " << k;
    shrank = shrank || r.points[k].step < prev.step;
  }
  EXPECT_TRUE(shrank) << "some corrector needed more than 2 iterations";
}

TEST(ContinuationArclength, ValidateNamesTheFieldAndConstraint) {
  jcont::Options o;
  EXPECT_EQ(o.validate(3), "");

  auto with = [](auto change) {
    jcont::Options b;
    change(b);
    return b.validate(3);
  };
  EXPECT_EQ(with([](auto& b) { b.initial_step = -1.0; }),
            "initial_step: must be finite and > 0, got -1");
  EXPECT_NE(with([](auto& b) { b.min_step = 1.0; }).find("min_step: must lie in (0, initial_step"),
            std::string::npos);
  EXPECT_NE(with([](auto& b) { b.max_step = 1e-3; }).find("max_step:"), std::string::npos);
  EXPECT_NE(with([](auto& b) { b.max_points = 0; }).find("max_points: must be >= 1, got 0"),
            std::string::npos);
  EXPECT_NE(with([](auto& b) { b.parameter_end = b.parameter_start; }).find("parameter_end:"),
            std::string::npos);
  EXPECT_EQ(with([](auto& b) { b.direction = -1; }),
            "direction: must be sign(parameter_end - parameter_start) = 1, got -1");
  EXPECT_NE(with([](auto& b) {
              b.target_corrector_iterations = 20;
            }).find("target_corrector_iterations:"),
            std::string::npos);
  EXPECT_NE(with([](auto& b) { b.step_growth = 1.0; }).find("step_growth:"), std::string::npos);
  EXPECT_NE(with([](auto& b) { b.residual_tolerance = 0.0; }).find("residual_tolerance:"),
            std::string::npos);
  EXPECT_NE(with([](auto& b) { b.parameter_scale = std::nan(""); }).find("parameter_scale:"),
            std::string::npos);
  EXPECT_EQ(with([](auto& b) { b.state_scale = VectorXd::Ones(2); }),
            "state_scale: must have size n = 3 (or be empty), got 2");
  EXPECT_EQ(with([](auto& b) {
              b.state_scale = VectorXd{{1.0, 0.0, 1.0}};
            }),
            "state_scale: entry 1 must be finite and > 0, got 0");

  // trace throws on invalid options and on a bad x0, naming the problem.
  const auto residual = LinearProblem().residual();
  jcont::Options bad;
  bad.state_scale = VectorXd::Ones(2);
  try {
    (void)jcont::trace(residual, VectorXd::Zero(3), bad);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("state_scale"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)jcont::trace(residual, VectorXd(), o), std::invalid_argument);
  EXPECT_THROW((void)jcont::trace(residual, VectorXd{{0.0, std::nan(""), 0.0}}, o),
               std::invalid_argument);
}

TEST(ContinuationArclength, StateScaleMakesALargeStateBehaveLikeTheUnitOne) {
  // x = 10⁶ z on the S-curve: scaled by 10⁶, the unknowns y are those of the unit problem.
  const double unit = 1e6;
  jcont::Options o;
  o.parameter_start = -4.0;
  o.parameter_end = 4.0;
  const auto reference = jcont::trace(s_curve(), VectorXd::Constant(1, -2.2), o);
  ASSERT_EQ(reference.reason, jcont::StopReason::reached_end) << describe(reference);

  jcont::Options scaled = o;
  scaled.state_scale = VectorXd::Constant(1, unit);
  scaled.residual_tolerance = o.residual_tolerance;
  const auto r = jcont::trace(s_curve(unit), VectorXd::Constant(1, -2.2 * unit), scaled);
  ASSERT_EQ(r.reason, jcont::StopReason::reached_end) << describe(r);
  EXPECT_LE(
      std::abs(static_cast<long>(r.points.size()) - static_cast<long>(reference.points.size())), 1);
  EXPECT_EQ(count_folds(r), 2);
  EXPECT_NEAR(r.points.back().x(0) / unit, reference.points.back().x(0), 1e-10);
  for (std::size_t k = 0; k < std::min(r.points.size(), reference.points.size()) - 1; ++k) {
    EXPECT_NEAR(r.points[k].lambda, reference.points[k].lambda, 1e-8) << "point " << k;
  }

  // Without the scale the arclength is all state: the same budget of points gets nowhere.
  jcont::Options unscaled = o;
  unscaled.max_points = 2 * static_cast<int>(reference.points.size());
  const auto u = jcont::trace(s_curve(unit), VectorXd::Constant(1, -2.2 * unit), unscaled);
  EXPECT_NE(u.reason, jcont::StopReason::reached_end) << describe(u);
}

// A continued run (Options::continued) on R = λ − x³ from (0, 0), where R_x = 0: the branch
// x = λ^{1/3} runs vertical in λ there, so a start at fixed λ has a singular Jacobian; the
// continued start is corrected on the hyperplane normal to the tangent it is given and follows
// that tangent's orientation, with parameter_start still the bound behind which the run ends.
TEST(ContinuationArclength, ContinuedRunStartsWhereFixedLambdaIsSingular) {
  const jcont::ResidualFunction cubic = [](const VectorXd& x, double lambda, bool jacobian) {
    jcont::Evaluation e;
    e.residual = VectorXd::Constant(1, lambda - x(0) * x(0) * x(0));
    if (jacobian) {
      e.d_state = MatrixXd::Constant(1, 1, -3.0 * x(0) * x(0));
      e.d_parameter = VectorXd::Ones(1);
    }
    return e;
  };
  jcont::Options o;
  o.parameter_start = -1.0;
  o.parameter_end = 1.0;
  o.continued = jcont::Options::Continued{0.0, Eigen::Vector2d(1.0, 0.0)};
  const auto up = jcont::trace(cubic, VectorXd::Zero(1), o);
  ASSERT_EQ(up.reason, jcont::StopReason::reached_end) << describe(up);
  EXPECT_EQ(up.points.front().lambda, 0.0);
  for (const auto& p : up.points) EXPECT_NEAR(p.x(0), std::cbrt(p.lambda), 1e-9) << p.lambda;
  EXPECT_NEAR(up.points.back().x(0), 1.0, 1e-12);

  // Along −x the branch goes down to λ = −1 = parameter_start: left_range, last point on it.
  o.continued->tangent = Eigen::Vector2d(-1.0, 0.0);
  const auto down = jcont::trace(cubic, VectorXd::Zero(1), o);
  ASSERT_EQ(down.reason, jcont::StopReason::left_range) << describe(down);
  EXPECT_NEAR(down.points.back().lambda, -1.0, 1e-12);
  EXPECT_NEAR(down.points.back().x(0), -1.0, 1e-9);

  // The tangent must have size n + 1.
  o.continued->tangent = Eigen::Vector3d(1.0, 0.0, 0.0);
  EXPECT_THROW(jcont::trace(cubic, VectorXd::Zero(1), o), std::invalid_argument);
}
