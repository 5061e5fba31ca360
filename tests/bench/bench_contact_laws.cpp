// Throughput of the tangential contact laws and of the periodic steady-state solve.
//
// Description: law evaluations per second on one core, on a realistic sampled path: a harmonic
// slip g_T(θ) = a cos θ + 0.2 a cos(3θ + φ) (2D: an ellipse plus its third harmonic), 64 samples
// per period, with the amplitude of each period drawn log-uniformly in a/g_max ∈ [1e-3, 5] so that
// sticking, microslip and gross slip all occur. The increments are precomputed; only the law is
// timed. items/s = law evaluations/s. The periodic solve is timed per call for N = 64, 256, 1024
// samples in three regimes (a/g_max = 1e-3, 0.3, 3); items/s = samples/s, and the counter
// `law_steps` gives the law evaluations per second including the Newton/fixed-point periods.
//
// Sample runs:
//   build/tests/jointhb_bench                                  # full run (figures in docs/)
//   build/tests/jointhb_bench --benchmark_min_time=0.01        # smoke test (ctest bench.smoke)
//   build/tests/jointhb_bench --benchmark_filter=Periodic

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstddef>
#include <numbers>
#include <random>
#include <vector>

#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/jenkins_law.hpp"
#include "jointhb/contact/periodic_state.hpp"
#include "jointhb/contact/tangential_law.hpp"

namespace {

using jointhb::contact::GaulMayerLaw;
using jointhb::contact::JenkinsLaw;
using jointhb::contact::PeriodicPath;
using jointhb::contact::TangentialLaw;
using jointhb::contact::TangentialLimits;
using jointhb::contact::Vec2;

// μ F_N = 0.3 · 100 N, k_T0 = 1e6 N/m: g_max = F_s/((1-n)k) = 45 µm for n = 1/3.
constexpr double kSlipLimit = 30.0;
constexpr double kStiffness = 1.0e6;
constexpr double kExponent = 1.0 / 3.0;
constexpr int kSamplesPerPeriod = 64;
constexpr int kPeriods = 256;

TangentialLimits limits() { return {kSlipLimit, kStiffness}; }

double full_slip_span() { return kSlipLimit / ((1.0 - kExponent) * kStiffness); }

struct Path {
  std::vector<double> increments;   // 1D: Δg along x
  std::vector<Vec2> increments_2d;  // 2D: Δg in the tangential plane
};

// Deterministic "random-ish" multi-amplitude harmonic path (fixed seed).
const Path& harmonic_path() {
  static const Path path = [] {
    std::mt19937_64 rng(20240521);
    std::uniform_real_distribution<double> log_ratio(std::log(1e-3), std::log(5.0));
    std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
    std::uniform_real_distribution<double> aspect(0.2, 1.0);
    Path p;
    const double g_max = full_slip_span();
    double x_prev = 0.0;
    Vec2 g_prev = Vec2::Zero();
    for (int period = 0; period < kPeriods; ++period) {
      const double a = g_max * std::exp(log_ratio(rng));
      const double b = a * aspect(rng);
      const double phi = angle(rng);
      for (int i = 1; i <= kSamplesPerPeriod; ++i) {
        const double theta = 2.0 * std::numbers::pi * i / kSamplesPerPeriod;
        const double x = a * std::cos(theta) + 0.2 * a * std::cos(3.0 * theta + phi);
        const Vec2 g(x, b * std::sin(theta + phi));
        p.increments.push_back(x - x_prev);
        p.increments_2d.push_back(g - g_prev);
        x_prev = x;
        g_prev = g;
      }
    }
    return p;
  }();
  return path;
}

void run_scalar(benchmark::State& state, const TangentialLaw& law) {
  const std::vector<double>& increments = harmonic_path().increments;
  const TangentialLimits lim = limits();
  double f = 0.0;
  for (auto _ : state) {
    for (const double dg : increments) {
      f = law.scalar_step(f, dg, lim).force;
    }
    benchmark::DoNotOptimize(f);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(increments.size()));
}

void run_plane(benchmark::State& state, const TangentialLaw& law) {
  const std::vector<Vec2>& increments = harmonic_path().increments_2d;
  const TangentialLimits lim = limits();
  Vec2 t = Vec2::Zero();
  for (auto _ : state) {
    for (const Vec2& dg : increments) {
      t = law.step(t, dg, lim).traction;
    }
    benchmark::DoNotOptimize(t.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(increments.size()));
}

void BM_GaulMayer_ScalarStep(benchmark::State& state) {
  const GaulMayerLaw law(kExponent);
  run_scalar(state, law);
}
BENCHMARK(BM_GaulMayer_ScalarStep);

void BM_GaulMayer_Step2D(benchmark::State& state) {
  const GaulMayerLaw law(kExponent);
  run_plane(state, law);
}
BENCHMARK(BM_GaulMayer_Step2D);

void BM_Jenkins_ScalarStep(benchmark::State& state) {
  const JenkinsLaw law;
  run_scalar(state, law);
}
BENCHMARK(BM_Jenkins_ScalarStep);

void BM_Jenkins_Step2D(benchmark::State& state) {
  const JenkinsLaw law;
  run_plane(state, law);
}
BENCHMARK(BM_Jenkins_Step2D);

// Periodic steady state on an elliptical 2D path (b = a/2) plus a third harmonic; range(0) = N,
// range(1) = regime: 0 → a/g_max = 1e-3 (near-sticking, slow contraction), 1 → 0.3 (microslip),
// 2 → 3 (gross slip).
void BM_PeriodicState(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const double ratios[] = {1e-3, 0.3, 3.0};
  const double a = ratios[state.range(1)] * full_slip_span();
  PeriodicPath path;
  path.slip.resize(n);
  path.limits.assign(n, limits());
  for (std::size_t i = 0; i < n; ++i) {
    const double theta = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    path.slip[i] = Vec2(a * std::cos(theta) + 0.2 * a * std::cos(3.0 * theta + 0.4),
                        0.5 * a * std::sin(theta + 0.4));
  }
  const GaulMayerLaw law(kExponent);
  std::int64_t periods = 0;
  bool converged = true;
  for (auto _ : state) {
    const auto result = jointhb::contact::solve_periodic_state(law, path);
    periods += result.iterations;
    converged = converged && result.termination == jointhb::Termination::converged;
    benchmark::DoNotOptimize(result.dissipation);
  }
  if (!converged) {
    state.SkipWithError("solve_periodic_state did not converge");
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
  state.counters["periods"] =
      benchmark::Counter(static_cast<double>(periods), benchmark::Counter::kAvgIterations);
  state.counters["law_steps"] = benchmark::Counter(
      static_cast<double>(periods) * static_cast<double>(n), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PeriodicState)
    ->ArgNames({"N", "regime"})
    ->ArgsProduct({{64, 256, 1024}, {0, 1, 2}})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
