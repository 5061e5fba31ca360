// Damping curves and FRFs of the interface balance with the Newton–Krylov solve of the bordered
// systems (LinearSolver::newton_krylov, the drivers' default) against the dense-LU reference: the
// same points to the Newton tolerance, with fewer factorisations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "../hb/interface_test_model.hpp"
#include "jointhb/continuation/interface_response.hpp"

namespace jointhb::continuation {
namespace {

using namespace jointhb::hb::testing;

// Largest relative difference between two point sets: unknowns relative to their ∞-norm.
template <class Point>
double worst_difference(const std::vector<Point>& a, const std::vector<Point>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    worst = std::max(worst, (a[i].unknowns - b[i].unknowns).template lpNorm<Eigen::Infinity>() /
                                a[i].unknowns.template lpNorm<Eigen::Infinity>());
  return worst;
}

TEST(InterfaceNewtonKrylov, BackboneMatchesDenseLu) {
  for (bool gm : {true, false}) {
    const Structure s = make_structure(6, 4, 9, 0.0, gm);
    const hb::InterfaceModel model = make_model(s, 8, gm);
    InterfaceBackboneOptions o;
    o.mode.balance = {.harmonics = 3, .time_samples = 64};
    o.log10_amplitude_start = gm ? -9.0 : -7.0;
    o.log10_amplitude_end = -3.5;
    ASSERT_EQ(o.continuation.linear_solver, LinearSolver::newton_krylov);  // the default
    o.matrix_free = false;  // dense Jacobian, lagged LU
    o.dense_below = 0;      // the solver itself, not the small-curve policy (dense LU up to 300 unknowns)
    const InterfaceBackbone krylov = trace_interface_backbone(model, o);
    o.continuation.linear_solver = LinearSolver::dense_lu;
    const InterfaceBackbone dense = trace_interface_backbone(model, o);
    ASSERT_TRUE(dense.completed()) << dense.message;
    ASSERT_TRUE(krylov.completed()) << krylov.message;
    const double worst = worst_difference(dense.points, krylov.points);
    const auto& a = dense.points.back().state;
    const auto& b = krylov.points.back().state;
    std::printf("%s: dense %zu points %d Newton %d LU; krylov %zu points %d Newton %d LU %d GMRES; "
                "worst %.2e, last ω %.3e ζ %.3e relative\n",
                gm ? "Gaul-Mayer" : "Jenkins", dense.points.size(), dense.newton_iterations,
                dense.timings.factorisations, krylov.points.size(), krylov.newton_iterations,
                krylov.timings.factorisations, krylov.timings.krylov_iterations, worst,
                std::abs(a.omega / b.omega - 1.0), std::abs(a.damping_ratio / b.damping_ratio - 1.0));
    // The last point lies on λ_end in both runs, whatever their paths.
    EXPECT_EQ(a.amplitude, b.amplitude);
    EXPECT_LT(std::abs(a.omega / b.omega - 1.0), 1e-10);
    EXPECT_LT(std::abs(a.damping_ratio / b.damping_ratio - 1.0), 1e-8);
    EXPECT_LT((dense.points.back().unknowns - krylov.points.back().unknowns).lpNorm<Eigen::Infinity>() /
                  dense.points.back().unknowns.lpNorm<Eigen::Infinity>(), 1e-8);
    if (dense.points.size() == krylov.points.size()) {
      EXPECT_LT(worst, 1e-8);
    }
    EXPECT_LT(krylov.timings.factorisations, dense.timings.factorisations / 2);
  }
}

// Matrix-free (the default with newton_krylov): products from the point blocks, the harmonic
// block-Jacobi preconditioner, no U × U matrix; the same curve to the Newton tolerance.
TEST(InterfaceMatrixFree, BackboneAndFrfMatchDenseLu) {
  const Structure s = make_structure(6, 4, 9, 0.0, false);
  const hb::InterfaceModel model = make_model(s, 8, false);
  InterfaceBackboneOptions o;
  o.mode.balance = {.harmonics = 3, .time_samples = 64};
  o.log10_amplitude_start = -7.0;
  o.log10_amplitude_end = -3.5;
  o.continuation.linear_solver = LinearSolver::dense_lu;
  const InterfaceBackbone dense = trace_interface_backbone(model, o);
  o.continuation.linear_solver = LinearSolver::newton_krylov;
  EXPECT_TRUE(o.matrix_free);  // the default
  o.dense_below = 0;           // the matrix-free path, not the small-curve policy
  EXPECT_EQ(o.preconditioner, hb::InterfacePreconditioner::point_local);  // the default
  const InterfaceBackbone free = trace_interface_backbone(model, o);
  ASSERT_TRUE(dense.completed()) << dense.message;
  {  // the harmonic block-Jacobi preconditioner, lagged until GMRES fails: the same curve
    InterfaceBackboneOptions h = o;
    h.preconditioner = hb::InterfacePreconditioner::harmonic_blocks;
    h.continuation.preconditioner_refresh = PreconditionerRefresh::on_failure;
    const InterfaceBackbone harmonic = trace_interface_backbone(model, h);
    ASSERT_TRUE(harmonic.completed()) << harmonic.message;
    std::printf("backbone, harmonic blocks: %d preconditioners, %d GMRES; worst %.2e against dense LU\n",
                harmonic.timings.factorisations, harmonic.timings.krylov_iterations,
                worst_difference(dense.points, harmonic.points));
    EXPECT_LT(worst_difference(dense.points, harmonic.points), 1e-8);
  }
  ASSERT_TRUE(free.completed()) << free.message;
  const auto& a = dense.points.back();
  const auto& b = free.points.back();
  const double last = (a.unknowns - b.unknowns).lpNorm<Eigen::Infinity>() / a.unknowns.lpNorm<Eigen::Infinity>();
  std::printf("backbone: dense %zu points %d Newton; matrix-free %zu points %d Newton, %d preconditioners, %d GMRES; "
              "last point %.2e, worst %.2e\n", dense.points.size(), dense.newton_iterations, free.points.size(),
              free.newton_iterations, free.timings.factorisations, free.timings.krylov_iterations, last,
              worst_difference(dense.points, free.points));
  EXPECT_EQ(a.state.amplitude, b.state.amplitude);
  EXPECT_LT(last, 1e-8);
  EXPECT_GT(free.timings.products, 0.0);

  const double w1 = std::sqrt(model.omega2[0]);
  InterfaceFrfOptions f;
  f.omega_start = 0.9 * w1;
  f.omega_end = 1.05 * w1;
  f.load_amplitude = 20.0;
  f.balance = {.harmonics = 3, .time_samples = 64};
  f.continuation.max_step = 0.05;
  f.continuation.linear_solver = LinearSolver::dense_lu;
  const InterfaceFrf frf_dense = trace_interface_frf(model, f);
  f.continuation.linear_solver = LinearSolver::newton_krylov;
  const InterfaceFrf frf_free = trace_interface_frf(model, f);
  ASSERT_TRUE(frf_dense.completed()) << frf_dense.message;
  ASSERT_TRUE(frf_free.completed()) << frf_free.message;
  std::printf("FRF: dense %zu points; matrix-free %zu points, %d preconditioners, %d GMRES; worst %.2e\n",
              frf_dense.points.size(), frf_free.points.size(), frf_free.timings.factorisations,
              frf_free.timings.krylov_iterations, worst_difference(frf_dense.points, frf_free.points));
  EXPECT_LT(std::abs(frf_dense.points.back().amplitude_h1 / frf_free.points.back().amplitude_h1 - 1.0), 1e-8);
  EXPECT_GT(frf_free.timings.products, 0.0);
  EXPECT_EQ(frf_dense.timings.products, 0.0);  // dense_lu ignores matrix_free
}

TEST(InterfaceNewtonKrylov, FrfMatchesDenseLu) {
  const Structure s = make_structure(6, 4, 9, 0.0, false);
  const hb::InterfaceModel model = make_model(s, 10, false);
  const double w1 = std::sqrt(model.omega2[0]);
  InterfaceFrfOptions o;
  o.omega_start = 0.9 * w1;
  o.omega_end = 1.05 * w1;
  o.load_amplitude = 20.0;
  o.balance = {.harmonics = 3, .time_samples = 64};
  o.continuation.max_step = 0.05;
  o.matrix_free = false;  // dense Jacobian, lagged LU
  const InterfaceFrf krylov = trace_interface_frf(model, o);
  o.continuation.linear_solver = LinearSolver::dense_lu;
  const InterfaceFrf dense = trace_interface_frf(model, o);
  ASSERT_TRUE(dense.completed()) << dense.message;
  ASSERT_TRUE(krylov.completed()) << krylov.message;
  const double worst = worst_difference(dense.points, krylov.points);
  std::printf("FRF: dense %zu points %d LU; krylov %zu points %d LU %d GMRES; worst %.2e\n", dense.points.size(),
              dense.timings.factorisations, krylov.points.size(), krylov.timings.factorisations,
              krylov.timings.krylov_iterations, worst);
  EXPECT_EQ(dense.points.back().omega, krylov.points.back().omega);
  EXPECT_LT(std::abs(dense.points.back().amplitude_h1 / krylov.points.back().amplitude_h1 - 1.0), 1e-8);
  if (dense.points.size() == krylov.points.size()) {
    EXPECT_LT(worst, 1e-8);
  }
  int slipping = 0;
  for (const auto& p : dense.points) slipping = std::max(slipping, p.slipping_points);
  EXPECT_GT(slipping, 0);
  EXPECT_LT(krylov.timings.factorisations, dense.timings.factorisations / 2);
}

}  // namespace
}  // namespace jointhb::continuation
