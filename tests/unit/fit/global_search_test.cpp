// The batch global searches of direct and mlsl (src/fit/global_search.hpp) on standard test
// functions with published global minima (Branin, six-hump camel, Goldstein–Price, Hartmann 3;
// L. C. W. Dixon, G. P. Szegö (eds.), "Towards Global Optimisation 2", North-Holland 1978, as
// tabulated by Jones et al. 1993, Table 1), against NLopt's own DIRECT-L at the same budget (an
// independent implementation of the method): both must reach the minimum to the same accuracy.
// The batch structure: every batch's points are known before any is evaluated, so that the path
// depends only on the values — checked by evaluating each batch in reverse order.
#include <gtest/gtest.h>
#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "../../../src/fit/global_search.hpp"

namespace jointhb::fit::detail {
namespace {

struct TestFunction {
  std::string name;
  int n;
  std::vector<double> lower, upper;
  double minimum;
  std::function<double(const std::vector<double>&)> f;  // in the physical box
  [[nodiscard]] double at_unit(const std::vector<double>& u) const {
    std::vector<double> x(u.size());
    for (std::size_t i = 0; i < u.size(); ++i) x[i] = lower[i] + u[i] * (upper[i] - lower[i]);
    return f(x);
  }
};

std::vector<TestFunction> test_functions() {
  using std::cos;
  using std::exp;
  using std::numbers::pi;
  std::vector<TestFunction> t;
  t.push_back({"branin", 2, {-5.0, 0.0}, {10.0, 15.0}, 0.397887357729739, [](const auto& x) {
                 const double a = x[1] - 5.1 / (4 * pi * pi) * x[0] * x[0] + 5.0 / pi * x[0] - 6.0;
                 return a * a + 10.0 * (1.0 - 1.0 / (8 * pi)) * cos(x[0]) + 10.0;
               }});
  t.push_back({"six-hump camel", 2, {-3.0, -2.0}, {3.0, 2.0}, -1.031628453489877,
               [](const auto& x) {
                 const double a = x[0] * x[0], b = x[1] * x[1];
                 return (4.0 - 2.1 * a + a * a / 3.0) * a + x[0] * x[1] + (-4.0 + 4.0 * b) * b;
               }});
  t.push_back({"goldstein-price", 2, {-2.0, -2.0}, {2.0, 2.0}, 3.0, [](const auto& x) {
                 const double p = x[0], q = x[1];
                 const double a = 1.0 + (p + q + 1) * (p + q + 1) *
                                            (19 - 14 * p + 3 * p * p - 14 * q + 6 * p * q + 3 * q * q);
                 const double b = 30.0 + (2 * p - 3 * q) * (2 * p - 3 * q) *
                                             (18 - 32 * p + 12 * p * p + 48 * q - 36 * p * q + 27 * q * q);
                 return a * b;
               }});
  t.push_back({"hartmann 3", 3, {0, 0, 0}, {1, 1, 1}, -3.862782147820756, [](const auto& x) {
                 const double alpha[4] = {1.0, 1.2, 3.0, 3.2};
                 const double a[4][3] = {{3, 10, 30}, {0.1, 10, 35}, {3, 10, 30}, {0.1, 10, 35}};
                 const double p[4][3] = {{0.3689, 0.1170, 0.2673},
                                         {0.4699, 0.4387, 0.7470},
                                         {0.1091, 0.8732, 0.5547},
                                         {0.03815, 0.5743, 0.8828}};
                 double s = 0.0;
                 for (int i = 0; i < 4; ++i) {
                   double e = 0.0;
                   for (int j = 0; j < 3; ++j) e += a[i][j] * (x[j] - p[i][j]) * (x[j] - p[i][j]);
                   s += alpha[i] * exp(-e);
                 }
                 return -s;
               }});
  return t;
}

// Evaluates each batch (in reverse order, to show that order does not matter) and records sizes.
struct Counted {
  const TestFunction& t;
  std::vector<int> batches;
  std::vector<double> operator()(const std::vector<std::vector<double>>& points) {
    batches.push_back(static_cast<int>(points.size()));
    std::vector<double> f(points.size());
    for (std::size_t k = points.size(); k-- > 0;) f[k] = t.at_unit(points[k]);
    return f;
  }
};

double nlopt_direct_l(const TestFunction& t, int budget) {
  nlopt_opt opt = nlopt_create(NLOPT_GN_DIRECT_L, static_cast<unsigned>(t.n));
  const std::vector<double> lo(static_cast<std::size_t>(t.n), 0.0), hi(static_cast<std::size_t>(t.n), 1.0);
  nlopt_set_lower_bounds(opt, lo.data());
  nlopt_set_upper_bounds(opt, hi.data());
  nlopt_set_maxeval(opt, budget);
  nlopt_set_min_objective(
      opt,
      [](unsigned n, const double* x, double*, void* data) {
        return static_cast<const TestFunction*>(data)->at_unit(std::vector<double>(x, x + n));
      },
      const_cast<TestFunction*>(&t));
  std::vector<double> x(static_cast<std::size_t>(t.n), 0.5);
  double f = 0.0;
  nlopt_optimize(opt, x.data(), &f);
  nlopt_destroy(opt);
  return f;
}

TEST(GlobalSearch, DirectLReachesThePublishedMinimaLikeNloptsDirectL) {
  for (const TestFunction& t : test_functions()) {
    SCOPED_TRACE(t.name);
    const int budget = t.n == 2 ? 300 : 600;
    Counted counted{t, {}};
    const GlobalOutcome g = direct_l(t.n, std::ref(counted), budget, 1e-8);
    const double ours = std::abs(g.objective - t.minimum) / std::max(1.0, std::abs(t.minimum));
    const double theirs =
        std::abs(nlopt_direct_l(t, budget) - t.minimum) / std::max(1.0, std::abs(t.minimum));
    std::printf("%-16s DIRECT-L (batch) error %.2e in %d evaluations, %d batches (largest %d); "
                "NLopt's DIRECT-L %.2e\n",
                t.name.c_str(), ours, g.evaluations, g.batches, g.largest_batch, theirs);
    EXPECT_LT(ours, 1e-4);
    EXPECT_LT(ours, std::max(10.0 * theirs, 2e-5));
    EXPECT_LE(g.evaluations, budget);
    EXPECT_EQ(g.stop_reason, "MAXEVAL_REACHED");
    EXPECT_EQ(counted.batches.front(), 1);  // the centre
    EXPECT_EQ(counted.batches.at(1), 2 * t.n);  // the first trisection along every side
    EXPECT_GT(*std::max_element(counted.batches.begin(), counted.batches.end()), 2 * t.n);
    EXPECT_EQ(g.objective, t.at_unit(g.best));
  }
}

TEST(GlobalSearch, DirectLStopsAtXtolAndDividesEverySideOfTheCentre) {
  const TestFunction t = test_functions()[0];
  Counted counted{t, {}};
  const GlobalOutcome g = direct_l(t.n, std::ref(counted), 100000, 1e-2);
  EXPECT_EQ(g.stop_reason, "XTOL_REACHED");
  EXPECT_LT(g.evaluations, 100000);
}

TEST(GlobalSearch, MlslWithLocalSearchesFindsEveryPublishedMinimum) {
  for (const TestFunction& t : test_functions()) {
    SCOPED_TRACE(t.name);
    Counted counted{t, {}};
    int searches = 0;
    const LocalSearches local = [&](const std::vector<std::vector<double>>& starts, int budget) {
      std::vector<LocalMinimum> found;
      for (const auto& s : starts) {  // NLopt's BOBYQA from each start
        ++searches;
        nlopt_opt opt = nlopt_create(NLOPT_LN_BOBYQA, static_cast<unsigned>(t.n));
        const std::vector<double> lo(s.size(), 0.0), hi(s.size(), 1.0);
        nlopt_set_lower_bounds(opt, lo.data());
        nlopt_set_upper_bounds(opt, hi.data());
        nlopt_set_maxeval(opt, budget);
        nlopt_set_xtol_abs1(opt, 1e-9);
        struct Data {
          const TestFunction* t;
          int count;
        } data{&t, 0};
        nlopt_set_min_objective(
            opt,
            [](unsigned n, const double* x, double*, void* p) {
              auto* d = static_cast<Data*>(p);
              ++d->count;
              return d->t->at_unit(std::vector<double>(x, x + n));
            },
            &data);
        std::vector<double> x = s;
        double f = 0.0;
        nlopt_optimize(opt, x.data(), &f);
        nlopt_destroy(opt);
        found.push_back({x, f, data.count});
      }
      return found;
    };
    MlslOptions o;
    o.max_evaluations = 500;
    const GlobalOutcome g = mlsl(t.n, std::ref(counted), local, o);
    const double error = std::abs(g.objective - t.minimum) / std::max(1.0, std::abs(t.minimum));
    std::printf("%-16s MLSL error %.2e in %d evaluations, %d local searches, sample batches of %d\n",
                t.name.c_str(), error, g.evaluations, g.local_searches, counted.batches.front());
    EXPECT_LT(error, 1e-8);
    EXPECT_GE(g.local_searches, 1);
    EXPECT_EQ(searches, g.local_searches);
    EXPECT_LE(g.evaluations, o.max_evaluations + g.local_searches);  // budgets rounded up to 1
    EXPECT_EQ(counted.batches.front(), std::max(8, 4 * t.n));
  }
}

TEST(GlobalSearch, MlslSeedsShiftTheSample) {
  const TestFunction t = test_functions()[1];
  std::vector<std::vector<double>> first[2];
  for (unsigned seed : {1u, 2u}) {
    MlslOptions o;
    o.max_evaluations = 8;
    o.seed = seed;
    (void)mlsl(
        2,
        [&](const std::vector<std::vector<double>>& p) {
          first[seed - 1] = p;
          return std::vector<double>(p.size(), 1.0);
        },
        [](const std::vector<std::vector<double>>& s, int) {
          return std::vector<LocalMinimum>(s.size());
        },
        o);
  }
  ASSERT_EQ(first[0].size(), 8u);
  EXPECT_NE(first[0], first[1]);
  for (const auto& u : first[0]) {
    for (double x : u) EXPECT_TRUE(x >= 0.0 && x < 1.0);
  }
}

}  // namespace
}  // namespace jointhb::fit::detail
