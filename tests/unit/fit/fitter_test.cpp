// The fitter on problems with known answers: exponential decay (least-squares optimum and
// Gauss–Newton covariance computed independently), a product that only determines a·b
// (identifiability), a model that fails in part of the box (penalty), and resume.
#include "jointhb/fit/fitter.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "jointhb/fit/history.hpp"

namespace jointhb::fit {
namespace {

// y = A exp(−k t) on 20 points with fixed pseudo-noise of 1 % (relative residuals).
struct Decay {
  std::vector<double> t, y;
  Decay() {
    for (int i = 0; i < 20; ++i) {
      t.push_back(0.2 * i);
      const double noise = 0.01 * std::sin(12.9898 * i + 78.233);  // deterministic, |n| ≤ 1 %
      y.push_back(2.0 * std::exp(-0.7 * t.back()) * (1.0 + noise));
    }
  }
  Eigen::VectorXd r(double a, double k) const {
    Eigen::VectorXd out(static_cast<Eigen::Index>(t.size()));
    for (std::size_t i = 0; i < t.size(); ++i) out[i] = (a * std::exp(-k * t[i]) - y[i]) / y[i];
    return out;
  }
  Eigen::MatrixXd jacobian(double a, double k) const {  // ∂r/∂(A, k), analytic
    Eigen::MatrixXd j(static_cast<Eigen::Index>(t.size()), 2);
    for (std::size_t i = 0; i < t.size(); ++i) {
      j(i, 0) = std::exp(-k * t[i]) / y[i];
      j(i, 1) = -a * t[i] * std::exp(-k * t[i]) / y[i];
    }
    return j;
  }
  Model model() const {
    return [this](const std::vector<double>& v) {
      const Eigen::VectorXd res = r(v[0], v[1]);
      return Evaluation{true, "", std::vector<double>(res.data(), res.data() + res.size())};
    };
  }
};

TEST(Fitter, ExponentialDecayMatchesGaussNewtonOptimumAndCovariance) {
  const Decay d;
  // The least-squares optimum by Gauss–Newton, independently of NLopt.
  Eigen::Vector2d x(1.0, 1.0);
  for (int it = 0; it < 50; ++it) {
    const Eigen::MatrixXd j = d.jacobian(x[0], x[1]);
    x -= (j.transpose() * j).ldlt().solve(j.transpose() * d.r(x[0], x[1]));
  }
  const Eigen::MatrixXd j = d.jacobian(x[0], x[1]);
  const double s2 = d.r(x[0], x[1]).squaredNorm() / (20 - 2);
  const Eigen::Matrix2d covariance = s2 * (j.transpose() * j).inverse();

  const std::vector<FitParameter> p = {{"A", 0.1, 10.0, 8.0, true}, {"k", 0.01, 3.0, 2.5, false}};
  FitOptions o;
  o.xtol = 1e-10;
  o.ftol_rel = 0.0;
  const FitResult r = fit(d.model(), p, o);
  ASSERT_TRUE(r.ok);
  ASSERT_TRUE(r.has_jacobian);
  EXPECT_NEAR(r.best[0], x[0], 1e-6 * x[0]);
  EXPECT_NEAR(r.best[1], x[1], 1e-6 * x[1]);
  EXPECT_NEAR(r.s2, s2, 1e-8 * s2);
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      EXPECT_NEAR(r.covariance(a, b), covariance(a, b),
                  1e-4 * std::sqrt(covariance(a, a) * covariance(b, b)));
    }
    EXPECT_NEAR(r.standard_errors[a], std::sqrt(covariance(a, a)),
                1e-4 * std::sqrt(covariance(a, a)));
  }
  EXPECT_TRUE(r.unresolved.empty());
  EXPECT_EQ(r.failed_evaluations, 0);
  EXPECT_EQ(r.evaluations, r.model_evaluations);
  EXPECT_NEAR(r.correlation(0, 1),
              covariance(0, 1) / std::sqrt(covariance(0, 0) * covariance(1, 1)), 1e-4);
  // The noise is ~0.6 % rms: the truth lies within 3 standard errors.
  EXPECT_LT(std::abs(r.best[0] - 2.0), 3 * r.standard_errors[0]);
  EXPECT_LT(std::abs(r.best[1] - 0.7), 3 * r.standard_errors[1]);
}

