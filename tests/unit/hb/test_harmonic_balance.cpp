// Harmonic balance residual and Jacobian (hb/harmonic_balance.hpp): the linear limit against the
// complex receptance, analytic Jacobians against central differences, and the two shortcuts
// (odd harmonics, stuck contacts as springs) against the full computation.
#include "jointhb/hb/harmonic_balance.hpp"
#include "jointhb/hb/jacobian_check.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Dense>
#include <complex>
#include <numbers>

namespace jointhb::hb {
namespace {

SparseMatrix dense(const Eigen::MatrixXd& a) { return a.sparseView(); }

// Two DOFs, a Jenkins contact to ground on DOF 1 and a Gaul–Mayer contact between 0 and 1.
DiscreteSystem two_dof(double damping_beta = 0.02) {
  DiscreteSystem s;
  Eigen::MatrixXd k(2, 2);
  k << 2.0, -1.0, -1.0, 2.0;
  s.mass = dense(Eigen::MatrixXd::Identity(2, 2));
  s.stiffness = dense(k);
  s.damping = dense(damping_beta * k + 0.01 * Eigen::MatrixXd::Identity(2, 2));
  ContactElement jenkins;
  jenkins.law = "jenkins";
  jenkins.dof_a = 1;
  jenkins.stiffness = 1.0;
  jenkins.friction_coefficient = 0.3;
  jenkins.normal_force = 1.0;
  ContactElement gm;
  gm.law = "gaul-mayer";
  gm.exponent = 1.0 / 3.0;
  gm.dof_a = 0;
  gm.dof_b = 1;
  gm.stiffness = 1.5;
  gm.friction_coefficient = 0.3;
  gm.normal_force = 0.5;
  s.contacts = {jenkins, gm};
  return s;
}

Excitation cosine_force(int dof, double amplitude) {
  Excitation e;
  e.forces.push_back({dof, amplitude, 1});
  return e;
}

// Newton's method at fixed Ω from the stuck solution; returns the converged X.
Eigen::VectorXd solve(const HarmonicBalance& hb, double omega, int* iterations = nullptr) {
  Eigen::VectorXd x = hb.stuck_solution(omega);
  HarmonicBalanceEvaluation ev;
  for (int it = 0; it < 60; ++it) {
    hb.evaluate(x, omega, true, ev);
    EXPECT_TRUE(ev.ok) << ev.message;
    const Eigen::VectorXd dx = ev.d_coefficients.fullPivLu().solve(-ev.residual);
    x += dx;
    if (dx.lpNorm<Eigen::Infinity>() < 1e-13 * (1.0 + x.lpNorm<Eigen::Infinity>())) {
      if (iterations) *iterations = it + 1;
      hb.evaluate(x, omega, false, ev);
      EXPECT_LT(ev.residual.lpNorm<Eigen::Infinity>(), 1e-12);
      return x;
    }
  }
  ADD_FAILURE() << "Newton did not converge at omega " << omega;
  return x;
}

TEST(HarmonicBalance, LinearSystemEqualsComplexReceptance) {
  DiscreteSystem s = two_dof();
  s.contacts.clear();
  const Excitation e = cosine_force(0, 0.7);
  HarmonicBalanceOptions o;
  o.harmonics = 3;
  o.time_samples = 16;
  o.selection = HarmonicSelection::all;
  const HarmonicBalance hb(s, e, o);
  for (double omega : {0.3, 1.0, 1.7, 3.0}) {
    const Eigen::VectorXd x = hb.stuck_solution(omega);
    // x(t) = Re(X e^{iΩt}) with X = (K − Ω²M + iΩC)^{-1} F → a = Re X, b = −Im X.
    const Eigen::MatrixXcd d = Eigen::MatrixXd(s.stiffness) -
                               omega * omega * Eigen::MatrixXd(s.mass) +
                               std::complex<double>(0, omega) * Eigen::MatrixXd(s.damping);
    Eigen::VectorXcd f = Eigen::VectorXcd::Zero(2);
    f[0] = 0.7;
    const Eigen::VectorXcd xc = d.partialPivLu().solve(f);
    const int a = hb.basis().cosine_index(1);
    for (int dof = 0; dof < 2; ++dof) {
      const double tol = 1e-13 * xc.cwiseAbs().maxCoeff();  // round-off of two LU solves
      EXPECT_NEAR(x[hb.index(dof, a)], xc[dof].real(), tol);
      EXPECT_NEAR(x[hb.index(dof, a + 1)], -xc[dof].imag(), tol);
      EXPECT_EQ(x[hb.index(dof, 0)], 0.0);
    }
    HarmonicBalanceEvaluation ev;
    hb.evaluate(x, omega, false, ev);
    EXPECT_LT(ev.residual.lpNorm<Eigen::Infinity>(), 1e-14);
  }
}

// Central differences of R with respect to X and Ω, compared entry by entry.
void expect_jacobian_matches_differences(const HarmonicBalance& hb, const Eigen::VectorXd& x,
                                         double omega, double tolerance) {
  HarmonicBalanceEvaluation ev;
  hb.evaluate(x, omega, true, ev);
  ASSERT_TRUE(ev.ok) << ev.message;
  const Eigen::Index n = x.size();
  Eigen::MatrixXd fd(n, n);
  HarmonicBalanceEvaluation plus, minus;
  const double scale = x.lpNorm<Eigen::Infinity>();
  for (Eigen::Index j = 0; j < n; ++j) {
    const double h = 1e-6 * scale;
    Eigen::VectorXd xp = x, xm = x;
    xp[j] += h;
    xm[j] -= h;
    hb.evaluate(xp, omega, false, plus);
    hb.evaluate(xm, omega, false, minus);
    fd.col(j) = (plus.residual - minus.residual) / (2.0 * h);
  }
  const double jscale = ev.d_coefficients.cwiseAbs().maxCoeff();
  EXPECT_LT((fd - ev.d_coefficients).cwiseAbs().maxCoeff(), tolerance * jscale)
      << "analytic\n"
      << ev.d_coefficients << "\nfinite differences\n"
      << fd;
  const double h = 1e-6 * omega;
  hb.evaluate(x, omega + h, false, plus);
  hb.evaluate(x, omega - h, false, minus);
  const Eigen::VectorXd fdo = (plus.residual - minus.residual) / (2.0 * h);
  EXPECT_LT((fdo - ev.d_omega).cwiseAbs().maxCoeff(),
            1e-7 * (1.0 + ev.d_omega.cwiseAbs().maxCoeff()));
}

TEST(HarmonicBalance, JacobianMatchesFiniteDifferencesInMicroslipAndGrossSlip) {
  for (double force : {0.05, 0.4, 2.0}) {
    HarmonicBalanceOptions o;
    o.harmonics = 5;
    o.time_samples = 64;
    o.selection = HarmonicSelection::all;
    const HarmonicBalance hb(two_dof(), cosine_force(0, force), o);
    const Eigen::VectorXd x = solve(hb, 1.2);
    // Perturb off the solution so that every harmonic is non-trivial.
    Eigen::VectorXd y =
        x + 0.1 * x.lpNorm<Eigen::Infinity>() *
                Eigen::VectorXd::LinSpaced(x.size(), -0.3, 0.4).array().sin().matrix();
    expect_jacobian_matches_differences(hb, y, 1.2, 1e-6);
  }
}

TEST(HarmonicBalance, JacobianWithStaticLoadAndReferenceState) {
  DiscreteSystem s = two_dof();
  s.contacts[0].reference_force = 0.1;
  s.contacts[0].reference_slip = 0.05;
  Excitation e = cosine_force(1, 0.3);
  e.static_force = Eigen::Vector2d(0.05, -0.02);
  e.forces.push_back({0, 0.05, 2});
  HarmonicBalanceOptions o;
  o.harmonics = 4;
  o.time_samples = 64;
  const HarmonicBalance hb(s, e, o);
  EXPECT_FALSE(hb.basis().odd_only());
  const Eigen::VectorXd x = solve(hb, 0.9);
  expect_jacobian_matches_differences(hb, x, 0.9, 1e-6);
}

TEST(HarmonicBalance, OddHarmonicsGiveTheFullAnswerOnSymmetricCases) {
  const DiscreteSystem s = two_dof();
  const Excitation e = cosine_force(0, 0.4);
  HarmonicBalanceOptions o;
  o.harmonics = 7;
  o.time_samples = 64;
  o.selection = HarmonicSelection::all;
  const HarmonicBalance full(s, e, o);
  o.selection = HarmonicSelection::automatic;
  const HarmonicBalance odd(s, e, o);
  ASSERT_TRUE(odd.basis().odd_only());
  ASSERT_FALSE(full.basis().odd_only());
  for (double omega : {0.8, 1.3, 2.0}) {
    const Eigen::VectorXd xf = solve(full, omega);
    const Eigen::VectorXd xo = solve(odd, omega);
    const double scale = xf.lpNorm<Eigen::Infinity>();
    for (int dof = 0; dof < 2; ++dof) {
      EXPECT_LT(std::abs(xf[full.index(dof, 0)]), 1e-13 * scale);
      for (int k = 1; k <= 7; ++k) {
        const int af = full.basis().cosine_index(k);
        const int ao = odd.basis().cosine_index(k);
        for (int p = 0; p < 2; ++p) {
          const double ref = xf[full.index(dof, af + p)];
          const double got = ao < 0 ? 0.0 : xo[odd.index(dof, ao + p)];
          EXPECT_NEAR(got, ref, 1e-12 * scale) << "dof " << dof << " k " << k;
        }
      }
    }
  }
}

TEST(HarmonicBalance, OddSelectionRejectsAsymmetricCases) {
  Excitation e = cosine_force(0, 0.4);
  e.static_force = Eigen::Vector2d(0.1, 0.0);
  HarmonicBalanceOptions o;
  o.harmonics = 3;
  o.time_samples = 16;
  o.selection = HarmonicSelection::odd;
  EXPECT_THROW(HarmonicBalance(two_dof(), e, o), std::invalid_argument);
  o.selection = HarmonicSelection::automatic;
  EXPECT_FALSE(HarmonicBalance(two_dof(), e, o).basis().odd_only());
}

TEST(HarmonicBalance, StuckJenkinsShortcutEqualsTheFullAft) {
  DiscreteSystem s = two_dof();
  s.contacts.erase(s.contacts.begin() + 1);  // Jenkins only
  s.contacts[0].reference_force = 0.05;
  s.contacts[0].reference_slip = 0.01;
  const Excitation e = cosine_force(0, 0.02);  // small: the contact sticks
  HarmonicBalanceOptions o;
  o.harmonics = 5;
  o.time_samples = 32;
  const HarmonicBalance fast(s, e, o);
  o.skip_stuck_contacts = false;
  const HarmonicBalance slow(s, e, o);
  const Eigen::VectorXd x = fast.stuck_solution(1.1);
  HarmonicBalanceEvaluation a, b;
  fast.evaluate(x, 1.1, true, a);
  slow.evaluate(x, 1.1, true, b);
  ASSERT_TRUE(a.contacts[0].skipped);
  ASSERT_FALSE(b.contacts[0].skipped);
  EXPECT_TRUE(b.contacts[0].stuck);
  EXPECT_LT((a.residual - b.residual).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((a.d_coefficients - b.d_coefficients).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_LT(a.residual.lpNorm<Eigen::Infinity>(), 1e-15);  // the stuck solution is exact
  EXPECT_EQ(a.dissipation, 0.0);
}

TEST(HarmonicBalance, ResidualReportsDissipationOfSlippingContacts) {
  HarmonicBalanceOptions o;
  o.harmonics = 5;
  o.time_samples = 64;
  const HarmonicBalance hb(two_dof(), cosine_force(0, 1.0), o);
  const Eigen::VectorXd x = solve(hb, 1.0);
  HarmonicBalanceEvaluation ev;
  hb.evaluate(x, 1.0, false, ev);
  EXPECT_GT(ev.dissipation, 0.0);
  // Energy balance over one period: the work of the external force equals the dissipation by
  // viscous damping and the contacts. W_ex = π Σ_k k (F_a,k x_b,k − F_b,k x_a,k) with F_b = 0:
  // W_ex = π F a... for a cos forcing: W = π F b_1 of the loaded DOF (x = a cos + b sin).
  const int a = hb.basis().cosine_index(1);
  const double w_ex = std::numbers::pi * 1.0 * x[hb.index(0, a + 1)];
  // Viscous: π Ω Σ_k k² (a_kᵀ C a_k + b_kᵀ C b_k).
  double w_visc = 0.0;
  const Eigen::MatrixXd c(hb.system().damping);
  for (int k : hb.basis().orders()) {
    const int ak = hb.basis().cosine_index(k);
    Eigen::Vector2d va(x[hb.index(0, ak)], x[hb.index(1, ak)]);
    Eigen::Vector2d vb(x[hb.index(0, ak + 1)], x[hb.index(1, ak + 1)]);
    w_visc += std::numbers::pi * 1.0 * k * k * (va.dot(c * va) + vb.dot(c * vb));
  }
  // Harmonic balance balances the truncated contact force exactly: its work (from the
  // coefficients) closes the balance to round-off. The periodic state's W_D, exact on the
  // samples, differs by the truncation of the force (small at H = 5 for this loop).
  EXPECT_NEAR(w_ex, w_visc + ev.fourier_dissipation, 1e-12 * w_ex);
  EXPECT_NEAR(ev.fourier_dissipation, ev.dissipation, 1e-3 * ev.dissipation);
}

TEST(HarmonicBalance, JacobianCheckFindsAWrongJacobian) {
  HarmonicBalanceOptions o;
  o.harmonics = 3;
  o.time_samples = 32;
  const HarmonicBalance hb(two_dof(), cosine_force(0, 0.4), o);
  const Eigen::VectorXd x = solve(hb, 1.2);
  const JacobianCheck ok = check_jacobian(hb, x, 1.2);
  EXPECT_LT(ok.max_error, 1e-6);
  EXPECT_LT(ok.max_error_omega, 1e-6);
  // The check is not blind: with a step far too large for the nonlinearity the one-sided
  // differences stop agreeing, and it says so (columns flagged, not silently passed).
  const JacobianCheck coarse = check_jacobian(hb, x, 1.2, 0.3);
  EXPECT_TRUE(coarse.kinked_columns > 0 || coarse.max_error > 1e-4);
}

TEST(HarmonicBalance, ResultDoesNotDependOnTheThreadCount) {
  // A chain of 8 DOFs with 8 contacts (above the parallel threshold), evaluated on 1 and 2 threads.
  DiscreteSystem s;
  const int n = 8;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    k(i, i) = 2.0;
    if (i + 1 < n) k(i, i + 1) = k(i + 1, i) = -1.0;
  }
  s.mass = dense(Eigen::MatrixXd::Identity(n, n));
  s.stiffness = dense(k);
  s.damping = dense(0.01 * k);
  for (int i = 0; i < n; ++i) {
    ContactElement c;
    c.law = i % 2 ? "gaul-mayer" : "jenkins";
    c.dof_a = i;
    c.dof_b = i + 1 < n ? i + 1 : -1;
    c.stiffness = 0.5 + 0.1 * i;
    c.normal_force = 0.05;
    s.contacts.push_back(c);
  }
  HarmonicBalanceOptions o;
  o.harmonics = 5;
  o.time_samples = 64;
  const HarmonicBalance hb(s, cosine_force(0, 1.0), o);
  const Eigen::VectorXd x = hb.stuck_solution(0.7);
  HarmonicBalanceEvaluation one, two;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  hb.evaluate(x, 0.7, true, one);
  omp_set_num_threads(2);
  hb.evaluate(x, 0.7, true, two);
  omp_set_num_threads(saved);
  ASSERT_GT(one.dissipation, 0.0);
  EXPECT_EQ(one.residual, two.residual);
  EXPECT_EQ(one.d_coefficients, two.d_coefficients);
  EXPECT_EQ(one.dissipation, two.dissipation);
}

TEST(HarmonicBalance, RejectsBadInput) {
  HarmonicBalanceOptions o;
  o.harmonics = 3;
  o.time_samples = 7;
  EXPECT_NE(o.validate().find("time_samples"), std::string::npos);
  o.time_samples = 16;
  Excitation e = cosine_force(0, 1.0);
  e.forces[0].harmonic = 4;
  EXPECT_THROW(HarmonicBalance(two_dof(), e, o), std::invalid_argument);
  e.forces[0].harmonic = 1;
  e.forces[0].dof = 5;
  EXPECT_THROW(HarmonicBalance(two_dof(), e, o), std::invalid_argument);
  DiscreteSystem s = two_dof();
  s.contacts[0].dof_a = 2;
  EXPECT_THROW(HarmonicBalance(s, cosine_force(0, 1.0), o), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::hb
