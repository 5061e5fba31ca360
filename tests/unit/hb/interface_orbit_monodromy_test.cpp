// Floquet multipliers of a finite-element joint's orbit (hb/interface_orbit_monodromy.hpp) against
// the discrete system's monodromy (hb/orbit_monodromy.hpp, itself checked against shooting) on the
// same system written both ways, and the closed form of the decoupled directions.
#include "jointhb/hb/interface_orbit_monodromy.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <complex>
#include <cstdio>
#include <numbers>
#include <tuple>
#include <utility>
#include <vector>

#include "interface_test_model.hpp"
#include "one_point_joint_orbit.hpp"
#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/hb/harmonic_balance.hpp"
#include "jointhb/hb/orbit_monodromy.hpp"

namespace jointhb::hb {
namespace {

using namespace jointhb::hb::testing;
using cd = std::complex<double>;

TEST(InterfaceOrbitMonodromy, OnePointJointHasTheDiscreteSystemsMultipliers) {
  // Force 0.2 on x1 at Ω = 1.05, below the stuck ω₁ = 1.181: the contact slips every half period
  // (μF_N = 0.1). The joint (every mode kept, R0 = 0) and the discrete system follow the same
  // orbit; the joint's z = (η₁..₄, η̇₁..₄, δt_T1, δt_T2) has the discrete system's 5 multipliers
  // (x0, x1, ẋ0, ẋ1, δF), the normal direction's undamped-by-contact pair
  // e^{(−c/2 ± i√(51 − c²/4)) T} (c = 0.002; the normal law's tangent equals C_pre, so D = 0
  // there), and three of the transverse direction with its force state. Jenkins and Gaul–Mayer
  // (whose tangent depends on the force state all along the loading branches).
  const double omega = 1.05, force = 0.2;
  for (const bool gaul_mayer : {false, true}) {
    SCOPED_TRACE(gaul_mayer ? "gaul-mayer" : "jenkins");
    InterfaceBalanceOptions jo;
    jo.harmonics = 7;
    jo.time_samples = 256;
    const TwinOrbit t = twin_orbit(omega, force, gaul_mayer, jo);
    ASSERT_TRUE(t.at.ok) << t.at.message;
    ASSERT_LT(t.at.residual.lpNorm<Eigen::Infinity>(), 1e-10);  // one orbit, both models
    ASSERT_GT(t.at.slipping_points, 0);

    OrbitMonodromyOptions mo;
    mo.samples = 2048;
    const FloquetResult rd = orbit_floquet(t.discrete, t.x, omega, mo);
    const FloquetResult rj = interface_orbit_floquet(t.joint, t.y, omega, mo);
    ASSERT_TRUE(rd.ok) << rd.message;
    ASSERT_TRUE(rj.ok) << rj.message;
    ASSERT_EQ(rd.multipliers.size(), 5);
    ASSERT_EQ(rj.multipliers.size(), 10);
    EXPECT_LT(matched(rd.multipliers, rj.multipliers), 1e-9);
    EXPECT_EQ(rj.unstable, rd.unstable);
    // The normal pair, by the trapezoidal rule's closed form: ρ = ((1 − hλ/2)⁻¹(1 + hλ/2))^{N_f}.
    const double period = 2.0 * std::numbers::pi / omega, h = period / mo.samples;
    Eigen::VectorXcd normal(2);
    for (int s = 0; s < 2; ++s) {
      const cd lambda(-0.001, (s == 0 ? 1.0 : -1.0) * std::sqrt(51.0 - 1e-6));
      normal[s] = std::pow((1.0 + 0.5 * h * lambda) / (1.0 - 0.5 * h * lambda), mo.samples);
    }
    EXPECT_LT(matched(normal, rj.multipliers), 1e-9);
    std::printf("%s: max |ρ| %.6f (discrete %.6f)\n", gaul_mayer ? "gaul-mayer" : "jenkins", rj.max_multiplier,
                rd.max_multiplier);
    if (gaul_mayer) continue;
    // Jenkins: the normal pair is the least damped, the largest multiplier (measured: 0.99403
    // against the x direction's 0.75352; the transverse pair 0.66819 and its force state 5e-9).
    EXPECT_NEAR(rj.max_multiplier, std::abs(normal[0]), 1e-9);
    EXPECT_GT(rj.max_multiplier, rd.max_multiplier);
  }
}

// The multipliers of the linear system M ẍ + C ẋ + K x = 0 after N steps of the trapezoidal rule
// over T: ((1 + hλ/2)/(1 − hλ/2))^N for each eigenvalue λ of the first-order form.
Eigen::VectorXcd trapezoidal_multipliers(const Eigen::MatrixXd& M, const Eigen::MatrixXd& C,
                                         const Eigen::MatrixXd& K, double period, int steps) {
  const Eigen::Index n = M.rows();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -M.ldlt().solve(K);
  a.bottomRightCorner(n, n) = -M.ldlt().solve(C);
  const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(a, false).eigenvalues();
  const double h = period / steps;
  Eigen::VectorXcd rho(2 * n);
  for (Eigen::Index k = 0; k < 2 * n; ++k)
    rho[k] = std::pow((1.0 + 0.5 * h * lambda[k]) / (1.0 - 0.5 * h * lambda[k]), steps);
  return rho;
}

TEST(InterfaceOrbitMonodromy, QuasiStaticResidualModeConvergesAsItsMassVanishes) {
  // The condensation δF = (I + D R0)⁻¹(α + D GΦ η) of T-40a, where D ≠ 0: on the preloaded state
  // (y = 0, the contact stuck) with the stuck tangent C_pre = 2 in t1 while the law's k_T = 3 (so
  // D = 1 there), the joint is the linear system K_t + Gᵀ(k_T − C_pre)G. x0 has mass ε; the
  // joint keeps three modes and leaves x0's local mode (ω² ≈ 8/ε) residual. Reference: the
  // eigenvalues of the whole 4-DOF linear system (its slow pair of x1 converges to the condensed
  // one like ε), with every mode kept the same to round-off.
  const double omega = 1.05;
  const double period = 2.0 * std::numbers::pi / omega;
  OrbitMonodromyOptions mo;
  mo.samples = 2048;
  std::vector<double> errors;
  for (const double eps : {1e-2, 1e-3, 1e-4}) {
    SCOPED_TRACE(eps);
    Eigen::MatrixXd phi;
    two_dof_joint_modes(3.0, eps, phi);
    Eigen::Matrix4d K = Eigen::Matrix4d::Zero();
    K << 8.0, -3.0, 0.0, 0.0, -3.0, 3.0, 0.0, 0.0, 0.0, 0.0, 53.0, 0.0, 0.0, 0.0, 0.0, 51.0;
    const Eigen::Matrix4d M = Eigen::Vector4d(eps, 1.0, 1.0, 1.0).asDiagonal();
    const Eigen::VectorXcd reference = trapezoidal_multipliers(M, 0.002 * M, K, period, mo.samples);
    for (const int kept : {4, 3}) {
      InterfaceModel model = two_dof_joint(3.0, kept, eps);
      model.stuck_tangents[0](0, 0) = 2.0;
      InterfaceBalanceOptions jo;
      jo.harmonics = 3;
      jo.time_samples = 32;
      const InterfaceBalance joint(model, jo);
      const FloquetResult rj =
          interface_orbit_floquet(joint, Eigen::VectorXd::Zero(joint.unknowns()), omega, mo);
      ASSERT_TRUE(rj.ok) << rj.message;
      ASSERT_EQ(rj.multipliers.size(), 2 * kept);  // a stuck spring: no force state
      if (kept == 4) {
        EXPECT_LT(matched(rj.multipliers, reference), 1e-9);
        continue;
      }
      // Each of the joint's six multipliers has its counterpart (x1's pair: the error).
      errors.push_back(matched(rj.multipliers, reference));
      std::printf("ε = %.0e: condensed multipliers within %.2e of the full system's\n", eps, errors.back());
    }
  }
  EXPECT_LT(errors.back(), 1e-4);
  EXPECT_GT(errors[0] / errors[1], 5.0);  // first order in ε
  EXPECT_GT(errors[1] / errors[2], 5.0);
}

TEST(InterfaceOrbitMonodromy, EveryPointOfAnFrfHasTheDiscreteSystemsStability) {
  // trace_interface_frf with stability (automatic: one contact point) on the one-point joint,
  // force 0.05 and 0.2 on x1 across its first resonance (the contact slips near it): at every
  // point the discrete system's multipliers, computed on its own orbit at the same Ω (the FE point
  // mapped back, x0 = δg_t1, x1 = Σ φ₁ⱼ ηⱼ, then Newton), are among the joint's, and the verdicts
  // agree. At 0.2 Newton from the stuck linear response at Ω = 0.8 fails and the curve starts by
  // the load ramp (InterfaceFrfSegment::load_ramp): the point it starts from is the discrete
  // system's solution too. Jenkins at both forces, Gaul–Mayer at 0.2.
  for (const auto& [gaul_mayer, force] : {std::pair{false, 0.05}, std::pair{false, 0.2}, std::pair{true, 0.2}}) {
    SCOPED_TRACE(::testing::Message() << (gaul_mayer ? "gaul-mayer " : "jenkins ") << force);
    continuation::InterfaceFrfOptions o;
    o.omega_start = 0.8;
    o.omega_end = 1.4;
    o.load_amplitude = force;
    o.balance.harmonics = 7;
    o.balance.time_samples = 256;
    o.monodromy.samples = 1024;
    const InterfaceModel model = two_dof_joint(3.0, 4, 1.0, gaul_mayer);
    ASSERT_TRUE(continuation::computes_interface_stability(o.stability, model.num_points()));
    const continuation::InterfaceFrf frf = continuation::trace_interface_frf(model, o);
    ASSERT_TRUE(frf.completed()) << frf.message;
    ASSERT_GT(frf.timings.stability, 0.0);
    Excitation e;
    e.forces.push_back({1, o.load_amplitude, 1});
    HarmonicBalanceOptions ho;
    ho.harmonics = 7;
    ho.time_samples = 256;
    ho.selection = HarmonicSelection::all;
    const HarmonicBalance b(two_dof_discrete(3.0, 1.0, gaul_mayer), e, ho);
    const InterfaceBalance joint(model, o.balance);
    Eigen::MatrixXd phi;
    two_dof_joint_modes(3.0, 1.0, phi);
    const Eigen::Index m = joint.basis().size();
    int slipping = 0;
    double worst = 0.0;
    for (const continuation::InterfaceFrfPoint& p : frf.points) {
      ASSERT_TRUE(p.stability_known);
      Eigen::VectorXd x(b.unknowns());
      x.segment(b.index(0, 0), m) = p.unknowns.segment(joint.gap_index(0, 0, 0), m);
      x.segment(b.index(1, 0), m).setZero();
      for (int j = 0; j < joint.modes(); ++j) x.segment(b.index(1, 0), m) += phi(1, j) * p.unknowns.segment(joint.modal_index(j, 0), m);
      HarmonicBalanceEvaluation mapped;
      b.evaluate(x, p.omega, false, mapped);
      EXPECT_LT(mapped.residual.lpNorm<Eigen::Infinity>(), 1e-9) << p.omega;  // one orbit, both models
      x = newton_solve(x, [&](const Eigen::VectorXd& v) {
        HarmonicBalanceEvaluation ev;
        b.evaluate(v, p.omega, true, ev);
        return std::pair{ev.residual, Eigen::MatrixXd(ev.d_coefficients)};
      });
      const FloquetResult rd = orbit_floquet(b, x, p.omega, o.monodromy);
      ASSERT_TRUE(rd.ok) << rd.message;
      worst = std::max(worst, matched(rd.multipliers, p.multipliers));
      EXPECT_EQ(p.stable, rd.stable()) << p.omega;
      EXPECT_EQ(p.bifurcation == hb::Bifurcation::fold, p.bifurcation != hb::Bifurcation::none) << p.omega;
      slipping += p.slipping_points;
    }
    std::printf("%s at %.2f: %zu points, %d slipping, discrete multipliers within %.1e\n",
                gaul_mayer ? "gaul-mayer" : "jenkins", force, frf.points.size(), slipping, worst);
    EXPECT_GT(slipping, 0);
    EXPECT_LT(worst, 1e-8);
  }
}

// An independent reference for a joint with every mode kept (R0 = 0): the period map of the
// modal model M η̈ + C η̇ + Λ η + (GΦ)ᵀ A (t(g) − t_pre − C_pre δg) = φᵀf F cos Ωt integrated
// by the trapezoidal rule on N steps with each point's own increments (ContactPoint::step, Newton
// on η_{i+1} at every step), over the state z = (η, η̇, t_T of every point).
struct ModalPeriodMap {
  const InterfaceModel& model;
  double omega = 0.0, force = 0.0;
  int steps = 0;

