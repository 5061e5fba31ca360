// compute_modes (ARPACK shift-invert with a CHOLMOD factor) against closed forms and Eigen's
// dense generalized eigensolver.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "jointhb/modal/modes.hpp"

namespace {

using jointhb::modal::compute_modes;
using jointhb::modal::ModalOptions;
using jointhb::modal::ModalResult;
using SpMat = Eigen::SparseMatrix<double>;

constexpr double kStiffness = 1.0e6;  // k [N/m]
constexpr double kMass = 0.5;         // m [kg]

// n equal masses in a line joined by equal springs; `grounded`: a spring from the first mass to
// the ground (fixed-free chain), else free-free.
void spring_mass_chain(int n, bool grounded, SpMat& K, SpMat& M) {
  std::vector<Eigen::Triplet<double>> k_entries, m_entries;
  for (int i = 0; i < n; ++i) {
    double diagonal = (i + 1 < n ? kStiffness : 0.0) + (i > 0 || grounded ? kStiffness : 0.0);
    k_entries.emplace_back(i, i, diagonal);
    if (i + 1 < n) {
      k_entries.emplace_back(i, i + 1, -kStiffness);
      k_entries.emplace_back(i + 1, i, -kStiffness);
    }
    m_entries.emplace_back(i, i, kMass);
  }
  K.resize(n, n);
  M.resize(n, n);
  K.setFromTriplets(k_entries.begin(), k_entries.end());
  M.setFromTriplets(m_entries.begin(), m_entries.end());
}

// A bar of linear elements with random lengths and properties and the consistent mass matrix
// (Ke = EA/h [1 −1; −1 1], Me = ρAh/6 [2 1; 1 2]); `fixed`: node 0 removed (fixed-free).
void bar_with_consistent_mass(int elements, bool fixed, SpMat& K, SpMat& M) {
  std::mt19937 random(2024);
  std::uniform_real_distribution<double> factor(0.7, 1.3);
  const int offset = fixed ? 1 : 0;
  const int n = elements + 1 - offset;
  std::vector<Eigen::Triplet<double>> k_entries, m_entries;
  for (int e = 0; e < elements; ++e) {
    const double h = 0.01 * factor(random);
    const double ea = 2.1e11 * 1e-4 * factor(random);
    const double rho_a = 7850.0 * 1e-4 * factor(random);
    const double ke[2][2] = {{ea / h, -ea / h}, {-ea / h, ea / h}};
    const double me[2][2] = {{rho_a * h / 3, rho_a * h / 6}, {rho_a * h / 6, rho_a * h / 3}};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        const int i = e + a - offset, j = e + b - offset;
        if (i < 0 || j < 0) continue;
        k_entries.emplace_back(i, j, ke[a][b]);
        m_entries.emplace_back(i, j, me[a][b]);
      }
  }
  K.resize(n, n);
  M.resize(n, n);
  K.setFromTriplets(k_entries.begin(), k_entries.end());
  M.setFromTriplets(m_entries.begin(), m_entries.end());
}

void expect_mass_orthonormal(const ModalResult& result, const SpMat& M, double tolerance) {
  const Eigen::MatrixXd gram = result.shapes.transpose() * (M * result.shapes);
  const auto m = gram.rows();
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(m, m)).cwiseAbs().maxCoeff(), tolerance);
}

TEST(ModalArpack, FixedFreeChainMatchesItsClosedForm) {
  // λ_j = (4k/m) sin²((2j − 1)π / (2(2n + 1))), j = 1..n.
  const int n = 400;
  SpMat K, M;
  spring_mass_chain(n, true, K, M);
  ModalOptions options;
  options.count = 12;
  const ModalResult result = compute_modes(K, M, options);
  ASSERT_EQ(result.termination, jointhb::Termination::converged) << result.message;
  ASSERT_EQ(result.eigenvalues.size(), 12);
  for (int j = 1; j <= 12; ++j) {
    const double s = std::sin((2 * j - 1) * std::numbers::pi / (2.0 * (2 * n + 1)));
    const double exact = 4.0 * kStiffness / kMass * s * s;
    EXPECT_NEAR(result.eigenvalues(j - 1) / exact, 1.0, 1e-11) << "mode " << j;
    EXPECT_NEAR(result.frequencies_hz(j - 1), std::sqrt(exact) / (2 * std::numbers::pi),
                1e-10 * std::sqrt(exact));
  }
  EXPECT_LT(result.residuals.maxCoeff(), 1e-8);
  EXPECT_LT(result.backward_errors.maxCoeff(), 1e-12);
  expect_mass_orthonormal(result, M, 1e-10);
  EXPECT_GT(result.iterations, 0);
  EXPECT_GT(result.operator_applications, 0);
  EXPECT_TRUE(result.message.empty());
  std::printf("  %s\n", result.brief().c_str());
}

