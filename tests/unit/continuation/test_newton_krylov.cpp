// The Newton–Krylov linear solver of the continuation (Options::linear_solver = newton_krylov:
// GMRES preconditioned by the LU of an earlier bordered matrix, docs/continuation.md §2) against
// the dense LU reference on a branch with folds: the same points to the Newton tolerance, with
// fewer factorisations; and GMRES itself (support/gmres.hpp) against a direct solve.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>

#include "../../../src/support/gmres.hpp"
#include "jointhb/continuation/pseudo_arclength.hpp"

namespace jcont = jointhb::continuation;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

// N weakly coupled Duffing oscillators at one harmonic, x = (a_1, b_1, …, a_N, b_N), λ = Ω:
//   (w_i² − Ω² + ¾γA_i²) a_i + 2ζΩ b_i + ε (L a)_i − F = 0
//   (w_i² − Ω² + ¾γA_i²) b_i − 2ζΩ a_i + ε (L b)_i     = 0,   L the chain Laplacian.
// Hardening (γ > 0) with small damping: the response curves have two folds.
jcont::ResidualFunction duffing_chain(int n_osc) {
  return [n_osc](const VectorXd& x, double omega, bool jacobian) {
    const double zeta = 0.02, gamma = 1.0, force = 0.05, eps = 0.05;
    const int n = 2 * n_osc;
    jcont::Evaluation e;
    e.residual = VectorXd::Zero(n);
    if (jacobian) {
      e.d_state = MatrixXd::Zero(n, n);
      e.d_parameter = VectorXd::Zero(n);
    }
    for (int i = 0; i < n_osc; ++i) {
      const double w = 1.0 + 0.005 * i;
      const double a = x(2 * i), b = x(2 * i + 1), a2 = a * a + b * b;
      const double k = w * w - omega * omega + 0.75 * gamma * a2, c = 2.0 * zeta * omega;
      e.residual(2 * i) = k * a + c * b - force;
      e.residual(2 * i + 1) = k * b - c * a;
      for (int j : {i - 1, i + 1}) {
        if (j < 0 || j >= n_osc) continue;
        for (int d = 0; d < 2; ++d) {
          e.residual(2 * i + d) += eps * (x(2 * i + d) - x(2 * j + d));
          if (jacobian) {
            e.d_state(2 * i + d, 2 * i + d) += eps;
            e.d_state(2 * i + d, 2 * j + d) -= eps;
          }
        }
      }
      if (jacobian) {
        e.d_state(2 * i, 2 * i) += k + 1.5 * gamma * a * a;
        e.d_state(2 * i, 2 * i + 1) += c + 1.5 * gamma * a * b;
        e.d_state(2 * i + 1, 2 * i) += -c + 1.5 * gamma * a * b;
        e.d_state(2 * i + 1, 2 * i + 1) += k + 1.5 * gamma * b * b;
        e.d_parameter(2 * i) = -2.0 * omega * a + 2.0 * zeta * b;
        e.d_parameter(2 * i + 1) = -2.0 * omega * b - 2.0 * zeta * a;
      }
    }
    return e;
  };
}

TEST(NewtonKrylov, SamePointsAsDenseLuThroughFoldsWithFewerFactorisations) {
  const int n_osc = 12;
  jcont::Options o;
  o.parameter_start = 0.5;
  o.parameter_end = 2.0;
  o.initial_step = 0.02;
  o.max_step = 0.1;
  o.max_points = 2000;
  o.residual_tolerance = 1e-12;
  const VectorXd x0 = VectorXd::Zero(2 * n_osc);
  const jcont::Result dense = jcont::trace(duffing_chain(n_osc), x0, o);
  o.linear_solver = jcont::LinearSolver::newton_krylov;
  const jcont::Result krylov = jcont::trace(duffing_chain(n_osc), x0, o);
  ASSERT_TRUE(dense.completed()) << dense.message;
  ASSERT_TRUE(krylov.completed()) << krylov.message;
  int folds = 0;
  for (const auto& p : dense.points) folds += p.fold ? 1 : 0;
  std::printf("dense: %zu points, %d Newton, %d LU; newton_krylov: %zu points, %d Newton, %d LU, %d GMRES; %d folds\n",
              dense.points.size(), dense.corrector_iterations, dense.factorisations, krylov.points.size(),
              krylov.corrector_iterations, krylov.factorisations, krylov.krylov_iterations, folds);
  EXPECT_GE(folds, 2);
  ASSERT_EQ(dense.points.size(), krylov.points.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < dense.points.size(); ++i) {
    const auto& a = dense.points[i];
    const auto& b = krylov.points[i];
    worst = std::max(worst, std::abs(a.lambda - b.lambda) / std::abs(a.lambda));
    worst = std::max(worst, (a.x - b.x).lpNorm<Eigen::Infinity>() / a.x.lpNorm<Eigen::Infinity>());
  }
  std::printf("worst relative difference %.2e\n", worst);
  EXPECT_LT(worst, 1e-8);
  EXPECT_EQ(krylov.points.back().lambda, o.parameter_end);
  EXPECT_GT(krylov.krylov_iterations, 0);
  EXPECT_LT(krylov.factorisations, dense.factorisations / 3);
}