  [[nodiscard]] int modes() const { return static_cast<int>(model.omega2.size()); }
  [[nodiscard]] int points() const { return static_cast<int>(model.areas.size()); }

  // A (t − t_pre − C_pre δg) at the gaps GΦ η, each point stepped from its tangential traction
  // `t0` and gap GΦ η0 (new tangential tractions in `t1`, the derivative by η in `d_eta`).
  Eigen::VectorXd contact_force(const Eigen::VectorXd& eta0, const Eigen::VectorXd& eta,
                                const Eigen::VectorXd& t0, Eigen::VectorXd& t1, Eigen::MatrixXd& d_eta) const {
    const int P = points();
    const Eigen::VectorXd g0 = model.gap_shapes * eta0, g1 = model.gap_shapes * eta;
    Eigen::VectorXd f(3 * P);
    Eigen::MatrixXd d_gap = Eigen::MatrixXd::Zero(3 * P, 3 * P);
    for (int p = 0; p < P; ++p) {
      const ContactPointReference& ref = model.references[static_cast<std::size_t>(p)];
      const contact::ContactStep step = model.groups[0].law.step(
          t0.segment<2>(2 * p), ref.gap + g0.segment<3>(3 * p), ref.gap + g1.segment<3>(3 * p));
      const Eigen::Matrix3d& c = model.stuck_tangents[static_cast<std::size_t>(p)];
      t1.segment<2>(2 * p) = step.traction.head<2>();
      f.segment<3>(3 * p) = model.areas[p] * (step.traction - ref.traction - c * g1.segment<3>(3 * p));
      d_gap.block<3, 3>(3 * p, 3 * p) = model.areas[p] * (step.tangent - c);
    }
    d_eta = d_gap * model.gap_shapes;
    return f;
  }

