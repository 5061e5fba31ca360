#pragma once
// A small synthetic preloaded joint for the tests of hb/interface_balance.hpp and
// continuation/interface_response.hpp: n DOFs, P contact points whose gaps are differences of DOF
// triples, and its modal/interface model built by dense eigen-decomposition.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/jenkins_law.hpp"
#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/hb/interface_model.hpp"

namespace jointhb::hb::testing {

namespace jc = jointhb::contact;
using Eigen::MatrixXd;
using Eigen::VectorXd;

inline constexpr double kLambda = 1.0e6;   // 1/m
inline constexpr double kP0 = 1.0e6;       // Pa
inline constexpr double kPref = 5.0e6;     // Pa, preloaded pressure
inline constexpr double kChi = 0.8;
inline constexpr double kMu = 0.3;
inline constexpr double kArea = 1.0e-5;    // m² per point

inline jc::ContactPoint make_law(bool gaul_mayer) {
  jc::ContactPointOptions o;
  o.normal = {kP0, kLambda, 0.0};
  o.friction_coefficient = kMu;
  // Gaul–Mayer: k_T = χ λ p_N; Jenkins: a constant k_T (with k_T ∝ p_N it ratchets, T-21).
  o.stiffness_model = gaul_mayer ? jc::TangentialStiffnessModel::proportional
                                 : jc::TangentialStiffnessModel::constant;
  o.stiffness_ratio = kChi;
  o.tangential_stiffness = kChi * kLambda * kPref;
  o.gap_pressure_ratio = 1e-9;
  std::shared_ptr<const jc::TangentialLaw> law;
  if (gaul_mayer) law = std::make_shared<jc::GaulMayerLaw>(1.0 / 3.0);
  else law = std::make_shared<jc::JenkinsLaw>();
  return jc::ContactPoint(o, law);
}

// A small "structure": n DOFs, P contact points whose gaps are differences of DOF triples
// (upper block minus lower block), a grounded spring chain plus random coupling, lumped masses.
struct Structure {
  int n = 0, P = 0;
  MatrixXd K, M, G;  // K_s (without contact), M, G (3P × n)
  VectorXd f;        // load shape
  int output = 0;
  std::vector<ContactPointReference> refs;
  std::vector<Eigen::Matrix3d> tangents;
  MatrixXd Kt;       // K_s + Gᵀ A C G
  double a = 0.0, b = 0.0;  // Rayleigh
};

inline Structure make_structure(int P, int interior, unsigned seed, double t_ref_scale = 0.0,
                                bool gaul_mayer = true) {
  Structure s;
  s.P = P;
  s.n = 6 * P + interior;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  const int n = s.n;
  s.K = MatrixXd::Zero(n, n);
  const double k0 = 2.0e7;
  // chain springs i—i+1 and to ground at both ends
  for (int i = 0; i + 1 < n; ++i) {
    const double k = k0 * u(rng);
    s.K(i, i) += k; s.K(i + 1, i + 1) += k; s.K(i, i + 1) -= k; s.K(i + 1, i) -= k;
  }
  s.K(0, 0) += k0;
  s.K(n - 1, n - 1) += k0;
  for (int e = 0; e < 2 * n; ++e) {  // random extra springs
    const int i = static_cast<int>(rng() % n), j = static_cast<int>(rng() % n);
    if (i == j) continue;
    const double k = 0.3 * k0 * u(rng);
    s.K(i, i) += k; s.K(j, j) += k; s.K(i, j) -= k; s.K(j, i) -= k;
  }
  s.M = MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) s.M(i, i) = 0.01 * u(rng);
  s.G = MatrixXd::Zero(3 * P, n);
  for (int p = 0; p < P; ++p)
    for (int d = 0; d < 3; ++d) {
      s.G(3 * p + d, 3 * p + d) = -1.0;           // lower
      s.G(3 * p + d, 3 * P + 3 * p + d) = 1.0;    // upper
    }
  s.f = VectorXd::Zero(n);
  s.f(n - 1) = 1.0;
  s.f(3 * P + 2) = 0.5;
  s.output = n - 1;
  const jc::ContactPoint law = make_law(true);
  const double g_n = law.options().normal.gap_at_pressure(kPref);
  s.Kt = s.K;
  for (int p = 0; p < P; ++p) {
    ContactPointReference r;
    const double pr = kPref * (1.0 + 0.3 * p);
    r.gap << 1e-7 * p, -2e-7, law.options().normal.gap_at_pressure(pr);
    r.traction << t_ref_scale * kMu * pr * 0.3, 0.0, -pr;
    s.refs.push_back(r);
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    c(0, 0) = c(1, 1) = kChi * kLambda * (gaul_mayer ? pr : kPref);
    c(2, 2) = kLambda * pr;
    s.tangents.push_back(c);
    s.Kt += s.G.middleRows(3 * p, 3).transpose() * kArea * c * s.G.middleRows(3 * p, 3);
  }
  (void)g_n;
  // Rayleigh damping ~1 % near the first mode.
  Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> es(s.Kt, s.M);
  const double w1 = std::sqrt(es.eigenvalues()[0]);
  s.a = 0.01 * w1;
  s.b = 0.01 / w1;
  return s;
}

