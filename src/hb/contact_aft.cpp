#include "jointhb/hb/contact_aft.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/contact/periodic_state.hpp"
#include "jointhb/contact/preloaded_normal_law.hpp"

namespace jointhb::hb {
namespace {

// The elastic trial force of a contact that sticks throughout, anchored at its reference state.
Eigen::VectorXd stuck_force(const ContactElement& c, const Eigen::VectorXd& g) {
  return (c.reference_force + c.stiffness * (g.array() - c.reference_slip)).matrix();
}

// The contact's state over the period (hb/contact_state.hpp): closed throughout, limit μF_N.
void classify_contact(const ContactElement& element, const contact::TangentialLaw& law, ContactAftResult& r) {
  const auto n = static_cast<std::size_t>(r.force_samples.size());
  std::vector<double> magnitude(n), limit(n, element.slip_limit());
  for (std::size_t i = 0; i < n; ++i) magnitude[i] = std::abs(r.force_samples[static_cast<Eigen::Index>(i)]);
  const ContactStateOptions options;
  const LimitMeasures m = limit_measures(magnitude, limit, options.limit_tolerance);
  r.limit_share = m.share;
  r.limit_ratio = m.ratio;
  r.state = classify_contact_state({0.0, m.share, m.ratio, law.sticks_below_limit()}, options);
}

// A normal element (N-3) has no memory: F(t_i) = F(g(t_i)) and ∂F/∂G = A diag(F'(g_i)) E. It is
// closed ("stuck") while its contact force F_N0 − F stays above the gapping floor ε_gap F_N0 of the
// finite-element points (the default of contact::ContactPointOptions), gapping or open below it.
ContactAftResult evaluate_normal_contact(const ContactElement& element, const FourierBasis& basis,
                                         const Eigen::VectorXd& gap_samples, bool jacobian) {
  const double gap_pressure_ratio = contact::ContactPointOptions{}.gap_pressure_ratio;
  const Eigen::Index n = gap_samples.size();
  ContactAftResult r;
  r.force_samples.resize(n);
  Eigen::VectorXd tangent(n);
  Eigen::Index open = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    r.force_samples[i] = contact::PreloadedNormalLaw::force(gap_samples[i], element.normal_force, element.stiffness);
    tangent[i] = contact::PreloadedNormalLaw::tangent(gap_samples[i], element.normal_force, element.stiffness);
    if (element.normal_force - r.force_samples[i] < gap_pressure_ratio * element.normal_force) ++open;
  }
  const double open_fraction = static_cast<double>(open) / static_cast<double>(n);
  r.state = classify_contact_state({open_fraction, 0.0, 0.0, true});
  if (jacobian) r.d_force = basis.to_frequency(tangent.asDiagonal() * basis.synthesis_matrix());
  return r;
}

}  // namespace

ContactAftResult evaluate_contact(const ContactElement& element, const contact::TangentialLaw& law,
                                  const FourierBasis& basis, const Eigen::VectorXd& gap_samples,
                                  const ContactAftOptions& options) {
  const int n = basis.time_samples();
  const int m = basis.size();
  if (element.normal()) return evaluate_normal_contact(element, basis, gap_samples, options.jacobian);
  ContactAftResult r;

  if (options.skip_stuck && law.sticks_below_limit()) {
    Eigen::VectorXd f = stuck_force(element, gap_samples);
    if (f.cwiseAbs().maxCoeff() <= element.slip_limit()) {
      r.force_samples = std::move(f);
      r.skipped = true;
      if (options.jacobian) {
        r.d_force = element.stiffness * Eigen::MatrixXd::Identity(m, m);
      }
      classify_contact(element, law, r);
      return r;
    }
  }

  contact::PeriodicPath path;
  path.slip.resize(static_cast<std::size_t>(n));
  path.limits.assign(static_cast<std::size_t>(n),
                     contact::TangentialLimits{element.slip_limit(), element.stiffness});
  for (int i = 0; i < n; ++i) path.slip[static_cast<std::size_t>(i)] = {gap_samples[i], 0.0};
  contact::PeriodicStateOptions po;
  po.tolerance = options.periodic_tolerance;
  po.reference_traction = {element.reference_force, 0.0};
  po.reference_slip = {element.reference_slip, 0.0};
  po.keep_step_derivatives = options.jacobian;
  const contact::PeriodicStateResult state = contact::solve_periodic_state(law, path, po);

  r.force_samples.resize(n);
  for (int i = 0; i < n; ++i) r.force_samples[i] = state.traction[static_cast<std::size_t>(i)].x();
  r.dissipation = state.dissipation;
  r.stuck = state.stuck;
  r.iterations = state.iterations;
  r.converged = state.termination == Termination::converged;
  r.message = state.message;
  classify_contact(element, law, r);
  if (!options.jacobian) return r;

  // Scalar sensitivity recursion over the m basis functions at once. On a path along x the
  // trial direction stays x, so the x-components of the 2D step derivatives carry it exactly.
  const Eigen::MatrixXd& e = basis.synthesis_matrix();  // δg_i for unit δG_j: E(i, j)
  Eigen::MatrixXd particular(n, m);                     // zero-start response
  Eigen::VectorXd propagator(n);                        // Π_{l<i} a_l
  Eigen::RowVectorXd acc = Eigen::RowVectorXd::Zero(m);
  double pi = 1.0;
  for (int i = 0; i < n; ++i) {
    particular.row(i) = acc;
    propagator[i] = pi;
    const int next = (i + 1) % n;
    const auto k = static_cast<std::size_t>(i);
    const double a = state.d_traction[k](0, 0);
    const double b = state.d_slip[k](0, 0);
    acc = a * acc + b * (e.row(next) - e.row(i));
    pi *= a;
  }
  Eigen::RowVectorXd start;
  if (std::abs(1.0 - pi) > contact::kPeriodicSingular) {
    start = acc / (1.0 - pi);
  } else {
    start = state.anchor_stiffness * e.row(0);  // anchored: t_0 = t_ref + k_0 (g_0 − g_ref)
  }
  particular += propagator * start;
  r.d_force = basis.to_frequency(particular);
  return r;
}

}  // namespace jointhb::hb
