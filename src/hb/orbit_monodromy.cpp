// Floquet multipliers from the monodromy of the variational equation along a harmonic-balance
// orbit (hb/orbit_monodromy.hpp, eqs. T-39 and T-40).
#include "jointhb/hb/orbit_monodromy.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <vector>

#include "floquet_input.hpp"
#include "jointhb/contact/periodic_state.hpp"
#include "jointhb/contact/preloaded_normal_law.hpp"
#include "../support/lapack_eig.hpp"

namespace jointhb::hb {
namespace {

using cd = std::complex<double>;

// One contact's force recursion on the fine samples: a_j, b_j of T-39, or stuck (a spring).
struct ContactSteps {
  bool stuck = true;
  std::vector<double> a, b;
};

std::optional<ContactSteps> contact_steps(const ContactElement& c, const Eigen::VectorXd& gap,
                                          double tolerance, std::string& why) {
  const auto law = DiscreteSystem::make_law(c);
  contact::PeriodicPath path;
  const auto n = static_cast<std::size_t>(gap.size());
  path.slip.resize(n);
  for (std::size_t j = 0; j < n; ++j) path.slip[j] = contact::Vec2(gap[static_cast<Eigen::Index>(j)], 0.0);
  path.limits.assign(n, contact::TangentialLimits{c.slip_limit(), c.stiffness});
  contact::PeriodicStateOptions o;
  o.tolerance = std::max(tolerance, 1e-15);
  o.reference_traction = contact::Vec2(c.reference_force, 0.0);
  o.reference_slip = contact::Vec2(c.reference_slip, 0.0);
  const contact::PeriodicStateResult r = contact::solve_periodic_state(*law, path, o);
  if (r.termination != Termination::converged) {
    why = "periodic state: " + r.status().message;
    return std::nullopt;
  }
  ContactSteps s;
  s.stuck = r.stuck;
  if (s.stuck) return s;
  s.a.resize(n);
  s.b.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    s.a[j] = r.d_traction[j](0, 0);
    s.b[j] = r.d_slip[j](0, 0);
  }
  return s;
}

}  // namespace

std::string OrbitMonodromyOptions::validate() const {
  if (samples < 64) return fmt::format("samples: must be ≥ 64, got {}", samples);
  if (!(unstable_tolerance > 0.0 && unstable_tolerance <= 1e-2)) {
    return fmt::format("unstable_tolerance: must be in (0, 1e-2], got {}", unstable_tolerance);
  }
  return {};
}