TEST(Fitter, ProductOfTwoParametersIsFlaggedUnidentifiable) {
  const Decay d;
  // Only a·b enters: y = (a b) exp(−k t).
  const Model m = [&](const std::vector<double>& v) {
    const Eigen::VectorXd res = d.r(v[0] * v[1], v[2]);
    return Evaluation{true, "", std::vector<double>(res.data(), res.data() + res.size())};
  };
  const std::vector<FitParameter> p = {
      {"a", 0.1, 10.0, 5.0, true}, {"b", 0.1, 10.0, 5.0, true}, {"k", 0.01, 3.0, 2.0, false}};
  const FitResult r = fit(m, p, FitOptions{});
  ASSERT_TRUE(r.ok && r.has_jacobian);
  EXPECT_NEAR(r.best[0] * r.best[1], 2.0, 0.05);
  ASSERT_EQ(r.unresolved.size(), 1u);
  const auto& v = r.unresolved[0].components;  // a·b fixed: log a + log b constant
  EXPECT_NEAR(std::abs(v[0]), std::sqrt(0.5), 1e-3);
  EXPECT_NEAR(v[0], -v[1], 1e-3);
  EXPECT_NEAR(v[2], 0.0, 1e-3);
  EXPECT_LT(r.unresolved[0].singular_value, 1e-3 * r.singular_values[0]);
  EXPECT_TRUE(std::isinf(r.standard_errors[0]) && std::isinf(r.standard_errors[1]));
  EXPECT_TRUE(std::isfinite(r.standard_errors[2]));
  EXPECT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("log a"), std::string::npos) << r.warnings[0];
}

TEST(Fitter, FailedEvaluationsArePenalisedNotFatal) {
  const Decay d;
  int calls = 0;
  const Model m = [&](const std::vector<double>& v) {
    ++calls;
    if (v[1] > 2.0) throw std::runtime_error("continuation stopped");  // part of the box fails
    if (v[0] > 6.0) return Evaluation{false, "start failed", {}};
    const Eigen::VectorXd res = d.r(v[0], v[1]);
    return Evaluation{true, "", std::vector<double>(res.data(), res.data() + res.size())};
  };
  const std::vector<FitParameter> p = {{"A", 0.1, 10.0, 5.0, false}, {"k", 0.01, 3.0, 1.9, false}};
  const FitResult r = fit(m, p, FitOptions{});
  ASSERT_TRUE(r.ok);
  EXPECT_GT(r.failed_evaluations, 0);
  EXPECT_EQ(r.model_evaluations, calls);
  const FitResult clean = fit(d.model(), p, FitOptions{});
  EXPECT_NEAR(r.best[0], clean.best[0], 1e-4);
  EXPECT_NEAR(r.best[1], clean.best[1], 1e-4);
  // A model that always fails: no exception, a result saying so.
  const FitResult none = fit(
      [](const std::vector<double>&) {
        return Evaluation{false, "never", {}};
      },
      p, {});
  EXPECT_FALSE(none.ok);
  EXPECT_EQ(none.failed_evaluations, none.evaluations);
  EXPECT_EQ(none.status().termination, Termination::failed);
  EXPECT_EQ(none.status().message, "every evaluation failed");
  // A successful fit stops on one of NLopt's tolerances (or its evaluation budget).
  const Termination t = r.status().termination;
  EXPECT_TRUE(t == Termination::converged || t == Termination::no_convergence) << r.status().brief();
  FitResult budget = r;
  budget.stop_reason = "MAXEVAL_REACHED";
  EXPECT_EQ(budget.status().termination, Termination::no_convergence);
  budget.stop_reason = "XTOL_REACHED";
  EXPECT_EQ(budget.status().termination, Termination::converged);
  budget.stop_reason = "ROUNDOFF_LIMITED";
  EXPECT_EQ(budget.status().termination, Termination::failed);
}

