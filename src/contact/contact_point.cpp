// Contact point: exponential normal law + pressure-dependent tangential law (contact_point.hpp).
#include "jointhb/contact/contact_point.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace jointhb::contact {

std::string ContactPointOptions::validate() const {
  if (std::string msg = normal.validate(); !msg.empty()) return "normal." + msg;
  if (!(friction_coefficient >= 0.0 && std::isfinite(friction_coefficient))) {
    return "friction_coefficient must be >= 0 and finite (0: frictionless)";
  }
  if (stiffness_model == TangentialStiffnessModel::proportional &&
      !(stiffness_ratio > 0.0 && std::isfinite(stiffness_ratio))) {
    return "stiffness_ratio must be > 0 and finite (proportional stiffness model)";
  }
  if (stiffness_model == TangentialStiffnessModel::constant &&
      !(tangential_stiffness > 0.0 && std::isfinite(tangential_stiffness))) {
    return "tangential_stiffness must be > 0 and finite (constant stiffness model)";
  }
  if (!(gap_pressure_ratio >= 0.0 && gap_pressure_ratio < 1.0)) {
    return "gap_pressure_ratio must lie in [0, 1)";
  }
  return {};
}

ContactPoint::ContactPoint(ContactPointOptions options, std::shared_ptr<const TangentialLaw> law)
    : options_(std::move(options)), law_(std::move(law)) {
  if (!law_) throw std::invalid_argument("contact point: tangential law is null");
  if (std::string msg = options_.validate(); !msg.empty()) {
    throw std::invalid_argument("contact point: " + msg);
  }
}

ContactPoint ContactPoint::with_constant_stiffness(double stiffness) const {
  ContactPointOptions o = options_;
  o.stiffness_model = TangentialStiffnessModel::constant;
  o.tangential_stiffness = stiffness;
  return ContactPoint(std::move(o), law_);
}

double ContactPointOptions::tangential_stiffness_floor() const {
  const double ratio = std::max(gap_pressure_ratio, 1e-300);
  if (normal.kind == NormalLawKind::linear) return stiffness_ratio * normal.penalty_stiffness * ratio;
  return stiffness_ratio * normal.decay * ratio * normal.reference_pressure;  // χ λ ε_gap p_N0
}

TangentialState ContactPoint::tangential_state(double gap) const {
  TangentialState s;
  const auto& o = options_;
  s.pressure = o.normal.pressure(gap);
  s.normal_stiffness = o.normal.stiffness(gap);
  // open: no normal stiffness (beyond a cutoff, or g_N > g_N0 for the linear law), or below the
  // gapping floor of the exponential law
  s.open = s.normal_stiffness == 0.0 || s.pressure < o.gap_pressure_ratio * o.normal.open_reference();
  if (s.open || o.friction_coefficient == 0.0) {
    // gapping: no friction capacity, no tangential stiffness (nothing divides by p_N); a
    // frictionless interface (μ = 0) likewise carries no tangential traction and has no stiffness
    return s;
  }
  s.limits.slip_limit = o.friction_coefficient * s.pressure;  // μ p_N
  s.d_limit = -o.friction_coefficient * s.normal_stiffness;   // d(μ p_N)/dg_N = -μ k_N
  if (o.stiffness_model == TangentialStiffnessModel::proportional) {
    s.limits.stiffness = o.stiffness_ratio * s.normal_stiffness;  // χ k_N (χ λ p_N, eq. 6)
    // d(χ k_N)/dg_N: -λ k_T for the exponential laws, 0 for the linear one (normal_law.hpp)
    s.d_stiffness = o.normal.kind == NormalLawKind::linear ? 0.0 : -o.normal.decay * s.limits.stiffness;
  } else {
    s.limits.stiffness = o.tangential_stiffness;
  }
  return s;
}

ContactStep ContactPoint::step(const Vec2& tangential_traction, const Vec3& g0,
                               const Vec3& g1) const {
  const TangentialState s = tangential_state(g1.z());
  const TangentialStep t = law_->step(tangential_traction, g1.head<2>() - g0.head<2>(), s.limits);
  ContactStep r;
  r.open = s.open;
  r.traction << t.traction, -s.pressure;  // t_N = -p_N (eq. 6, paper's p_N = -t_N)
  r.tangent.topLeftCorner<2, 2>() = t.d_slip;
  r.tangent.block<2, 1>(0, 2) = t.d_limit * s.d_limit + t.d_stiffness * s.d_stiffness;
  r.tangent(2, 2) = s.normal_stiffness;
  r.d_previous.topLeftCorner<2, 2>() = t.d_traction;
  r.dissipation = t.dissipation;
  return r;
}

PeriodicContactResult ContactPoint::periodic(const std::vector<Vec3>& path,
                                             const PeriodicStateOptions& options) const {
  const std::size_t n = path.size();
  PeriodicPath tangential;
  tangential.slip.resize(n);
  tangential.limits.resize(n);
  PeriodicContactResult r;
  r.d_limit.resize(n);
  r.d_stiffness.resize(n);
  r.normal_stiffness.resize(n);
  std::vector<double> pressure(n);
  std::size_t open = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const TangentialState s = tangential_state(path[i].z());
    tangential.slip[i] = path[i].head<2>();
    tangential.limits[i] = s.limits;
    r.d_limit[i] = s.d_limit;
    r.d_stiffness[i] = s.d_stiffness;
    r.normal_stiffness[i] = s.normal_stiffness;
    pressure[i] = s.pressure;
    open += s.open ? 1 : 0;
  }
  r.tangential = solve_periodic_state(*law_, tangential, options);
  r.traction.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    r.traction[i] << r.tangential.traction[i], -pressure[i];
  }
  r.open_fraction = n ? static_cast<double>(open) / static_cast<double>(n) : 0.0;
  return r;
}

Eigen::MatrixXd ContactPoint::periodic_sensitivity(const PeriodicContactResult& state,
                                                   const Eigen::MatrixXd& path) {
  const auto n = static_cast<Eigen::Index>(state.traction.size());
  if (path.rows() != 3 * n) {
    throw std::invalid_argument("contact point sensitivity: perturbation must have 3N rows");
  }
  const Eigen::Index m = path.cols();
  Eigen::MatrixXd slip(2 * n, m), limit(n, m), stiffness(n, m);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    slip.middleRows(2 * i, 2) = path.middleRows(3 * i, 2);
    limit.row(i) = state.d_limit[k] * path.row(3 * i + 2);
    stiffness.row(i) = state.d_stiffness[k] * path.row(3 * i + 2);
  }
  const Eigen::MatrixXd tangential =
      contact::periodic_sensitivity(state.tangential, slip, limit, stiffness);
  Eigen::MatrixXd result(3 * n, m);
  for (Eigen::Index i = 0; i < n; ++i) {
    result.middleRows(3 * i, 2) = tangential.middleRows(2 * i, 2);
    result.row(3 * i + 2) =
        state.normal_stiffness[static_cast<std::size_t>(i)] * path.row(3 * i + 2);
  }
  return result;
}

}  // namespace jointhb::contact
