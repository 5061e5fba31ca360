// Harmonic balance in modal/interface form (hb/interface_balance.hpp) against independent
// references: central differences of the residual (Jacobian, ∂/∂Ω, ∂/∂ξ), the direct complex
// solve of the stuck linear system, and a plain harmonic balance of the same structure in its
// physical coordinates (every DOF an unknown, dense Newton) written here from the point AFT alone.
#include "jointhb/hb/interface_balance.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <cstdio>
#include <memory>
#include <random>

#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/jenkins_law.hpp"
#include "jointhb/hb/contact_point_aft.hpp"
#include "interface_test_model.hpp"

namespace jointhb::hb {
namespace {

using namespace jointhb::hb::testing;

// Plain Newton on the interface balance at fixed (Ω, ξ = 0).
VectorXd solve(const InterfaceBalance& hb, double omega, const VectorXd& load, double* residual = nullptr) {
  VectorXd y = hb.linear_solution(omega, load);
  InterfaceBalanceEvaluation e;
  for (int it = 0; it < 40; ++it) {
    hb.evaluate(y, omega, 0.0, load, true, e);
    EXPECT_TRUE(e.ok) << e.message;
    const double r = e.residual.lpNorm<Eigen::Infinity>();
    if (residual) *residual = r;
    const VectorXd dy = e.jacobian.partialPivLu().solve(-e.residual);
    y += dy;
    if (dy.lpNorm<Eigen::Infinity>() < 1e-13 * y.lpNorm<Eigen::Infinity>()) break;
  }
  hb.evaluate(y, omega, 0.0, load, false, e);
  if (residual) *residual = e.residual.lpNorm<Eigen::Infinity>();
  return y;
}

// Reference: harmonic balance in physical coordinates Q (n × m),
//   S(Ω) Q + Gᵀ A ΔT(G Q) = f F,  C = a M + b K_t,
// ΔT from evaluate_contact_point with the mean tangential traction replaced by C_TT δg_T,0
// (eq. T-28) and, when `frozen`, the tangential stiffness of each point held at its preloaded
// value (eq. T-30: a constant-model point with k = C_pre,TT). Dense Newton with the AFT Jacobian.
// Returns the gap coefficients (m × 3P).
MatrixXd physical_reference(const Structure& s, const FourierBasis& basis, bool gaul_mayer,
                            double omega, const VectorXd& load, bool frozen = true) {
  const int n = s.n, m = basis.size(), P = s.P;
  const MatrixXd C = s.a * s.M + s.b * s.Kt;
  const jc::ContactPoint law = make_law(gaul_mayer);
  // Kronecker helpers: DOF-major vec(Q) index i·m + c.
  auto linear = [&](const MatrixXd& A0, const MatrixXd& A1, const MatrixXd& A2) {
    // block operator: mean A0; harmonic k: [A0 − (kΩ)² A2, kΩ A1; −kΩ A1, A0 − (kΩ)² A2]
    MatrixXd S = MatrixXd::Zero(n * m, n * m);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        S(i * m, j * m) = A0(i, j);
        for (int k : basis.orders()) {
          const int ia = basis.cosine_index(k), ib = ia + 1;
          const double kw = k * omega;
          S(i * m + ia, j * m + ia) = A0(i, j) - kw * kw * A2(i, j);
          S(i * m + ib, j * m + ib) = A0(i, j) - kw * kw * A2(i, j);
          S(i * m + ia, j * m + ib) = kw * A1(i, j);
          S(i * m + ib, j * m + ia) = -kw * A1(i, j);
        }
      }
    return S;
  };
  const MatrixXd S = linear(s.K, C, s.M);
  MatrixXd GK = MatrixXd::Zero(3 * P * m, n * m);  // G ⊗ I_m, rows (3p+d)·m + c
  for (int r = 0; r < 3 * P; ++r)
    for (int j = 0; j < n; ++j)
      if (s.G(r, j) != 0.0)
        for (int c = 0; c < m; ++c) GK(r * m + c, j * m + c) = s.G(r, j);
  VectorXd F = VectorXd::Zero(n * m);
  for (int i = 0; i < n; ++i) F.segment(i * m, m) = s.f[i] * load;
  // start: stuck linear solution
  const MatrixXd St = linear(s.Kt, C, s.M);
  VectorXd q = St.partialPivLu().solve(F);
  ContactPointAftOptions o;
  o.jacobian = true;
  o.periodic_tolerance = 1e-12;
  for (int it = 0; it < 40; ++it) {
    const VectorXd g = GK * q;  // (3p+d)·m + c
    VectorXd T(3 * P * m);
    MatrixXd JT = MatrixXd::Zero(3 * P * m, 3 * P * m);
    for (int p = 0; p < P; ++p) {
      const Eigen::Map<const MatrixXd> dg(g.data() + 3 * p * m, m, 3);
      const Eigen::Matrix3d& c = s.tangents[p];
      const jc::ContactPoint point = frozen ? law.with_constant_stiffness(c(0, 0)) : law;
      ContactPointAftResult r = evaluate_contact_point(point, s.refs[p], basis, dg, o);
      EXPECT_TRUE(r.converged) << r.message;
      for (int d = 0; d < 2; ++d) {  // T-28
        r.traction(0, d) = c(d, d) * dg(0, d);
        r.jacobian.row(d * m).setZero();
        r.jacobian(d * m, d * m) = c(d, d);
      }
      Eigen::Map<MatrixXd>(T.data() + 3 * p * m, m, 3) = kArea * r.traction;
      JT.block(3 * p * m, 3 * p * m, 3 * m, 3 * m) = kArea * r.jacobian;
    }
    const VectorXd R = S * q + GK.transpose() * T - F;
    const MatrixXd J = S + GK.transpose() * JT * GK;
    const VectorXd dq = J.partialPivLu().solve(-R);
    q += dq;
    if (dq.lpNorm<Eigen::Infinity>() < 1e-13 * q.lpNorm<Eigen::Infinity>()) break;
  }
  const VectorXd g = GK * q;
  return Eigen::Map<const MatrixXd>(g.data(), m, 3 * P);
}

TEST(InterfaceBalance, JacobianMatchesCentralDifferences) {
  for (bool gm : {true, false}) {
    const Structure s = make_structure(3, 4, 7, 0.5, gm);
    const InterfaceBalance hb(make_model(s, 5, gm), {.harmonics = 2, .time_samples = 32});
    // A state with slip: the linear solution at a force level that slips, perturbed.
    const double omega = 1.05 * std::sqrt(hb.model().omega2[0]);
    const VectorXd load = hb.cosine_load(20.0);
    VectorXd y = hb.linear_solution(omega, load);
    std::mt19937 rng(3);
    std::normal_distribution<double> nd(0.0, 1.0);
    const VectorXd scale = hb.unknown_scale();
    for (Eigen::Index i = 0; i < y.size(); ++i) y[i] += 0.05 * y.lpNorm<Eigen::Infinity>() / scale.maxCoeff() * scale[i] * nd(rng);
    const double xi = 3.0;
    InterfaceBalanceEvaluation e, ep, em;
    hb.evaluate(y, omega, xi, load, true, e);
    ASSERT_TRUE(e.ok);
    EXPECT_GT(e.slipping_points, 0);
    MatrixXd fd(y.size(), y.size());
    for (Eigen::Index j = 0; j < y.size(); ++j) {
      const double h = 1e-6 * scale[j] * y.cwiseQuotient(scale).lpNorm<Eigen::Infinity>();
      VectorXd yp = y, ym = y;
      yp[j] += h;
      ym[j] -= h;
      hb.evaluate(yp, omega, xi, load, false, ep);
      hb.evaluate(ym, omega, xi, load, false, em);
      fd.col(j) = (ep.residual - em.residual) / (2 * h);
    }
    const double err = (fd - e.jacobian).cwiseAbs().maxCoeff() / e.jacobian.cwiseAbs().maxCoeff();
    std::printf("%s: Jacobian vs central differences %.2e (%d of %d points slip)\n",
                gm ? "Gaul-Mayer" : "Jenkins", err, e.slipping_points, s.P);
    EXPECT_LT(err, 1e-6);
    const double hw = 1e-6 * omega;
    hb.evaluate(y, omega + hw, xi, load, false, ep);
    hb.evaluate(y, omega - hw, xi, load, false, em);
    const VectorXd fdw = (ep.residual - em.residual) / (2 * hw);
    EXPECT_LT((fdw - e.d_omega).lpNorm<Eigen::Infinity>(), 1e-6 * e.d_omega.lpNorm<Eigen::Infinity>());
    const double hx = 1e-4;
    hb.evaluate(y, omega, xi + hx, load, false, ep);
    hb.evaluate(y, omega, xi - hx, load, false, em);
    const VectorXd fdx = (ep.residual - em.residual) / (2 * hx);
    EXPECT_LT((fdx - e.d_xi).lpNorm<Eigen::Infinity>(), 1e-6 * e.d_xi.lpNorm<Eigen::Infinity>());
  }
}

// Stuck limit: the linear solution has zero residual at vanishing load, and its output equals
// the direct complex solve of (K_t − Ω²M + iΩC) u = f, to the residual-mode expansion error.
TEST(InterfaceBalance, LinearSolutionMatchesDirectSolve) {
  const Structure s = make_structure(3, 6, 11);
  const MatrixXd C = s.a * s.M + s.b * s.Kt;
  Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> es(s.Kt, s.M);
  const double w1 = std::sqrt(es.eigenvalues()[0]);
  int exact_cases = 0;
  for (int ns : {2, 6, 12, s.n}) {  // s.n: every mode kept, the exact case
    const InterfaceBalance hb(make_model(s, ns, true), {.harmonics = 1, .time_samples = 16});
    double worst = 0.0;
    for (double r : {0.5, 0.97, 1.4}) {
      const double omega = r * w1;
      const Eigen::MatrixXcd D = (s.Kt - omega * omega * s.M).cast<std::complex<double>>() +
                                 std::complex<double>(0, omega) * C.cast<std::complex<double>>();
      const Eigen::VectorXcd u = D.partialPivLu().solve(s.f.cast<std::complex<double>>());
      const VectorXd load = hb.cosine_load(1.0);
      const VectorXd y = hb.linear_solution(omega, load);
      const VectorXd uo = hb.output_coefficients(0, y, omega, 0.0, load, MatrixXd::Zero(3, 3 * s.P));
      // X = a − i b
      const std::complex<double> x(uo[1], -uo[2]);
      worst = std::max(worst, std::abs(x - u[s.output]) / std::abs(u[s.output]));
      // gaps
      const Eigen::VectorXcd g = s.G.cast<std::complex<double>>() * u;
      for (int i = 0; i < 3 * s.P; ++i) {
        const std::complex<double> gi(y[hb.gap_index(i / 3, i % 3, 1)], -y[hb.gap_index(i / 3, i % 3, 2)]);
        worst = std::max(worst, std::abs(gi - g[i]) / g.cwiseAbs().maxCoeff());
      }
    }
    std::printf("kept %d of %d modes: stuck response error %.2e\n", ns, s.n, worst);
    if (ns == 12) {
      EXPECT_LT(worst, 1e-4);
    }
    if (ns == s.n) {
      EXPECT_LT(worst, 1e-12);
      ++exact_cases;
    }
  }
  EXPECT_EQ(exact_cases, 1);  // the all-modes case ran
}

// The nonlinear solution equals plain harmonic balance in physical coordinates: to round-off when
// every mode is kept, and to the residual-mode expansion error when some are not.
// Gaul–Mayer with proportional k_T is checked both with the stiffness frozen at the preload
// (eq. T-30, the default) and following the pressure; Jenkins has a constant k_T.
TEST(InterfaceBalance, MatchesPhysicalCoordinateBalance) {
  for (int variant = 0; variant < 3; ++variant) {
    const bool gm = variant < 2, frozen = variant != 1;
    const Structure s = make_structure(3, 4, 5, 0.3, gm);
    const FourierBasis basis(3, 64);
    Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> es(s.Kt, s.M);
    const double omega = 0.98 * std::sqrt(es.eigenvalues()[0]);
    const double amplitude = 40.0;
    const InterfaceBalanceOptions options{.harmonics = 3, .time_samples = 64,
                                          .preloaded_tangential_stiffness = frozen};
    const InterfaceBalance full(make_model(s, s.n, gm), options);
    const VectorXd load = full.cosine_load(amplitude);
    const MatrixXd ref = physical_reference(s, basis, gm, omega, load, frozen);
    { const MatrixXd ref2 = physical_reference(s, basis, gm, omega, load, !frozen);
      std::printf("  (T-30 frozen vs instantaneous k_T: the two references differ by %.2e)\n", (ref-ref2).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff()); }
    double res = 0.0;
    const VectorXd y = solve(full, omega, load, &res);
    InterfaceBalanceEvaluation e;
    full.evaluate(y, omega, 0.0, load, false, e);
    EXPECT_GT(e.slipping_points, 0);
    const Eigen::Map<const MatrixXd> g(y.data() + full.modes() * basis.size(), basis.size(), 3 * s.P);
    const double err = (g - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff();
    std::printf("%s%s, all %d modes kept: gaps vs physical HB %.2e (residual %.1e, %d points slip)\n",
                gm ? "Gaul-Mayer" : "Jenkins", gm ? (frozen ? " (k_T frozen, T-30)" : " (k_T(p_N(t)))") : "",
                s.n, err, res, e.slipping_points);
    EXPECT_LT(err, 1e-9);
    double previous = 1.0;
    for (int ns : {3, 8, 14}) {
      const InterfaceBalance part(make_model(s, ns, gm), options);
      const VectorXd yp = solve(part, omega, load);
      const Eigen::Map<const MatrixXd> gp(yp.data() + part.modes() * basis.size(), basis.size(), 3 * s.P);
      const double e2 = (gp - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff();
      std::printf("  kept %2d modes: %.2e\n", ns, e2);
      EXPECT_LT(e2, previous * 1.0001);
      previous = e2;
    }
    EXPECT_LT(previous, 1e-3);
  }
}

// The per-point summaries (output fields) come from the same periodic states as the residual:
// their area-weighted W_D add up to the evaluation's dissipation, their slip/open flags to its
// counts, and the pressure range brackets the preloaded pressure of every point that stays closed.
TEST(InterfaceBalance, PointSummariesAddUpToTheEvaluation) {
  const Structure s = make_structure(3, 4, 5, 0.3, true);
  const InterfaceBalanceOptions options{.harmonics = 3, .time_samples = 64};
  const InterfaceBalance hb(make_model(s, s.n, true), options);
  Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> es(s.Kt, s.M);
  const double omega = 0.98 * std::sqrt(es.eigenvalues()[0]);
  const VectorXd load = hb.cosine_load(40.0);
  const VectorXd y = solve(hb, omega, load);
  InterfaceBalanceEvaluation e;
  hb.evaluate(y, omega, 0.0, load, false, e);
  const std::vector<InterfacePointSummary> sum = hb.point_summaries(y);
  ASSERT_EQ(static_cast<int>(sum.size()), s.P);
  double w = 0.0;
  int slipping = 0, open = 0;
  ContactStateCounts states;
  for (int p = 0; p < s.P; ++p) {
    const InterfacePointSummary& q = sum[static_cast<std::size_t>(p)];
    w += hb.model().areas[p] * q.dissipation;
    slipping += q.state == ContactState::microslip || q.state == ContactState::gross_slip;
    open += q.open;
    states.add(q.state);
    EXPECT_EQ(q.open, q.state == ContactState::open);
    EXPECT_EQ(q.limit_share > 0.0 && q.open_fraction == 0.0, q.state == ContactState::gross_slip);
    EXPECT_GE(q.limit_ratio, 0.0);
    EXPECT_LE(q.limit_ratio, 1.0 + 1e-12);
    EXPECT_GE(q.dissipation, -1e-15);
    EXPECT_GE(q.open_fraction, 0.0);
    EXPECT_LE(q.open_fraction, 1.0);
    EXPECT_GT(q.tangential_motion, 0.0);
    const double p_pre = -hb.model().references[static_cast<std::size_t>(p)].traction.z();
    if (q.open_fraction == 0.0) {
      EXPECT_LE(q.pressure_min, p_pre * (1 + 1e-12));
      EXPECT_GE(q.pressure_max, p_pre * (1 - 1e-12));
    }
  }
  std::printf("  %d points: %d slipping, %d open; sum A W_D = %.6e J vs evaluation %.6e J\n", s.P, slipping, open, w,
              e.dissipation);
  EXPECT_GT(slipping, 0);
  EXPECT_EQ(slipping, e.slipping_points);
  EXPECT_EQ(open, e.open_points);
  EXPECT_EQ(states.count, e.states.count);
  EXPECT_EQ(states.total(), s.P);
  EXPECT_NEAR(w, e.dissipation, 1e-12 * std::abs(e.dissipation));
  EXPECT_THROW((void)hb.point_summaries(VectorXd::Zero(3)), std::invalid_argument);
}

TEST(InterfaceBalance, RejectsBadInput) {
  const Structure s = make_structure(2, 2, 1);
  InterfaceModel m = make_model(s, 4, true);
  EXPECT_THROW(InterfaceBalance(m, {.harmonics = 0}), std::invalid_argument);
  EXPECT_THROW(InterfaceBalance(m, {.harmonics = 3, .time_samples = 7}), std::invalid_argument);
  InterfaceModel bad = m;
  bad.areas[0] = -1.0;
  EXPECT_THROW(InterfaceBalance(bad, {}), std::invalid_argument);
  const InterfaceBalance hb(m, {});
  InterfaceBalanceEvaluation e;
  EXPECT_THROW(hb.evaluate(VectorXd::Zero(3), 1.0, 0.0, {}, false, e), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::hb