TEST(ModalArpack, ConsistentMassBarMatchesDenseGeneralizedEigensolver) {
  SpMat K, M;
  bar_with_consistent_mass(150, true, K, M);
  const Eigen::MatrixXd k_dense = K.toDense(), m_dense = M.toDense();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(k_dense, m_dense);
  ModalOptions options;
  options.count = 10;
  options.shift = -1e3;
  const ModalResult result = compute_modes(K, M, options);
  ASSERT_EQ(result.termination, jointhb::Termination::converged) << result.message;
  for (int j = 0; j < 10; ++j) {
    EXPECT_NEAR(result.eigenvalues(j) / dense.eigenvalues()(j), 1.0, 1e-10) << "mode " << j;
    // Same M-normalised vector up to sign.
    const Eigen::VectorXd reference = dense.eigenvectors().col(j);
    const double overlap = result.shapes.col(j).dot(M * reference);
    EXPECT_NEAR(std::abs(overlap), 1.0, 1e-9) << "mode " << j;
  }
  EXPECT_LT(result.residuals.maxCoeff(), 1e-8);
  expect_mass_orthonormal(result, M, 1e-10);
}

TEST(ModalArpack, FreeFreeChainGivesTheRigidModeAndTheElasticOnes) {
  // Singular K: λ_j = (4k/m) sin²(jπ / (2n)), j = 0..n−1, λ_0 = 0 the rigid translation.
  const int n = 300;
  SpMat K, M;
  spring_mass_chain(n, false, K, M);
  ModalOptions options;
  options.count = 8;  // default shift −(2π·1 Hz)²
  const ModalResult result = compute_modes(K, M, options);
  ASSERT_EQ(result.termination, jointhb::Termination::converged) << result.message;
  const double lambda_1 =
      4.0 * kStiffness / kMass * std::pow(std::sin(std::numbers::pi / (2 * n)), 2);
  EXPECT_LT(std::abs(result.eigenvalues(0)), 1e-8 * lambda_1);
  EXPECT_LT(std::abs(result.frequencies_hz(0)), 1e-3);
  // The rigid mode is the uniform translation, mass-normalised: φ = 1/√(n m).
  EXPECT_LT((result.shapes.col(0).array() - 1.0 / std::sqrt(n * kMass)).abs().maxCoeff(), 1e-9);
  for (int j = 1; j < 8; ++j) {
    const double s = std::sin(j * std::numbers::pi / (2.0 * n));
    EXPECT_NEAR(result.eigenvalues(j) / (4.0 * kStiffness / kMass * s * s), 1.0, 1e-10)
        << "mode " << j;
  }
  EXPECT_LT(result.residuals.maxCoeff(), 1e-8);
  expect_mass_orthonormal(result, M, 1e-10);
}

TEST(ModalArpack, FreeFreeBarWithConsistentMassMatchesDense) {
  SpMat K, M;
  bar_with_consistent_mass(120, false, K, M);
  const Eigen::MatrixXd k_dense = K.toDense(), m_dense = M.toDense();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(k_dense, m_dense);
  ModalOptions options;
  options.count = 6;
  const ModalResult result = compute_modes(K, M, options);
  ASSERT_EQ(result.termination, jointhb::Termination::converged) << result.message;
  EXPECT_LT(std::abs(result.eigenvalues(0)), 1e-8 * dense.eigenvalues()(1));
  for (int j = 1; j < 6; ++j) {
    EXPECT_NEAR(result.eigenvalues(j) / dense.eigenvalues()(j), 1.0, 1e-10) << "mode " << j;
    EXPECT_LT(result.residuals(j), 1e-8) << "mode " << j;
  }
  // The rigid mode's residual against |σ| sits at the round-off floor of Kφ, ~ε‖K‖/(‖M‖|σ|);
  // its backward error is at round-off like every other mode's.
  EXPECT_LT(result.backward_errors.maxCoeff(), 1e-14);
  std::printf("  rigid mode: lambda = %.3g, residual %.2g, backward error %.2g\n",
              result.eigenvalues(0), result.residuals(0), result.backward_errors(0));
}