// The matrix-free interface of the continuation (Evaluation::d_state_product and
// make_preconditioner, the bordered preconditioner by block elimination): the Duffing chain's
// Jacobian given only as a product, preconditioned by its diagonal (Jacobi) — far from exact,
// so restarts and rebuilds are exercised — gives the dense LU's points.
TEST(NewtonKrylov, MatrixFreeJacobianGivesTheDenseLuPoints) {
  const int n_osc = 12;
  jcont::Options o;
  o.parameter_start = 0.5;
  o.parameter_end = 2.0;
  o.initial_step = 0.02;
  o.max_step = 0.1;
  o.max_points = 2000;
  o.residual_tolerance = 1e-12;
  const VectorXd x0 = VectorXd::Zero(2 * n_osc);
  const jcont::ResidualFunction dense_residual = duffing_chain(n_osc);
  const jcont::Result dense = jcont::trace(dense_residual, x0, o);
  int products = 0;
  const jcont::ResidualFunction free_residual = [&](const VectorXd& x, double omega, bool jacobian) {
    jcont::Evaluation e = dense_residual(x, omega, jacobian);
    if (jacobian) {
      const MatrixXd j = std::move(e.d_state);
      e.d_state.resize(0, 0);
      e.d_state_product = [j, &products](const VectorXd& v) {
        ++products;
        return VectorXd(j * v);
      };
      e.make_preconditioner = [d = VectorXd(j.diagonal())]() -> jcont::LinearOperator {
        return [d](const VectorXd& v) { return VectorXd(v.cwiseQuotient(d)); };
      };
    }
    return e;
  };
  // dense_lu cannot use a matrix-free Jacobian
  EXPECT_THROW((void)jcont::trace(free_residual, x0, o), std::logic_error);
  o.linear_solver = jcont::LinearSolver::newton_krylov;
  o.krylov_max_iterations = 30;
  const jcont::Result free = jcont::trace(free_residual, x0, o);
  ASSERT_TRUE(dense.completed()) << dense.message;
  ASSERT_TRUE(free.completed()) << free.message;
  std::printf("matrix-free: %zu points (dense %zu), %d preconditioner builds, %d GMRES, %d products\n",
              free.points.size(), dense.points.size(), free.factorisations, free.krylov_iterations, products);
  ASSERT_EQ(dense.points.size(), free.points.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < dense.points.size(); ++i)
    worst = std::max(worst, (dense.points[i].x - free.points[i].x).lpNorm<Eigen::Infinity>() /
                                dense.points[i].x.lpNorm<Eigen::Infinity>());
  std::printf("worst relative difference %.2e\n", worst);
  EXPECT_LT(worst, 1e-8);
  EXPECT_GT(products, free.krylov_iterations);
}

TEST(NewtonKrylov, RejectsBadOptions) {
  jcont::Options o;
  o.krylov_max_iterations = 0;
  EXPECT_NE(o.validate(2).find("krylov_max_iterations"), std::string::npos);
  o = {};
  o.krylov_tolerance = 1e-3;
  EXPECT_NE(o.validate(2).find("krylov_tolerance"), std::string::npos);
  o = {};
  o.linear_solver = static_cast<jcont::LinearSolver>(7);
  EXPECT_NE(o.validate(2).find("linear_solver"), std::string::npos);
}

TEST(Gmres, MatchesDirectSolve) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  const int n = 60;
  MatrixXd a = MatrixXd::Identity(n, n) * 8.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) a(i, j) += g(rng);
  VectorXd b(n);
  for (int i = 0; i < n; ++i) b(i) = g(rng);
  const VectorXd exact = a.partialPivLu().solve(b);
  const auto apply = [&](const VectorXd& v) { return VectorXd(a * v); };
  // No preconditioner: at most n iterations in exact arithmetic.
  VectorXd z;
  const auto plain = jointhb::support::gmres(apply, [](const VectorXd& v) { return v; }, b, n, 1e-13, z);
  EXPECT_TRUE(plain.converged);
  EXPECT_LT((z - exact).norm() / exact.norm(), 1e-11);
  // An exact preconditioner: one iteration.
  const Eigen::PartialPivLU<MatrixXd> lu(a);
  const auto exact_pc = jointhb::support::gmres(apply, [&](const VectorXd& v) { return VectorXd(lu.solve(v)); }, b, 5, 1e-13, z);
  EXPECT_TRUE(exact_pc.converged);
  EXPECT_EQ(exact_pc.iterations, 1);
  EXPECT_LT((z - exact).norm() / exact.norm(), 1e-13);
  // Too few iterations: not converged, and it says so.
  const auto few = jointhb::support::gmres(apply, [](const VectorXd& v) { return v; }, b, 3, 1e-13, z);
  EXPECT_FALSE(few.converged);
  EXPECT_GT(few.residual, 1e-6);
}

}  // namespace
