// The batch-parallel global phase of direct and mlsl (global_search.hpp).
#include "global_search.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <stdexcept>

#include "jointhb/study/sampling.hpp"

namespace jointhb::fit::detail {
namespace {

// ---- DIRECT-L ----------------------------------------------------------------------------------

struct Rectangle {
  std::vector<double> centre;
  std::vector<int> level;  ///< side 3^(−level_i) in coordinate i
  double f = 0.0;
  [[nodiscard]] int shortest_level() const { return *std::min_element(level.begin(), level.end()); }
};

double direct_side(int level) { return std::pow(3.0, -level); }

// The rectangles an iteration divides (Jones et al. 1993, Def. 4.1; one per size, DIRECT-L): the
// best rectangle of each size, on the lower-right convex hull from the best of all, that passes
// the ε test.
std::vector<std::size_t> potentially_optimal(const std::vector<Rectangle>& rects) {
  constexpr double epsilon = 0.0;
  std::map<int, std::size_t> best_of_level;  // level of the longest side → least f (first on ties)
  std::size_t best = 0;
  for (std::size_t i = 0; i < rects.size(); ++i) {
    if (rects[i].f < rects[best].f) best = i;
    const int l = rects[i].shortest_level();
    auto it = best_of_level.find(l);
    if (it == best_of_level.end() || rects[i].f < rects[it->second].f) best_of_level[l] = i;
  }
  const double f_min = rects[best].f;
  // The hull's points by increasing size d = 3^(−l)/2, from the largest size holding f_min.
  struct Point {
    double d, f;
    std::size_t rect;
  };
  std::vector<Point> points;
  for (auto it = best_of_level.rbegin(); it != best_of_level.rend(); ++it) {  // small d first
    points.push_back({0.5 * direct_side(it->first), rects[it->second].f, it->second});
  }
  std::size_t first = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (points[k].f <= f_min) first = k;  // the largest size at which f_min is reached
  }
  std::vector<Point> hull;
  for (std::size_t k = first; k < points.size(); ++k) {
    const Point& p = points[k];
    while (hull.size() >= 2) {
      const Point& a = hull[hull.size() - 2];
      const Point& b = hull.back();
      // b lies on or above the segment a → p: not on the lower hull.
      if ((b.d - a.d) * (p.f - a.f) - (b.f - a.f) * (p.d - a.d) <= 0.0) {
        hull.pop_back();
      } else {
        break;
      }
    }
    hull.push_back(p);
  }
  std::vector<std::size_t> selected;
  for (std::size_t k = 0; k < hull.size(); ++k) {
    if (k + 1 < hull.size()) {
      const double slope = (hull[k + 1].f - hull[k].f) / (hull[k + 1].d - hull[k].d);
      if (hull[k].f - slope * hull[k].d > f_min - epsilon * std::abs(f_min)) continue;
    }
    selected.push_back(hull[k].rect);
  }
  return selected;
}

// The longest sides of a rectangle: the coordinates it is sampled and trisected along.
std::vector<int> longest_sides(const Rectangle& r) {
  const int l = r.shortest_level();
  std::vector<int> dims;
  for (std::size_t i = 0; i < r.level.size(); ++i) {
    if (r.level[i] == l) dims.push_back(static_cast<int>(i));
  }
  return dims;
}

void global_note_batch(GlobalOutcome& out, std::size_t size) {
  ++out.batches;
  out.largest_batch = std::max(out.largest_batch, static_cast<int>(size));
  out.evaluations += static_cast<int>(size);
}

void global_note_best(GlobalOutcome& out, const std::vector<double>& u, double f) {
  if (out.best.empty() || f < out.objective) {
    out.best = u;
    out.objective = f;
  }
}

// ---- MLSL --------------------------------------------------------------------------------------

double critical_distance(int n, std::size_t points, double sigma) {
  const double kn = static_cast<double>(points);
  const double dn = static_cast<double>(n);
  return std::pow(std::tgamma(1.0 + dn / 2.0) * sigma * std::log(kn) / kn, 1.0 / dn) /
         std::sqrt(std::numbers::pi);
}

double unit_distance(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s);
}

// S(a) < S(b), ties broken by index: a strict order on the sample.
bool ranks_below(double fa, std::size_t a, double fb, std::size_t b) {
  return fa < fb || (fa == fb && a < b);
}

}  // namespace

