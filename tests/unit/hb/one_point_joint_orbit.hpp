#pragma once
// The one-point joint of interface_test_model.hpp and its discrete twin on one orbit: Newton's
// method on the discrete balance, the map of its coefficients to the joint's unknowns, and the
// matching of two sets of multipliers (shared by the stability tests of finite-element joints).
#include <Eigen/Dense>
#include <algorithm>
#include <complex>
#include <tuple>
#include <utility>

#include "interface_test_model.hpp"
#include "jointhb/hb/harmonic_balance.hpp"
#include "jointhb/hb/interface_balance.hpp"

namespace jointhb::hb::testing {

// Newton's method with step halving on a residual `evaluate(x, jacobian) → (R, J)` (a stuck
// start is far from a slipping solution: kinks).
template <class Evaluate>
Eigen::VectorXd newton_solve(Eigen::VectorXd x, const Evaluate& evaluate) {
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  std::tie(r, j) = evaluate(x);
  for (int it = 0; it < 100 && r.lpNorm<Eigen::Infinity>() > 1e-13; ++it) {
    const Eigen::VectorXd dx = j.partialPivLu().solve(r);
    const double norm = r.norm();
    for (double alpha = 1.0; alpha > 1e-4; alpha *= 0.5) {
      Eigen::VectorXd rt;
      Eigen::MatrixXd jt;
      std::tie(rt, jt) = evaluate(Eigen::VectorXd(x - alpha * dx));
      if (rt.norm() < (1.0 - 0.25 * alpha) * norm) {
        x -= alpha * dx;
        r = std::move(rt);
        j = std::move(jt);
        break;
      }
    }
  }
  return x;
}

// The forced response (force F cos Ωt on x1) of the discrete system at Ω.
inline Eigen::VectorXd discrete_solution(const HarmonicBalance& b, double omega) {
  return newton_solve(b.stuck_solution(omega), [&](const Eigen::VectorXd& x) {
    HarmonicBalanceEvaluation ev;
    b.evaluate(x, omega, true, ev);
    return std::pair{ev.residual, Eigen::MatrixXd(ev.d_coefficients)};
  });
}

// The discrete coefficients mapped to the joint's unknowns: η = ΦᵀMx, δg = (x0, 0, 0).
inline Eigen::VectorXd joint_unknowns(const InterfaceBalance& joint, const HarmonicBalance& b,
                                      const Eigen::VectorXd& x, double m0 = 1.0) {
  Eigen::MatrixXd phi;
  two_dof_joint_modes(3.0, m0, phi);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(joint.unknowns());
  const FourierBasis& db = b.basis();
  const FourierBasis& jb = joint.basis();
  for (const int k : db.orders()) {  // k ≥ 1: the orbit's mean is zero (symmetric case)
    for (int c = 0; c < 2; ++c) {
      const int di = db.cosine_index(k) + c;
      const int ji = jb.cosine_index(k) + c;
      const double x0 = x[b.index(0, di)], x1 = x[b.index(1, di)];
      for (int j = 0; j < joint.modes(); ++j) y[joint.modal_index(j, ji)] = phi(0, j) * m0 * x0 + phi(1, j) * x1;
      y[joint.gap_index(0, 0, ji)] = x0;
    }
  }
  return y;
}

// Largest distance from each multiplier of `subset` to the nearest of `all`.
inline double matched(const Eigen::VectorXcd& subset, const Eigen::VectorXcd& all) {
  double worst = 0.0;
  for (const std::complex<double>& r : subset) {
    double best = 1e300;
    for (const std::complex<double>& q : all) best = std::min(best, std::abs(r - q));
    worst = std::max(worst, best);
  }
  return worst;
}

// The one-point joint (every mode kept; Jenkins or Gaul–Mayer) and its discrete twin on one orbit:
// force `force` on x1 at Ω, the discrete solution x at the H and N_t of `joint_options`, its map y
// to the joint's unknowns, and the joint's loaded residual there (`at`, without the Jacobian).
struct TwinOrbit {
  HarmonicBalance discrete;
  InterfaceBalance joint;
  Eigen::VectorXd x, y;
  InterfaceBalanceEvaluation at;
};

inline TwinOrbit twin_orbit(double omega, double force, bool gaul_mayer, const InterfaceBalanceOptions& joint_options) {
  Excitation e;
  e.forces.push_back({1, force, 1});
  HarmonicBalanceOptions ho;
  ho.harmonics = joint_options.harmonics;
  ho.time_samples = joint_options.time_samples;
  TwinOrbit t{HarmonicBalance(two_dof_discrete(3.0, 1.0, gaul_mayer), e, ho),
              InterfaceBalance(two_dof_joint(3.0, 4, 1.0, gaul_mayer), joint_options), {}, {}, {}};
  t.x = discrete_solution(t.discrete, omega);
  t.y = joint_unknowns(t.joint, t.discrete, t.x);
  t.joint.evaluate(t.y, omega, 0.0, t.joint.cosine_load(force), false, t.at);
  return t;
}

}  // namespace jointhb::hb::testing