FloquetResult orbit_floquet(const HarmonicBalance& balance, const Eigen::VectorXd& coefficients,
                            double omega, const OrbitMonodromyOptions& options) {
  if (auto msg = options.validate(); !msg.empty()) throw std::invalid_argument(msg);
  FloquetResult out;
  out.message =
      detail::floquet_input_problem("orbit_floquet", "coefficients", coefficients, balance.unknowns(), omega);
  if (!out.message.empty()) return out;
  const DiscreteSystem& s = balance.system();
  const int n = s.dofs();
  const int nf = options.samples;
  const FourierBasis& coarse = balance.basis();
  const FourierBasis fine(coarse.harmonics(), nf, coarse.odd_only());
  Eigen::MatrixXd c(coarse.size(), n);
  for (int i = 0; i < n; ++i) c.col(i) = coefficients.segment(balance.index(i, 0), coarse.size());
  const Eigen::MatrixXd x = fine.to_time(c);  // nf × n

  // Contacts: stuck ones become springs (K_total), slipping ones carry a force state, normal ones
  // (N-3, elastic) are springs whose stiffness F'(g(t)) varies over the period (no state).
  Eigen::MatrixXd k_total = Eigen::MatrixXd(s.stiffness);
  std::vector<ContactSteps> slipping;
  std::vector<Eigen::VectorXd> incidence;  // e_a − e_b of each slipping contact
  std::vector<Eigen::VectorXd> normal_incidence, normal_tangent;  // F'(g(t_j)) per fine sample
  for (const auto& e : s.contacts) {
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    b[e.dof_a] = 1.0;
    if (e.dof_b >= 0) b[e.dof_b] = -1.0;
    const Eigen::VectorXd gap = x * b;
    if (e.normal()) {
      normal_incidence.push_back(b);
      normal_tangent.push_back(gap.unaryExpr([&e](double g) {
        return contact::PreloadedNormalLaw::tangent(g, e.normal_force, e.stiffness);
      }));
      continue;
    }
    std::string why;
    std::optional<ContactSteps> steps =
        contact_steps(e, gap, balance.options().periodic_tolerance, why);
    if (!steps) {
      out.message = why;
      return out;
    }
    if (steps->stuck) {
      k_total += e.stiffness * b * b.transpose();
    } else {
      slipping.push_back(std::move(*steps));
      incidence.push_back(b);
    }
  }
  const int ns = static_cast<int>(slipping.size());
  Eigen::MatrixXd bmat(n, ns);
  for (int k = 0; k < ns; ++k) bmat.col(k) = incidence[static_cast<std::size_t>(k)];
  const Eigen::MatrixXd mass = Eigen::MatrixXd(s.mass);
  const Eigen::MatrixXd damping =
      s.damping.rows() == n ? Eigen::MatrixXd(s.damping) : Eigen::MatrixXd::Zero(n, n);

  // Unit initial states of z = (δx, δẋ, δF); the acceleration from the equation of motion.
  const int d = 2 * n + ns;
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(n, d), v = Eigen::MatrixXd::Zero(n, d);
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(ns, d);
  y.leftCols(n).setIdentity();
  v.middleCols(n, n).setIdentity();
  f.rightCols(ns).setIdentity();
  // K(t_j): K_total plus the normal elements' tangents at fine sample j.
  const auto stiffness_at = [&](int j) {
    Eigen::MatrixXd k = k_total;
    for (std::size_t e = 0; e < normal_incidence.size(); ++e) {
      k += normal_tangent[e][j] * normal_incidence[e] * normal_incidence[e].transpose();
    }
    return k;
  };
  const bool time_varying = !normal_incidence.empty();
  const Eigen::LLT<Eigen::MatrixXd> mass_llt(mass);
  Eigen::MatrixXd a = mass_llt.solve(-(damping * v + stiffness_at(0) * y + bmat * f));

  const double period = 2.0 * std::numbers::pi / omega;
  const double dt = period / nf;
  const double c0 = 4.0 / (dt * dt), c1 = 2.0 / dt;
  const Eigen::MatrixXd inertial = c0 * mass + c1 * damping;
  Eigen::VectorXd b_step(ns), b_previous = Eigen::VectorXd::Constant(ns, -1.0), a_step(ns);
  Eigen::LLT<Eigen::MatrixXd> step_llt;
  for (int j = 0; j < nf; ++j) {
    for (int k = 0; k < ns; ++k) {
      a_step[k] = slipping[static_cast<std::size_t>(k)].a[static_cast<std::size_t>(j)];
      b_step[k] = slipping[static_cast<std::size_t>(k)].b[static_cast<std::size_t>(j)];
    }
    // Refactor only where a contact's tangent changes (at every step with normal elements).
    if (j == 0 || time_varying || b_step != b_previous) {
      step_llt.compute(inertial + stiffness_at((j + 1) % nf) + bmat * b_step.asDiagonal() * bmat.transpose());
      if (step_llt.info() != Eigen::Success) {
        out.message = fmt::format("the step matrix is not positive definite at t = {:.4g} T",
                                  static_cast<double>(j) / nf);
        return out;
      }
      b_previous = b_step;
    }
    const Eigen::MatrixXd rhs = mass * (c0 * (y + dt * v) + a) + damping * (c1 * y + v) -
                                bmat * (a_step.asDiagonal() * f -
                                        b_step.asDiagonal() * (bmat.transpose() * y));
    const Eigen::MatrixXd y1 = step_llt.solve(rhs);
    f = a_step.asDiagonal() * f + b_step.asDiagonal() * (bmat.transpose() * (y1 - y));
    const Eigen::MatrixXd a1 = c0 * (y1 - y - dt * v) - a;
    v = c1 * (y1 - y) - v;
    a = a1;
    y = y1;
  }
  Eigen::MatrixXd phi(d, d);
  phi << y, v, f;
  return floquet_from_monodromy(phi, period, options.unstable_tolerance);
}

FloquetResult floquet_from_monodromy(const Eigen::MatrixXd& monodromy, double period,
                                     double unstable_tolerance) {
  FloquetResult out;
  if (!monodromy.allFinite()) {
    out.message = "the monodromy is not finite";
    return out;
  }
  // Balanced QR (support/lapack_eig.hpp): Φ's blocks carry the units of its state.
  const support::EigenDecomposition eig = support::eigen_decomposition(monodromy, false);
  if (!eig.ok) {
    out.message = "the eigensolver did not converge";
    return out;
  }
  const Eigen::Index d = monodromy.rows();
  std::vector<cd> rho(eig.values.data(), eig.values.data() + d);
  std::stable_sort(rho.begin(), rho.end(),
                   [](const cd& p, const cd& q) { return std::abs(p) > std::abs(q); });
  out.multipliers.resize(d);
  out.exponents.resize(d);
  for (Eigen::Index k = 0; k < d; ++k) {
    const cd r = rho[static_cast<std::size_t>(k)];
    out.multipliers[k] = r;
    out.exponents[k] = cd(std::log(std::max(std::abs(r), 1e-300)), std::arg(r)) / period;
    out.max_multiplier = std::max(out.max_multiplier, std::abs(r));
    if (std::abs(r) > 1.0 + unstable_tolerance) ++out.unstable;
  }
  out.ok = true;
  return out;
}

}  // namespace jointhb::hb
