// Floquet multipliers of a finite-element joint's orbit from the monodromy of its variational
// equation (hb/interface_orbit_monodromy.hpp, eqs. T-39a and T-40a).
#include "jointhb/hb/interface_orbit_monodromy.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "floquet_input.hpp"
#include "jointhb/contact/contact_point.hpp"

namespace jointhb::hb {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// One contact point along the orbit: its law's step derivatives (T-39a) on the fine samples.
struct PointSteps {
  bool spring = false;  // stuck all period with a constant stiffness: δt_T = k δg_T, no state
  int state = -1;       // index of its force state (2 rows) when not a spring
  contact::PeriodicContactResult periodic;
  std::vector<double> stiffness;  // k_T at each sample (springs)
};

// K_i of step i → sample `next` (δt = α + K δg) for point `s` (3 × 3, local frame).
Eigen::Matrix3d landing_tangent(const PointSteps& s, std::size_t i, std::size_t next) {
  Eigen::Matrix3d k = Eigen::Matrix3d::Zero();
  k(2, 2) = s.periodic.normal_stiffness[next];
  if (s.spring) {
    k(0, 0) = k(1, 1) = s.stiffness[next];
    return k;
  }
  const contact::PeriodicStateResult& t = s.periodic.tangential;
  k.topLeftCorner<2, 2>() = t.d_slip[i];
  k.block<2, 1>(0, 2) =
      t.d_limit[i] * s.periodic.d_limit[next] + t.d_stiffness[i] * s.periodic.d_stiffness[next];
  return k;
}

}  // namespace

