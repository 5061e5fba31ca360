// Cost of the AFT of one 3D contact point (hb/contact_point_aft.hpp).
//
// Description: one Gaul–Mayer point (n = 0.3, proportional stiffness, p_ref = 1 MPa, λ = 2e5 1/m)
// in microslip with normal motion: δg_T = 0.3 g_max (first harmonic, elliptical, plus 2nd and 3rd
// harmonics where the basis has them), δg_N = 0.5/λ. Timed per point evaluation for H = 1, 3, 7
// and N = 64, 128, 256, with and without the Jacobian (range(2)). BM_ContactPointPeriodicOnly
// times the periodic steady state alone on the same sampled path, to split the cost between the
// tangential law and the transforms/sensitivity.
//
// Sample runs:
//   build/tests/jointhb_bench --benchmark_filter=ContactPoint
//   build/tests/jointhb_bench --benchmark_filter=ContactPoint --benchmark_min_time=0.01

#include <benchmark/benchmark.h>

#include <memory>

#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/hb/contact_point_aft.hpp"

namespace {

namespace jc = jointhb::contact;
namespace hb = jointhb::hb;

constexpr double kLambda = 2.0e5;

jc::ContactPoint point() {
  jc::ContactPointOptions o;
  o.normal = {2.0e6, kLambda, 0.0};
  o.friction_coefficient = 0.4;
  o.stiffness_ratio = 0.8;
  return jc::ContactPoint(o, std::make_shared<jc::GaulMayerLaw>(0.3));
}

hb::ContactPointReference reference(const jc::ContactPoint& p) {
  hb::ContactPointReference r;
  r.gap << 0.0, 0.0, p.options().normal.gap_at_pressure(1.0e6);
  r.traction << 0.0, 0.0, -1.0e6;
  return r;
}

Eigen::MatrixXd motion(const hb::FourierBasis& basis) {
  const double g_max = 0.4 / (0.7 * 0.8 * kLambda);
  const double a = 0.3 * g_max;
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(basis.size(), 3);
  const auto set = [&](int order, int component, double c, double s) {
    const int i = basis.cosine_index(order);
    if (i < 0) return;
    g(i, component) = c;
    g(i + 1, component) = s;
  };
  set(1, 0, a, 0.3 * a);
  set(1, 1, -0.2 * a, 0.5 * a);
  set(1, 2, 0.4 / kLambda, 0.3 / kLambda);
  set(2, 0, 0.1 * a, -0.05 * a);
  set(2, 2, -0.05 / kLambda, 0.0);
  set(3, 1, 0.07 * a, 0.0);
  return g;
}

void BM_ContactPointAft(benchmark::State& state) {
  const hb::FourierBasis basis(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const auto p = point();
  const auto ref = reference(p);
  const Eigen::MatrixXd dg = motion(basis);
  hb::ContactPointAftOptions o;
  o.jacobian = state.range(2) != 0;
  std::int64_t periods = 0;
  for (auto _ : state) {
    const auto r = hb::evaluate_contact_point(p, ref, basis, dg, o);
    periods += r.iterations;
    benchmark::DoNotOptimize(r.traction.data());
  }
  state.counters["periods"] =
      benchmark::Counter(static_cast<double>(periods), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_ContactPointAft)
    ->ArgNames({"H", "N", "jac"})
    ->ArgsProduct({{1, 3, 7}, {64, 128, 256}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);

void BM_ContactPointPeriodicOnly(benchmark::State& state) {
  const hb::FourierBasis basis(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const auto p = point();
  const auto ref = reference(p);
  const Eigen::MatrixXd dg = basis.to_time(motion(basis));
  std::vector<jc::Vec3> path(static_cast<std::size_t>(dg.rows()));
  for (Eigen::Index i = 0; i < dg.rows(); ++i) {
    path[static_cast<std::size_t>(i)] = ref.gap + dg.row(i).transpose();
  }
  jc::PeriodicStateOptions po;
  po.tolerance = 1e-14;
  po.keep_step_derivatives = state.range(2) != 0;
  for (auto _ : state) {
    const auto r = p.periodic(path, po);
    benchmark::DoNotOptimize(r.tangential.dissipation);
  }
}
BENCHMARK(BM_ContactPointPeriodicOnly)
    ->ArgNames({"H", "N", "deriv"})
    ->ArgsProduct({{7}, {64, 128, 256}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