  [[nodiscard]] Eigen::VectorXd operator()(const Eigen::VectorXd& z) const {
    const int n = modes(), P = points();
    Eigen::VectorXd eta = z.head(n), vel = z.segment(n, n), t = z.tail(2 * P), t1(2 * P);
    const Eigen::VectorXd damping = (model.rayleigh_mass + model.rayleigh_stiffness * model.omega2.array()).matrix();
    const double h = 2.0 * std::numbers::pi / omega / steps, c0 = 4.0 / (h * h), c1 = 2.0 / h;
    Eigen::MatrixXd d_eta;
    // The initial acceleration with the state's tractions (a zero step: t1 = t).
    Eigen::VectorXd acc = model.load_modal * force - damping.cwiseProduct(vel) - model.omega2.cwiseProduct(eta) -
                          model.gap_shapes.transpose() * contact_force(eta, eta, t, t1, d_eta);
    for (int i = 0; i < steps; ++i) {
      const double load = force * std::cos(omega * (i + 1) * h);
      Eigen::VectorXd next = eta + h * vel;
      for (int it = 0; it < 50; ++it) {
        const Eigen::VectorXd f = contact_force(eta, next, t, t1, d_eta);
        const Eigen::VectorXd r = c0 * (next - eta - h * vel) - acc + damping.cwiseProduct(c1 * (next - eta) - vel) +
                                  model.omega2.cwiseProduct(next) + model.gap_shapes.transpose() * f -
                                  model.load_modal * load;
        Eigen::MatrixXd j = model.gap_shapes.transpose() * d_eta;
        j.diagonal() += (c0 + c1 * damping.array() + model.omega2.array()).matrix();
        const Eigen::VectorXd dx = j.partialPivLu().solve(r);
        next -= dx;
        if (dx.norm() <= 1e-15 * next.norm()) break;
      }
      contact_force(eta, next, t, t1, d_eta);
      const Eigen::VectorXd acc1 = c0 * (next - eta - h * vel) - acc;
      vel = c1 * (next - eta) - vel;
      acc = acc1;
      eta = next;
      t = t1;
    }
    Eigen::VectorXd out(z.size());
    out << eta, vel, t;
    return out;
  }