FloquetResult interface_orbit_floquet(const InterfaceBalance& balance, const VectorXd& y,
                                      double omega, const OrbitMonodromyOptions& options) {
  if (auto msg = options.validate(); !msg.empty()) throw std::invalid_argument(msg);
  FloquetResult out;
  out.message = detail::floquet_input_problem("interface_orbit_floquet", "unknowns", y, balance.unknowns(), omega);
  if (!out.message.empty()) return out;
  const InterfaceModel& model = balance.model();
  const int ns = balance.modes();
  const int P = balance.points();
  const int nf = options.samples;
  const auto nfs = static_cast<std::size_t>(nf);
  const FourierBasis& coarse = balance.basis();
  const FourierBasis fine(coarse.harmonics(), nf, coarse.odd_only());
  const Eigen::Index m = coarse.size();

  // The orbit's gaps on the fine samples, and each point's periodic state with step derivatives.
  MatrixXd gap_coefficients(m, 3 * P);
  for (int p = 0; p < P; ++p)
    for (int c = 0; c < 3; ++c) gap_coefficients.col(3 * p + c) = y.segment(balance.gap_index(p, c, 0), m);
  const MatrixXd gaps = fine.to_time(gap_coefficients);  // nf × 3P
  std::vector<PointSteps> steps(static_cast<std::size_t>(P));
  int force_states = 0;
  contact::PeriodicStateOptions po;
  po.tolerance = balance.options().periodic_tolerance;
  po.max_iterations = balance.options().max_periodic_iterations;
  po.keep_step_derivatives = true;
  for (int p = 0; p < P; ++p) {
    const contact::ContactPoint& law = balance.point_law(p);
    const ContactPointReference& ref = model.references[static_cast<std::size_t>(p)];
    std::vector<contact::Vec3> path(nfs);
    for (std::size_t i = 0; i < nfs; ++i)
      path[i] = ref.gap + gaps.row(static_cast<Eigen::Index>(i)).segment<3>(3 * p).transpose();
    po.reference_traction = ref.traction.head<2>();
    po.reference_slip = ref.gap.head<2>();
    PointSteps& s = steps[static_cast<std::size_t>(p)];
    s.periodic = law.periodic(path, po);
    if (s.periodic.tangential.termination != Termination::converged) {
      out.message = fmt::format("point {}: periodic state: {}", p, s.periodic.tangential.status().message);
      return out;
    }
    const bool constant = std::all_of(s.periodic.d_stiffness.begin(), s.periodic.d_stiffness.end(),
                                      [](double d) { return d == 0.0; });
    s.spring = s.periodic.tangential.stuck && s.periodic.open_fraction == 0.0 && constant;
    if (s.spring) {
      s.stiffness.resize(nfs);
      for (std::size_t i = 0; i < nfs; ++i) s.stiffness[i] = law.tangential_state(path[i].z()).limits.stiffness;
    } else {
      s.state = force_states;
      force_states += 2;
    }
  }

  // Modal data: Λ, C_m = a + b ω², GΦ, R0, areas and C_pre per point.
  const VectorXd lambda = model.omega2;
  const VectorXd modal_damping =
      (model.rayleigh_mass + model.rayleigh_stiffness * model.omega2.array()).matrix();
  const MatrixXd& shapes = model.gap_shapes;  // 3P × ns
  const MatrixXd& r0 = model.residual_flexibility;
  const bool residual = r0.size() > 0 && r0.cwiseAbs().maxCoeff() > 0.0;

  // Unit initial states of z = (η, η̇, δt_T of the force states).
  const int d = 2 * ns + force_states;
  MatrixXd eta = MatrixXd::Zero(ns, d), vel = MatrixXd::Zero(ns, d);
  MatrixXd force = MatrixXd::Zero(force_states, d);
  eta.leftCols(ns).setIdentity();
  vel.middleCols(ns, ns).setIdentity();
  force.rightCols(force_states).setIdentity();

  // δt = α/A + K δg at landing sample `next` of step i (T-39a; i < 0: the initial state itself,
  // δt_T = the force state): α (3P × d, area-weighted) the force states' part, K per point
  // (tangents), D = A (K − C_pre) block diagonal (3P × 3P).
  MatrixXd dmat = MatrixXd::Zero(3 * P, 3 * P);
  std::vector<Eigen::Matrix3d> tangents(static_cast<std::size_t>(P));
  const auto contact_terms = [&](int i, const MatrixXd& gap_before, MatrixXd& alpha) {
    const std::size_t next = i < 0 ? 0 : (static_cast<std::size_t>(i) + 1) % nfs;
    alpha.setZero(3 * P, d);
    for (int p = 0; p < P; ++p) {
      const PointSteps& s = steps[static_cast<std::size_t>(p)];
      Eigen::Matrix3d& k = tangents[static_cast<std::size_t>(p)];
      if (i < 0) {
        k.setZero();
        k(2, 2) = s.periodic.normal_stiffness[0];
        if (s.spring) k(0, 0) = k(1, 1) = s.stiffness[0];
      } else {
        k = landing_tangent(s, static_cast<std::size_t>(i), next);
      }
      const double area = model.areas[p];
      dmat.block<3, 3>(3 * p, 3 * p) = area * (k - model.stuck_tangents[static_cast<std::size_t>(p)]);
      if (s.spring) continue;
      if (i < 0) {
        alpha.middleRows(3 * p, 2) = area * force.middleRows(s.state, 2);
      } else {
        const contact::PeriodicStateResult& t = s.periodic.tangential;
        const auto ii = static_cast<std::size_t>(i);
        alpha.middleRows(3 * p, 2) =
            area * (t.d_traction[ii] * force.middleRows(s.state, 2) - t.d_slip[ii] * gap_before.middleRows(3 * p, 2));
      }
    }
  };
  // δF = W (α + D GΦ η) with W = (I + D R0)⁻¹ (T-40a); returns W D GΦ and W α.
  Eigen::PartialPivLU<MatrixXd> w_lu;
  const auto condensed = [&](const MatrixXd& alpha, MatrixXd& stiffness_part, MatrixXd& force_part) {
    if (!residual) {
      stiffness_part = dmat * shapes;
      force_part = alpha;
      return;
    }
    w_lu.compute(MatrixXd::Identity(3 * P, 3 * P) + dmat * r0);
    stiffness_part = w_lu.solve(dmat * shapes);
    force_part = w_lu.solve(alpha);
  };

  // δg = GΦ η − R0 δF (T-40a).
  const auto gaps_of = [&](const MatrixXd& modal, const MatrixXd& contact) -> MatrixXd {
    return residual ? MatrixXd(shapes * modal - r0 * contact) : MatrixXd(shapes * modal);
  };
  MatrixXd alpha, wdg, walpha;
  contact_terms(-1, MatrixXd(), alpha);
  condensed(alpha, wdg, walpha);
  MatrixXd contact_force = walpha + wdg * eta;  // δF_0 (3P × d)
  MatrixXd gap = gaps_of(eta, contact_force);
  MatrixXd acc = -(modal_damping.asDiagonal() * vel + lambda.asDiagonal() * eta +
                   shapes.transpose() * contact_force);

  const double period = 2.0 * std::numbers::pi / omega;
  const double dt = period / nf;
  const double c0 = 4.0 / (dt * dt), c1 = 2.0 / dt;
  const VectorXd inertial = (c0 + c1 * modal_damping.array() + lambda.array()).matrix();
  for (int i = 0; i < nf; ++i) {
    contact_terms(i, gap, alpha);
    condensed(alpha, wdg, walpha);
    MatrixXd step = shapes.transpose() * wdg;
    step.diagonal() += inertial;
    const MatrixXd rhs = c0 * (eta + dt * vel) + acc +
                         modal_damping.asDiagonal() * (c1 * eta + vel) - shapes.transpose() * walpha;
    const MatrixXd eta1 = step.partialPivLu().solve(rhs);
    contact_force = walpha + wdg * eta1;
    const MatrixXd gap1 = gaps_of(eta1, contact_force);
    // The force states at the landing sample: δt_T = α_T/A + K_T δg (T-39a).
    for (int p = 0; p < P; ++p) {
      const PointSteps& s = steps[static_cast<std::size_t>(p)];
      if (s.spring) continue;
      force.middleRows(s.state, 2) = alpha.middleRows(3 * p, 2) / model.areas[p] +
                                     tangents[static_cast<std::size_t>(p)].topRows<2>() * gap1.middleRows(3 * p, 3);
    }
    const MatrixXd acc1 = c0 * (eta1 - eta - dt * vel) - acc;
    vel = c1 * (eta1 - eta) - vel;
    acc = acc1;
    eta = eta1;
    gap = gap1;
  }
  MatrixXd phi(d, d);
  phi << eta, vel, force;
  // A rigid-body kept mode does not move the interface (Gφ_j = 0): its rows and columns hold only
  // its own trivial multipliers (1 and the damped velocity), left out.
  const int rigid = model.rigid_modes;
  if (rigid > 0) {
    std::vector<Eigen::Index> keep;
    for (Eigen::Index k = 0; k < d; ++k)
      if (!(k < rigid || (k >= ns && k < ns + rigid))) keep.push_back(k);
    phi = MatrixXd(phi(keep, keep));
  }
  return floquet_from_monodromy(phi, period, options.unstable_tolerance);
}

}  // namespace jointhb::hb