GlobalOutcome direct_l(int n, const BatchObjective& objective, int max_evaluations, double xtol) {
  if (n < 1) throw std::invalid_argument("direct_l: dimensions must be >= 1");
  GlobalOutcome out;
  std::vector<Rectangle> rects;
  if (max_evaluations < 1) {
    out.stop_reason = "MAXEVAL_REACHED";
    return out;
  }
  Rectangle root{std::vector<double>(static_cast<std::size_t>(n), 0.5),
                 std::vector<int>(static_cast<std::size_t>(n), 0), 0.0};
  root.f = objective({root.centre}).at(0);
  global_note_batch(out, 1);
  global_note_best(out, root.centre, root.f);
  rects.push_back(std::move(root));
  for (;;) {
    // The batch: c ± δ e_i along the longest sides of each selected rectangle.
    std::vector<std::size_t> divide;
    for (std::size_t j : potentially_optimal(rects)) {
      if (direct_side(rects[j].shortest_level() + 1) >= xtol) divide.push_back(j);
    }
    if (divide.empty()) {
      out.stop_reason = "XTOL_REACHED";
      break;
    }
    std::vector<std::vector<double>> batch;
    for (std::size_t j : divide) {
      const double delta = direct_side(rects[j].shortest_level() + 1);
      for (int i : longest_sides(rects[j])) {
        for (const double sign : {1.0, -1.0}) {
          std::vector<double> u = rects[j].centre;
          u[static_cast<std::size_t>(i)] += sign * delta;
          batch.push_back(std::move(u));
        }
      }
    }
    if (out.evaluations + static_cast<int>(batch.size()) > max_evaluations) {
      out.stop_reason = "MAXEVAL_REACHED";
      break;
    }
    const std::vector<double> f = objective(batch);
    if (f.size() != batch.size()) throw std::logic_error("direct_l: the batch objective lost points");
    global_note_batch(out, batch.size());
    for (std::size_t k = 0; k < batch.size(); ++k) global_note_best(out, batch[k], f[k]);
    // Trisection of each rectangle, its sides in the order of w_i (ties: lower coordinate first).
    std::size_t at = 0;
    for (std::size_t j : divide) {
      const std::vector<int> dims = longest_sides(rects[j]);
      struct Side {
        double w;
        int dim;
        std::size_t plus;
      };
      std::vector<Side> sides;
      for (int i : dims) {
        sides.push_back({std::min(f[at], f[at + 1]), i, at});
        at += 2;
      }
      std::sort(sides.begin(), sides.end(), [](const Side& a, const Side& b) {
        return a.w < b.w || (a.w == b.w && a.dim < b.dim);
      });
      std::vector<int> level = rects[j].level;
      for (const Side& s : sides) {
        ++level[static_cast<std::size_t>(s.dim)];
        rects.push_back({batch[s.plus], level, f[s.plus]});
        rects.push_back({batch[s.plus + 1], level, f[s.plus + 1]});
      }
      rects[j].level = level;
    }
  }
  return out;
}

GlobalOutcome mlsl(int n, const BatchObjective& objective, const LocalSearches& local,
                   const MlslOptions& o) {
  if (n < 1) throw std::invalid_argument("mlsl: dimensions must be >= 1");
  const int population = o.population > 0 ? o.population : std::max(8, 4 * n);
  // The shift of the Sobol points (a Cranley–Patterson rotation), from the seed.
  std::mt19937_64 engine(o.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<double> shift(static_cast<std::size_t>(n));
  for (double& s : shift) s = uniform(engine);

  GlobalOutcome out;
  std::vector<std::vector<double>> sample;
  std::vector<double> values;
  std::vector<bool> started;
  std::vector<LocalMinimum> minima;
  for (;;) {
    const int size = std::min(population, o.max_evaluations - out.evaluations);
    if (size < population && !sample.empty()) {  // a whole level no longer fits
      out.stop_reason = "MAXEVAL_REACHED";
      break;
    }
    if (size < 1) {
      out.stop_reason = "MAXEVAL_REACHED";
      break;
    }
    const std::size_t first = sample.size();
    const auto sobol = study::sobol_points(static_cast<int>(first) + size, n);
    std::vector<std::vector<double>> batch(sobol.begin() + static_cast<long>(first), sobol.end());
    for (auto& u : batch) {
      for (std::size_t i = 0; i < u.size(); ++i) u[i] = std::fmod(u[i] + shift[i], 1.0);
    }
    const std::vector<double> f = objective(batch);
    if (f.size() != batch.size()) throw std::logic_error("mlsl: the batch objective lost points");
    global_note_batch(out, batch.size());
    for (std::size_t k = 0; k < batch.size(); ++k) {
      global_note_best(out, batch[k], f[k]);
      sample.push_back(batch[k]);
      values.push_back(f[k]);
      started.push_back(false);
    }
    // The starting points of this level (Rinnooy Kan & Timmer 1987, §3).
    const double r = critical_distance(n, sample.size(), o.sigma);
    std::vector<std::size_t> candidates;
    for (std::size_t i = 0; i < sample.size(); ++i) {
      if (started[i] || !std::isfinite(values[i])) continue;
      bool dominated = false;
      for (std::size_t j = 0; j < sample.size() && !dominated; ++j) {
        dominated = j != i && ranks_below(values[j], j, values[i], i) && unit_distance(sample[i], sample[j]) <= r;
      }
      for (std::size_t m = 0; m < minima.size() && !dominated; ++m) {
        dominated = minima[m].objective <= values[i] && unit_distance(sample[i], minima[m].u) <= r;
      }
      if (!dominated) candidates.push_back(i);
    }
    std::sort(candidates.begin(), candidates.end(), [&](std::size_t a, std::size_t b) {
      return ranks_below(values[a], a, values[b], b);
    });
    if (candidates.size() > static_cast<std::size_t>(o.max_local)) {
      candidates.resize(static_cast<std::size_t>(o.max_local));
    }
    const int left = o.max_evaluations - out.evaluations;
    if (candidates.empty()) continue;
    if (left < 1) {
      out.stop_reason = "MAXEVAL_REACHED";
      break;
    }
    std::vector<std::vector<double>> starts;
    for (std::size_t i : candidates) {
      starts.push_back(sample[i]);
      started[i] = true;
    }
    const int budget = std::max(1, left / static_cast<int>(starts.size()));
    const std::vector<LocalMinimum> found = local(starts, budget);
    if (found.size() != starts.size()) throw std::logic_error("mlsl: a local search was lost");
    ++out.batches;
    for (const LocalMinimum& m : found) {
      out.evaluations += m.evaluations;
      ++out.local_searches;
      if (std::isfinite(m.objective) && !m.u.empty()) {
        global_note_best(out, m.u, m.objective);
        minima.push_back(m);
      }
    }
  }
  return out;
}

}  // namespace jointhb::fit::detail