TEST(Fitter, ResumeFromHistoryGivesTheSameResultWithFewerModelCalls) {
  const Decay d;
  const std::vector<FitParameter> p = {{"A", 0.1, 10.0, 8.0, true}, {"k", 0.01, 3.0, 2.5, false}};
  FitOptions o;
  o.starts = 3;
  const auto file = std::filesystem::temp_directory_path() /
                    ("jointhb-fit-history-" + std::to_string(::getpid()) + ".csv");
  std::vector<HistoryRow> rows;
  FitResult full;
  {
    HistoryWriter writer(file, {"A", "k"}, d.t.size(), false);
    full = fit(d.model(), p, o, [&](const HistoryRow& row) {
      rows.push_back(row);
      writer.write(row);
    });
  }
  ASSERT_EQ(static_cast<int>(rows.size()), full.evaluations);
  const auto back = read_history(file, {"A", "k"});
  ASSERT_EQ(back.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(back[i].values, rows[i].values);
    EXPECT_EQ(back[i].objective, rows[i].objective);
    EXPECT_EQ(back[i].residuals, rows[i].residuals);
  }
  // Interrupted after 60 % of the evaluations (the last line cut short).
  const std::size_t kept = rows.size() * 6 / 10;
  std::vector<HistoryRow> part(back.begin(), back.begin() + static_cast<long>(kept));
  std::vector<HistoryRow> added;
  const FitResult resumed = fit(
      d.model(), p, o, [&](const HistoryRow& row) { added.push_back(row); }, part);
  EXPECT_EQ(resumed.best, full.best);
  EXPECT_EQ(resumed.objective, full.objective);
  EXPECT_EQ(resumed.evaluations, full.evaluations);
  EXPECT_EQ(resumed.replayed, static_cast<int>(kept));
  EXPECT_EQ(resumed.model_evaluations, full.evaluations - static_cast<int>(kept));
  ASSERT_FALSE(added.empty());
  EXPECT_EQ(added.front().eval, static_cast<int>(kept) + 1);
  EXPECT_EQ(resumed.standard_errors, full.standard_errors);
  std::filesystem::remove(file);
}

TEST(Fitter, HistoryIgnoresALastLineCutShortAndRejectsOtherParameters) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("jointhb-fit-cut-" + std::to_string(::getpid()) + ".csv");
  {
    HistoryWriter w(file, {"x"}, 1, false);
    w.write({1, 0, 0.25, {1.5}, false, {0.5}});
  }
  {
    std::FILE* f = std::fopen(file.string().c_str(), "a");
    std::fputs("2,0,0.1", f);  // no newline: interrupted
    std::fclose(f);
  }
  const auto rows = read_history(file, {"x"});
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].values[0], 1.5);
  EXPECT_THROW(read_history(file, {"y"}), std::runtime_error);
  std::filesystem::remove(file);
}

TEST(Fitter, LatinHypercubeIsDeterministicAndStratified) {
  const auto a = latin_hypercube(9, 3, 7);
  const auto b = latin_hypercube(9, 3, 7);
  ASSERT_EQ(a.size(), 8u);
  EXPECT_EQ(a, b);
  for (int d = 0; d < 3; ++d) {
    std::vector<int> seen(8, 0);
    for (const auto& u : a) ++seen[static_cast<std::size_t>(u[d] * 8)];
    for (int s : seen) EXPECT_EQ(s, 1);
  }
  EXPECT_NE(latin_hypercube(9, 3, 8), a);
}

TEST(Fitter, GlobalAlgorithmsFindTheOptimum) {
  const Decay d;
  const std::vector<FitParameter> p = {{"A", 0.1, 10.0, 8.0, true}, {"k", 0.01, 3.0, 2.5, false}};
  const FitResult ref = fit(d.model(), p, FitOptions{});
  for (const char* a : {"direct", "mlsl", "neldermead", "cobyla"}) {
    FitOptions o;
    o.algorithm = a;
    o.max_evaluations = 300;
    const FitResult r = fit(d.model(), p, o);
    ASSERT_TRUE(r.ok) << a;
    EXPECT_NEAR(r.best[0], ref.best[0], 1e-3 * ref.best[0]) << a;
    EXPECT_NEAR(r.best[1], ref.best[1], 1e-3 * ref.best[1]) << a;
  }
  FitOptions bad;
  bad.algorithm = "simplex";
  EXPECT_THROW(fit(d.model(), p, bad), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::fit