// The modal/interface model of a Structure keeping n_s modes (all others residual, s = 0).
inline InterfaceModel make_model(const Structure& s, int ns, bool gaul_mayer) {
  Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> es(s.Kt, s.M);
  const VectorXd w2 = es.eigenvalues();
  const MatrixXd phi = es.eigenvectors();
  InterfaceModel m;
  m.omega2 = w2.head(ns);
  m.gap_shapes = s.G * phi.leftCols(ns);
  m.rayleigh_mass = s.a;
  m.rayleigh_stiffness = s.b;
  m.residual_shift = 0.0;
  const int n = s.n, P3 = 3 * s.P;
  m.residual_flexibility = MatrixXd::Zero(P3, P3);
  m.residual_inertia = MatrixXd::Zero(P3, P3);
  m.load_residual0 = VectorXd::Zero(P3);
  m.load_residual1 = VectorXd::Zero(P3);
  InterfaceOutput out;
  out.name = "output";
  out.modal = phi.row(s.output).head(ns).transpose();
  out.residual0 = VectorXd::Zero(P3);
  out.residual1 = VectorXd::Zero(P3);
  for (int r = ns; r < n; ++r) {
    const VectorXd gr = s.G * phi.col(r);
    const double mu = w2[r], fr = phi.col(r).dot(s.f), cr = phi(s.output, r);
    m.residual_flexibility += gr * gr.transpose() / mu;
    m.residual_inertia += gr * gr.transpose() / (mu * mu);
    m.load_residual0 += gr * fr / mu;
    m.load_residual1 += gr * fr / (mu * mu);
    out.residual0 += gr * cr / mu;
    out.residual1 += gr * cr / (mu * mu);
    out.load_residual0 += cr * fr / mu;
    out.load_residual1 += cr * fr / (mu * mu);
  }
  m.groups.push_back({"joint", make_law(gaul_mayer), 0, s.P});
  m.references = s.refs;
  m.areas = VectorXd::Constant(s.P, kArea);
  m.stuck_tangents = s.tangents;
  m.load_name = "f";
  m.load_modal = phi.leftCols(ns).transpose() * s.f;
  m.outputs.push_back(out);
  return m;
}


// A joint of one contact point grounding DOF x0 of a 2-DOF chain in x (k_1 = 1 to ground, k_2
// between x0 and x1, unit masses, C = 0.002 M), the point's transverse (y0) and normal (z0) DOFs
// held by springs of 50: Jenkins, k_T = 3, μ p A = 0.1. Every mode kept (no residual modes). Its
// damping curve of mode 1 (k_2 = 3: stuck ω₁ = 1.181, ω₂ = 2.934) falls to Ω ≈ 0.9 as it slips,
// where 3Ω meets ω₂ (a 3:1 internal resonance): the curve turns back in amplitude and forward
// again (k_2 = 2: six times, between Ω = 0.71 and 0.83). `kept` < 4: the lowest modes kept, the
// others residual (s = 0, eq. T-24). `m0`: the mass of x0 (M = diag(m0, 1, 1, 1)). `gaul_mayer`:
// the point's tangential law Gaul–Mayer (n = 1/3, the same k_T and μ p A) instead of Jenkins.
// The mass-normalised modes φ (4 × 4, ascending; φᵀMφ = I) and ω² of that joint, contact stuck.
inline Eigen::SelfAdjointEigenSolver<MatrixXd> two_dof_joint_modes(double k2, double m0, MatrixXd& phi) {
  const double kt = 3.0;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(4, 4);  // (x0, x1, y0, z0), contact stuck
  K(0, 0) = 1.0 + k2 + kt;
  K(0, 1) = K(1, 0) = -k2;
  K(1, 1) = k2;
  K(2, 2) = 50.0 + kt;
  K(3, 3) = 50.0 + 1.0;  // + λ p_N of the normal law below
  const Eigen::Vector4d scale(1.0 / std::sqrt(m0), 1.0, 1.0, 1.0);  // M^(-1/2)
  const Eigen::SelfAdjointEigenSolver<MatrixXd> es(scale.asDiagonal() * K * scale.asDiagonal());
  phi = scale.asDiagonal() * es.eigenvectors();
  return es;
}