TEST(ModalArpack, SameInputGivesTheSameOutputBitForBit) {
  SpMat K, M;
  bar_with_consistent_mass(200, false, K, M);
  ModalOptions options;
  options.count = 7;
  const ModalResult first = compute_modes(K, M, options);
  const ModalResult second = compute_modes(K, M, options);
  ASSERT_EQ(first.termination, jointhb::Termination::converged);
  EXPECT_EQ(first.iterations, second.iterations);
  EXPECT_EQ((first.eigenvalues - second.eigenvalues).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((first.shapes - second.shapes).cwiseAbs().maxCoeff(), 0.0);
}

TEST(ModalArpack, ReportsAShiftAboveTheLowestEigenvalueAsAFailedFactorization) {
  SpMat K, M;
  spring_mass_chain(50, true, K, M);
  ModalOptions options;
  options.count = 3;
  options.shift = 4.0 * kStiffness / kMass * 0.5;  // well inside the spectrum
  const ModalResult result = compute_modes(K, M, options);
  EXPECT_EQ(result.termination, jointhb::Termination::failed);
  EXPECT_NE(result.message.find("not positive definite"), std::string::npos) << result.message;
  EXPECT_EQ(result.eigenvalues.size(), 0);
}

TEST(ModalArpack, ReportsTooFewIterationsAsNotConverged) {
  SpMat K, M;
  spring_mass_chain(3000, true, K, M);
  ModalOptions options;
  options.count = 10;
  options.ncv = 11;
  options.max_iterations = 1;
  const ModalResult result = compute_modes(K, M, options);
  EXPECT_EQ(result.termination, jointhb::Termination::no_convergence);
  EXPECT_NE(result.message.find("modes converged"), std::string::npos) << result.message;
  EXPECT_LT(result.eigenvalues.size(), 10);
}

// The status convention (contact/termination.hpp) on the three ways compute_modes ends.
TEST(ModalArpack, StatusSaysEachTermination) {
  SpMat K, M;
  spring_mass_chain(50, true, K, M);
  ModalOptions options;
  options.count = 3;
  const ModalResult good = compute_modes(K, M, options);
  ASSERT_EQ(good.termination, jointhb::Termination::converged) << good.message;
  EXPECT_EQ(good.status().termination, jointhb::Termination::converged);
  EXPECT_TRUE(good.status().ok());
  EXPECT_EQ(good.status().brief(), "converged: 3 of 3 modes converged");  // message is empty

  options.shift = 4.0 * kStiffness / kMass * 0.5;  // inside the spectrum: K − σM indefinite
  const ModalResult failed = compute_modes(K, M, options);
  ASSERT_EQ(failed.termination, jointhb::Termination::failed);
  EXPECT_EQ(failed.status().termination, jointhb::Termination::failed);
  EXPECT_EQ(failed.status().message, failed.message);

  spring_mass_chain(3000, true, K, M);
  options = ModalOptions{};
  options.count = 10;
  options.ncv = 11;
  options.max_iterations = 1;
  const ModalResult short_run = compute_modes(K, M, options);
  ASSERT_EQ(short_run.termination, jointhb::Termination::no_convergence);
  EXPECT_EQ(short_run.status().termination, jointhb::Termination::no_convergence);
  EXPECT_FALSE(short_run.status().ok());
  EXPECT_EQ(short_run.status().brief(), "no_convergence: " + short_run.message);
}

TEST(ModalArpack, RejectsInvalidOptionsAndMatricesNamingTheField) {
  SpMat K, M;
  spring_mass_chain(10, true, K, M);
  ModalOptions options;
  options.count = 0;
  EXPECT_NE(options.validate().find("count"), std::string::npos);
  EXPECT_THROW((void)compute_modes(K, M, options), std::invalid_argument);
  options.count = 10;  // = n
  EXPECT_THROW((void)compute_modes(K, M, options), std::invalid_argument);
  options.count = 3;
  options.ncv = 3;
  EXPECT_NE(options.validate().find("ncv"), std::string::npos);
  options.ncv = 0;
  options.tolerance = 0.0;
  EXPECT_NE(options.validate().find("tolerance"), std::string::npos);
  options.tolerance = 1e-10;
  options.shift = std::nan("");
  EXPECT_NE(options.validate().find("shift"), std::string::npos);
  options.shift = -1.0;
  SpMat lower = SpMat(K.triangularView<Eigen::Lower>());  // not stored in full
  try {
    (void)compute_modes(lower, M, options);
    FAIL() << "a lower-triangle K was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("symmetric"), std::string::npos) << error.what();
  }
  SpMat small(5, 5);
  EXPECT_THROW((void)compute_modes(K, small, options), std::invalid_argument);
}

}  // namespace