  // ∂map/∂z by central differences (steps relative to each block's size).
  [[nodiscard]] Eigen::MatrixXd jacobian(const Eigen::VectorXd& z) const {
    const int n = modes();
    const double eta_size = z.head(n).cwiseAbs().maxCoeff(), vel_size = z.segment(n, n).cwiseAbs().maxCoeff();
    const double t_size = z.tail(2 * points()).cwiseAbs().maxCoeff();
    Eigen::MatrixXd j(z.size(), z.size());
    for (Eigen::Index k = 0; k < z.size(); ++k) {
      const double size = k < n ? eta_size : k < 2 * n ? vel_size : t_size;
      const double e = 1e-6 * size;
      Eigen::VectorXd zp = z, zm = z;
      zp[k] += e;
      zm[k] -= e;
      j.col(k) = ((*this)(zp) - (*this)(zm)) / (2.0 * e);
    }
    return j;
  }
};

TEST(InterfaceOrbitMonodromy, GaulMayerJointMatchesShootingOfItsTimeIntegration) {
  // The synthetic Gaul–Mayer joint (2 points, pressures in MPa, gaps in µm, k_T ≈ 4e12 Pa/m; every
  // mode kept) forced at 0.5 and 0.8 ω₁ in microslip: its multipliers against shooting (Newton on
  // ModalPeriodMap(z) = z, monodromy by central differences). The monodromy's blocks span 27
  // orders of magnitude (modal coordinates against tractions): unbalanced QR gave max |ρ| ≈ 1e4
  // on this stable orbit (docs/stability.md §7); the balanced eigensolver gives the shooting value.
  const Structure s = make_structure(2, 2, 7);
  const InterfaceModel model = make_model(s, s.n, true);
  InterfaceBalanceOptions o;
  o.harmonics = 7;
  o.time_samples = 128;
  const InterfaceBalance b(model, o);
  const double omega = 0.8 * std::sqrt(b.model().omega2[0]), force = 0.5;
  const Eigen::VectorXd load = b.cosine_load(force);
  const Eigen::VectorXd y = newton_solve(b.linear_solution(omega, load), [&](const Eigen::VectorXd& v) {
    InterfaceBalanceEvaluation ev;
    b.evaluate(v, omega, 0.0, load, true, ev);
    return std::pair{ev.residual, ev.jacobian};
  });
  InterfaceBalanceEvaluation at;
  b.evaluate(y, omega, 0.0, load, false, at);
  ASSERT_LT(at.residual.lpNorm<Eigen::Infinity>(), 1e-12);
  ASSERT_GT(at.slipping_points, 0);
  OrbitMonodromyOptions mo;
  mo.samples = 512;
  const FloquetResult rj = interface_orbit_floquet(b, y, omega, mo);
  ASSERT_TRUE(rj.ok) << rj.message;

  // Shooting from the orbit's state at t = 0: η and η̇ from the coefficients, t_T from the
  // periodic state of each point on the orbit's gaps.
  const int n = b.modes(), P = b.points();
  const Eigen::Index m = b.basis().size();
  const FourierBasis fine(o.harmonics, mo.samples, false);
  Eigen::VectorXd z(2 * n + 2 * P);
  for (int j = 0; j < n; ++j) {
    const Eigen::VectorXd c = y.segment(b.modal_index(j, 0), m);
    z[j] = c[0];
    z[n + j] = 0.0;
    for (int k = 1; k <= o.harmonics; ++k) {
      z[j] += c[b.basis().cosine_index(k)];
      z[n + j] += k * omega * c[b.basis().cosine_index(k) + 1];
    }
  }
  for (int p = 0; p < P; ++p) {
    Eigen::MatrixXd gc(m, 3);
    for (int d = 0; d < 3; ++d) gc.col(d) = y.segment(b.gap_index(p, d, 0), m);
    const Eigen::MatrixXd g = fine.to_time(gc);
    const ContactPointReference& ref = model.references[static_cast<std::size_t>(p)];
    std::vector<contact::Vec3> path(static_cast<std::size_t>(mo.samples));
    for (int i = 0; i < mo.samples; ++i) path[static_cast<std::size_t>(i)] = ref.gap + g.row(i).transpose();
    contact::PeriodicStateOptions po;
    po.reference_traction = ref.traction.head<2>();
    po.reference_slip = ref.gap.head<2>();
    z.segment<2>(2 * n + 2 * p) = model.groups[0].law.periodic(path, po).tangential.traction[0];
  }
  const ModalPeriodMap map{model, omega, force, mo.samples};
  Eigen::MatrixXd j;
  double residual = 0.0;
  for (int it = 0; it < 8; ++it) {
    const Eigen::VectorXd r = map(z) - z;
    residual = r.tail(2 * P).norm() / z.tail(2 * P).norm();
    j = map.jacobian(z);
    if (residual < 1e-11) break;
    z -= (j - Eigen::MatrixXd::Identity(z.size(), z.size())).partialPivLu().solve(r);
  }
  ASSERT_LT(residual, 1e-11);  // a periodic orbit of the time integration
  const FloquetResult shooting = floquet_from_monodromy(j, 2.0 * std::numbers::pi / omega, mo.unstable_tolerance);
  ASSERT_TRUE(shooting.ok);
  ASSERT_EQ(shooting.multipliers.size(), rj.multipliers.size());  // every point has a force state
  double worst = 0.0;
  for (Eigen::Index k = 0; k < rj.multipliers.size(); ++k)
    if (std::abs(shooting.multipliers[k]) > 0.1)
      worst = std::max(worst, std::abs(std::abs(rj.multipliers[k]) - std::abs(shooting.multipliers[k])));
  std::printf("max |ρ| %.7f (shooting %.7f), moduli above 0.1 within %.1e\n", rj.max_multiplier,
              shooting.max_multiplier, worst);
  EXPECT_LT(rj.max_multiplier, 1.0);  // stable; the near-neutral multiplier is the traction's creep
  EXPECT_TRUE(rj.stable());
  EXPECT_NEAR(rj.max_multiplier, shooting.max_multiplier, 2e-6);  // measured 2e-7
  EXPECT_LT(worst, 5e-5);                                          // measured 5.7e-6
}

}  // namespace
}  // namespace jointhb::hb