inline InterfaceModel two_dof_joint(double k2, int kept = 4, double m0 = 1.0, bool gaul_mayer = false) {
  const double kt = 3.0;
  MatrixXd phi;
  const Eigen::SelfAdjointEigenSolver<MatrixXd> es = two_dof_joint_modes(k2, m0, phi);
  InterfaceModel m;
  m.omega2 = es.eigenvalues().head(kept);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(3, 4);
  G(0, 0) = G(1, 2) = G(2, 3) = 1.0;
  m.gap_shapes = G * phi.leftCols(kept);
  m.rayleigh_mass = 0.002;
  m.residual_flexibility = Eigen::MatrixXd::Zero(3, 3);
  m.residual_inertia = Eigen::MatrixXd::Zero(3, 3);
  m.load_residual0 = m.load_residual1 = Eigen::VectorXd::Zero(3);
  const Eigen::Vector4d load(0.0, 1.0, 0.0, 0.0);  // on x1
  for (int r = kept; r < 4; ++r) {
    const Eigen::Vector3d gr = G * phi.col(r);
    const double mu = es.eigenvalues()[r];
    m.residual_flexibility += gr * gr.transpose() / mu;
    m.residual_inertia += gr * gr.transpose() / (mu * mu);
    m.load_residual0 += gr * phi.col(r).dot(load) / mu;
    m.load_residual1 += gr * phi.col(r).dot(load) / (mu * mu);
  }
  jc::ContactPointOptions o;
  o.normal = {1.0, 1.0, 0.0};  // p_N0 = 1 at g_N = 0, λ = 1
  o.friction_coefficient = 0.1;
  o.stiffness_model = jc::TangentialStiffnessModel::constant;
  o.tangential_stiffness = kt;
  o.gap_pressure_ratio = 1e-9;
  std::shared_ptr<const jc::TangentialLaw> law;
  if (gaul_mayer) law = std::make_shared<jc::GaulMayerLaw>(1.0 / 3.0);
  else law = std::make_shared<jc::JenkinsLaw>();
  m.groups.push_back({"joint", jc::ContactPoint(o, law), 0, 1});
  ContactPointReference preload;
  preload.traction << 0.0, 0.0, -1.0;
  m.references.push_back(preload);
  m.areas = Eigen::VectorXd::Ones(1);
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  c(0, 0) = c(1, 1) = kt;
  c(2, 2) = 1.0;
  m.stuck_tangents.push_back(c);
  m.load_name = "f";
  m.load_modal = phi.leftCols(kept).transpose() * load;
  InterfaceOutput out;
  out.name = "x1";
  out.modal = phi.row(1).head(kept).transpose();
  out.residual0 = out.residual1 = Eigen::VectorXd::Zero(3);
  for (int r = kept; r < 4; ++r) {
    const Eigen::Vector3d gr = G * phi.col(r);
    const double mu = es.eigenvalues()[r];
    out.residual0 += gr * phi(1, r) / mu;
    out.residual1 += gr * phi(1, r) / (mu * mu);
    out.load_residual0 += phi(1, r) * phi.col(r).dot(load) / mu;
    out.load_residual1 += phi(1, r) * phi.col(r).dot(load) / (mu * mu);
  }
  m.outputs.push_back(out);
  return m;
}

// The joint of two_dof_joint(k2, ·, m0, gaul_mayer) as a discrete system: x0 (mass m0) and x1, the
// Jenkins (or Gaul–Mayer, n = 1/3) contact on x0 (k_T = 3, μF_N = 0.1), C = 0.002 M.
inline DiscreteSystem two_dof_discrete(double k2, double m0 = 1.0, bool gaul_mayer = false) {
  DiscreteSystem d;
  Eigen::Matrix2d k;
  k << 1.0 + k2, -k2, -k2, k2;
  const Eigen::Matrix2d mass = Eigen::Vector2d(m0, 1.0).asDiagonal();
  d.mass = mass.sparseView();
  d.stiffness = k.sparseView();
  d.damping = (0.002 * mass).sparseView();
  ContactElement contact;
  contact.law = gaul_mayer ? "gaul-mayer" : "jenkins";
  contact.exponent = 1.0 / 3.0;
  contact.dof_a = 0;
  contact.stiffness = 3.0;
  contact.friction_coefficient = 0.1;
  contact.normal_force = 1.0;
  d.contacts.push_back(contact);
  return d;
}

// A slipping state of a balance: the linear solution at a force that slips, perturbed by 5 % of
// its size per unknown (seeded).
template <class Balance>
VectorXd slipping_state(const Balance& hb, double omega, const VectorXd& load, unsigned seed) {
  VectorXd y = hb.linear_solution(omega, load);
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  const VectorXd scale = hb.unknown_scale();
  const double size = y.cwiseQuotient(scale).lpNorm<Eigen::Infinity>();
  for (Eigen::Index i = 0; i < y.size(); ++i) y[i] += 0.05 * size * scale[i] * nd(rng);
  return y;
}

}  // namespace jointhb::hb::testing
