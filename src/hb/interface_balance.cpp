// Harmonic balance of a preloaded FE joint in modal/interface form (interface_balance.hpp;
// docs/theory.md §11).
#include "jointhb/hb/interface_balance.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <mutex>
#include <numbers>
#include <span>
#include <stdexcept>

#include "../support/blas_gemm.hpp"
#include "../support/lapack_lu.hpp"
#include "../support/stopwatch.hpp"
#include "residual_coefficients.hpp"

namespace jointhb::hb {
namespace {

using detail::cd;
using detail::ResidualCoefficients;
using detail::residual_coefficients;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// out(:, ia/ib) += (c0 R0 + c1 R1) applied to the pair (a, b) given as W0 = R0 [a b], W1 = R1 [a b]:
// X = a − i b, X' = c0 W0 X + c1 W1 X, a' = Re X', b' = −Im X'.
void add_complex_pair(cd c0, cd c1, const VectorXd& w0a, const VectorXd& w0b, const VectorXd& w1a,
                      const VectorXd& w1b, Eigen::Ref<VectorXd> out_a, Eigen::Ref<VectorXd> out_b) {
  // X' = c0 (w0a − i w0b) + c1 (w1a − i w1b)
  out_a += c0.real() * w0a + c0.imag() * w0b + c1.real() * w1a + c1.imag() * w1b;
  out_b += -(c0.imag() * w0a - c0.real() * w0b + c1.imag() * w1a - c1.real() * w1b);
}

}  // namespace

std::string InterfaceBalanceOptions::validate() const {
  if (harmonics < 1) return fmt::format("harmonics: must be ≥ 1, got {}", harmonics);
  if (time_samples < 2 * harmonics + 2)
    return fmt::format("time_samples: must be ≥ 2·harmonics + 2 = {}, got {}", 2 * harmonics + 2,
                       time_samples);
  if (!(periodic_tolerance > 0.0 && periodic_tolerance <= 1e-3))
    return fmt::format("periodic_tolerance: must be in (0, 1e-3], got {}", periodic_tolerance);
  if (max_periodic_iterations < 1)
    return fmt::format("max_periodic_iterations: must be ≥ 1, got {}", max_periodic_iterations);
  if (!(drift_tolerance >= 0.0 && drift_tolerance <= 1e-3))
    return fmt::format("drift_tolerance: must be in [0, 1e-3], got {}", drift_tolerance);
  if (!(drift_ratio >= 0.0 && drift_ratio <= 0.1))
    return fmt::format("drift_ratio: must be in [0, 0.1], got {}", drift_ratio);
  return {};
}

struct InterfaceBalance::Impl {
  InterfaceModel model;
  InterfaceBalanceOptions options;
  FourierBasis basis;
  int m = 0, ns = 0, P = 0;
  Index U = 0;
  double omega_ref = 1.0, g_ref = 1.0;
  VectorXd modal_damping;  // c_j = a + b ω_j²
  // One contact point per point when the tangential stiffness is frozen at its preloaded value
  // (eq. T-30); empty: the groups' laws.
  std::vector<contact::ContactPoint> frozen;
  mutable InterfaceBalanceTimings timings;
  // Single-precision copies of R0 and R1 for inexact inner products (apply_jacobian), made once.
  struct SingleCopies {
    Eigen::MatrixXf r0, r1;
  };
  mutable std::once_flag single_once;
  mutable SingleCopies single;
  const SingleCopies& single_copies() const {
    std::call_once(single_once, [this] {
      single.r0 = model.residual_flexibility.cast<float>();
      single.r1 = model.residual_inertia.cast<float>();
    });
    return single;
  }

  Impl(InterfaceModel mo, InterfaceBalanceOptions op)
      : model(std::move(mo)), options(op), basis(op.harmonics, op.time_samples, false) {
    m = basis.size();
    ns = model.num_modes();
    P = model.num_points();
    U = static_cast<Index>(ns + 3 * P) * m;
    modal_damping = model.rayleigh_mass + model.rayleigh_stiffness * model.omega2.array();
    if (model.rigid_modes >= ns) throw std::invalid_argument("model: no elastic kept mode");
    omega_ref = std::sqrt(model.omega2[model.rigid_modes]);
    g_ref = model.gap_shapes.col(model.rigid_modes).lpNorm<Eigen::Infinity>();
    if (!(g_ref > 0.0)) g_ref = 1.0;
    if (options.preloaded_tangential_stiffness) freeze_tangential_stiffness();
  }

  // k_T,p = k_T(p_pre,p) (eq. T-30), floored at the stiffness of the gapping floor pressure so
  // that a point open in the preloaded state stays a valid (constant-model) point.
  void freeze_tangential_stiffness() {
    bool any = false;
    for (const InterfaceGroup& g : model.groups)
      any = any || g.law.options().stiffness_model == contact::TangentialStiffnessModel::proportional;
    if (!any) return;
    frozen.reserve(static_cast<std::size_t>(P));
    for (const InterfaceGroup& g : model.groups) {
      const contact::ContactPointOptions& o = g.law.options();
      const bool proportional = o.stiffness_model == contact::TangentialStiffnessModel::proportional;
      const double floor = o.tangential_stiffness_floor();
      for (int q = 0; q < g.count; ++q) {
        if (!proportional) {
          frozen.push_back(g.law);
          continue;
        }
        const double gap = model.references[static_cast<std::size_t>(g.first + q)].gap.z();
        const double k = g.law.tangential_state(gap).limits.stiffness;
        frozen.push_back(g.law.with_constant_stiffness(std::max(k, floor)));
      }
    }
  }

  // ΔT − C_pre δg per point (m × 3P, per unit area), with the mean-tangential closure (T-28),
  // and the per-point Jacobian blocks B_p = A_p ∂N_p/∂δg_p.
  struct Contact {
    MatrixXd force;  // A N, m × 3P
    std::vector<MatrixXd> blocks;
    double dissipation = 0.0;
    int open = 0, drifting = 0;
    ContactStateCounts states;
    bool ok = true;
    std::string message;
  };

  Contact contact(const Eigen::Ref<const MatrixXd>& dg, bool jacobian,
                  std::vector<InterfacePointSummary>* summaries = nullptr) const {
    Contact c;
    if (summaries != nullptr) summaries->assign(static_cast<std::size_t>(P), {});
    c.force.resize(m, 3 * P);
    if (jacobian) c.blocks.resize(static_cast<std::size_t>(P));
    ContactPointAftOptions o;
    o.periodic_tolerance = options.periodic_tolerance;
    o.max_iterations = options.max_periodic_iterations;
    o.jacobian = jacobian;
    const std::span<const ContactPointReference> refs(model.references);
    const std::span<const double> areas(model.areas.data(), static_cast<std::size_t>(P));
    for (const InterfaceGroup& g : model.groups) {
      // drift limit: drift_tolerance × the group's largest preloaded slip limit μ p_N
      double p_max = 0.0;
      for (int q = 0; q < g.count; ++q) p_max = std::max(p_max, -model.references[static_cast<std::size_t>(g.first + q)].traction.z());
      o.drift_limit = options.drift_tolerance * g.law.options().friction_coefficient * p_max;
      o.drift_ratio = options.drift_ratio;
      const std::span<const contact::ContactPoint> laws =
          frozen.empty() ? std::span<const contact::ContactPoint>(&g.law, 1)
                         : std::span<const contact::ContactPoint>(frozen).subspan(
                               static_cast<std::size_t>(g.first), static_cast<std::size_t>(g.count));
      const InterfaceAftResult r = evaluate_interface_aft(
          laws, refs.subspan(g.first, g.count), basis,
          dg.middleCols(3 * g.first, 3 * g.count), o, areas.subspan(g.first, g.count));
      c.dissipation += r.dissipation;
      c.open += r.open_points;
      if (!r.converged && c.ok) {
        c.ok = false;
        c.message = fmt::format("interface '{}': {}", g.name, r.message);
      }
      for (int q = 0; q < g.count; ++q) {
        const int p = g.first + q;
        const ContactPointAftResult& pr = r.points[static_cast<std::size_t>(q)];
        c.states.add(pr.state);
        if (pr.drifting) ++c.drifting;
        if (summaries != nullptr) (*summaries)[static_cast<std::size_t>(p)] = summarise(p, pr, dg.middleCols(3 * p, 3));
        const Eigen::Matrix3d& C = model.stuck_tangents[static_cast<std::size_t>(p)];
        const double area = model.areas[p];
        MatrixXd n = pr.traction - dg.middleCols(3 * p, 3) * C.transpose();
        if (options.static_mean_tangential) n(0, 0) = n(0, 1) = 0.0;
        c.force.middleCols(3 * p, 3) = area * n;
        if (jacobian) {
          MatrixXd b = pr.jacobian;
          for (int r1 = 0; r1 < 3; ++r1)
            for (int r2 = 0; r2 < 3; ++r2) b.block(r1 * m, r2 * m, m, m).diagonal().array() -= C(r1, r2);
          if (options.static_mean_tangential) {
            b.row(0).setZero();
            b.row(m).setZero();
          }
          c.blocks[static_cast<std::size_t>(p)] = area * b;
        }
      }
    }
    return c;
  }

  // The fields of InterfacePointSummary from one point's periodic state and its gap coefficients.
  InterfacePointSummary summarise(int p, const ContactPointAftResult& pr, const Eigen::Ref<const MatrixXd>& dg) const {
    InterfacePointSummary s;
    s.dissipation = pr.dissipation;
    s.open_fraction = pr.open_fraction;
    s.stuck = pr.stuck;
    s.open = pr.shortcut == ContactPointShortcut::open;
    s.state = pr.state;
    s.limit_ratio = pr.limit_ratio;
    s.limit_share = pr.limit_share;
    const MatrixXd g = basis.to_time(dg);  // N × 3
    const Eigen::RowVector3d mean = g.colwise().mean();
    for (Index i = 0; i < g.rows(); ++i) {
      s.tangential_motion = std::max(s.tangential_motion, std::hypot(g(i, 0) - mean(0), g(i, 1) - mean(1)));
      s.normal_motion = std::max(s.normal_motion, std::abs(g(i, 2) - mean(2)));
    }
    const double t_ref = model.references[static_cast<std::size_t>(p)].traction.z();
    const Eigen::VectorXd pressure = -(t_ref + pr.traction_samples.col(2).array()).matrix();
    s.pressure_min = std::max(0.0, pressure.minCoeff());
    s.pressure_max = std::max(0.0, pressure.maxCoeff());
    return s;
  }

  // The residual-mode combination of eq. (T-23) per harmonic, given W0 = R0 V and W1 = R1 V
  // (rows × m, coefficients in columns): out += (R0 − s R1) V on the mean and c0 W0 + c1 W1 on
  // (a_k, b_k). `which`: 0 value, 1 ∂/∂Ω, 2 ∂/∂ξ (the mean does not depend on Ω or ξ).
  template <class Out>
  void combine_residual(const MatrixXd& w0, const MatrixXd& w1, double omega, double xi, int which,
                        Out&& out) const {
    if (which == 0) out.col(0) += w0.col(0) - model.residual_shift * w1.col(0);
    for (int k : basis.orders()) {
      const int ia = basis.cosine_index(k), ib = ia + 1;
      const ResidualCoefficients rc = residual_coefficients(model, k, omega, xi);
      const cd c0 = which == 0 ? rc.c0 : which == 1 ? rc.c0_omega : rc.c0_xi;
      const cd c1 = which == 0 ? rc.c1 : which == 1 ? rc.c1_omega : rc.c1_xi;
      add_complex_pair(c0, c1, w0.col(ia), w0.col(ib), w1.col(ia), w1.col(ib), out.col(ia), out.col(ib));
    }
  }

  // r_k(Ω, ξ) F: the load's residual-mode gaps (3P × m).
  void apply_load_residual(const VectorXd& load, double omega, double xi, int which, MatrixXd& out) const {
    if (load.size() == 0) return;
    combine_residual(model.load_residual0 * load.transpose(), model.load_residual1 * load.transpose(),
                     omega, xi, which, out);
  }

  // D_j(kΩ, ξ) on η_j's coefficients, or its derivative (which = 1: Ω, 2: ξ).
  void apply_modal(const MatrixXd& eta, double omega, double xi, int which, MatrixXd& out) const {
    for (int j = 0; j < ns; ++j) {
      const double w2 = model.omega2[j], c = modal_damping[j] - xi;
      if (which == 0) out(0, j) += j < model.rigid_modes ? omega_ref * omega_ref * eta(0, j) : w2 * eta(0, j);
      for (int k : basis.orders()) {
        const int ia = basis.cosine_index(k), ib = ia + 1;
        const double a = eta(ia, j), b = eta(ib, j), kw = k * omega;
        if (which == 0) {
          out(ia, j) += (w2 - kw * kw) * a + kw * c * b;
          out(ib, j) += (w2 - kw * kw) * b - kw * c * a;
        } else if (which == 1) {
          out(ia, j) += -2.0 * k * kw * a + k * c * b;
          out(ib, j) += -2.0 * k * kw * b - k * c * a;
        } else {
          out(ia, j) += -kw * b;
          out(ib, j) += kw * a;
        }
      }
    }
  }
};

InterfaceBalance::InterfaceBalance(InterfaceModel model, InterfaceBalanceOptions options) {
  if (const std::string msg = options.validate(); !msg.empty()) throw std::invalid_argument(msg);
  if (const std::string msg = model.validate(); !msg.empty())
    throw std::invalid_argument("interface model: " + msg);
  impl_ = std::make_unique<Impl>(std::move(model), options);
}
InterfaceBalance::~InterfaceBalance() = default;
InterfaceBalance::InterfaceBalance(InterfaceBalance&&) noexcept = default;
InterfaceBalance& InterfaceBalance::operator=(InterfaceBalance&&) noexcept = default;

const InterfaceModel& InterfaceBalance::model() const { return impl_->model; }
const FourierBasis& InterfaceBalance::basis() const { return impl_->basis; }
const InterfaceBalanceOptions& InterfaceBalance::options() const { return impl_->options; }
int InterfaceBalance::modes() const { return impl_->ns; }
int InterfaceBalance::points() const { return impl_->P; }
const contact::ContactPoint& InterfaceBalance::point_law(int p) const {
  if (p < 0 || p >= impl_->P) throw std::invalid_argument(fmt::format("point_law: point {} of {}", p, impl_->P));
  if (!impl_->frozen.empty()) return impl_->frozen[static_cast<std::size_t>(p)];
  for (const InterfaceGroup& g : impl_->model.groups)
    if (p < g.first + g.count) return g.law;
  return impl_->model.groups.back().law;
}
Index InterfaceBalance::unknowns() const { return impl_->U; }
Index InterfaceBalance::modal_index(int mode, int coefficient) const {
  return static_cast<Index>(mode) * impl_->m + coefficient;
}
Index InterfaceBalance::gap_index(int point, int component, int coefficient) const {
  return static_cast<Index>(impl_->ns + 3 * point + component) * impl_->m + coefficient;
}
double InterfaceBalance::reference_omega() const { return impl_->omega_ref; }
double InterfaceBalance::reference_gap() const { return impl_->g_ref; }
VectorXd InterfaceBalance::unknown_scale() const {
  VectorXd s = VectorXd::Ones(impl_->U);
  s.tail(impl_->U - static_cast<Index>(impl_->ns) * impl_->m).setConstant(impl_->g_ref);
  return s;
}
InterfaceBalanceTimings InterfaceBalance::timings() const { return impl_->timings; }

VectorXd InterfaceBalance::cosine_load(double amplitude) const {
  VectorXd f = VectorXd::Zero(impl_->m);
  f[impl_->basis.cosine_index(1)] = amplitude;
  return f;
}

std::vector<InterfacePointSummary> InterfaceBalance::point_summaries(const VectorXd& y) const {
  const Impl& d = *impl_;
  if (y.size() != d.U)
    throw std::invalid_argument(fmt::format("InterfaceBalance::point_summaries: {} unknowns, expected {}", y.size(), d.U));
  const Eigen::Map<const MatrixXd> dg(y.data() + static_cast<Index>(d.ns) * d.m, d.m, 3 * d.P);
  std::vector<InterfacePointSummary> summaries;
  (void)d.contact(dg, false, &summaries);
  return summaries;
}

void InterfaceBalance::evaluate(const VectorXd& y, double omega, double xi, const VectorXd& load,
                                bool jacobian, InterfaceBalanceEvaluation& out) const {
  const Impl& d = *impl_;
  if (y.size() != d.U)
    throw std::invalid_argument(fmt::format("InterfaceBalance::evaluate: {} unknowns, expected {}", y.size(), d.U));
  if (load.size() != 0 && load.size() != d.m)
    throw std::invalid_argument(fmt::format("InterfaceBalance::evaluate: load has {} coefficients, expected {}", load.size(), d.m));
  const int m = d.m, ns = d.ns, P = d.P;
  const auto t0 = support::Clock::now();
  const Eigen::Map<const MatrixXd> eta(y.data(), m, ns);
  const Eigen::Map<const MatrixXd> dg(y.data() + static_cast<Index>(ns) * m, m, 3 * P);
  const Impl::Contact c = d.contact(dg, jacobian);
  const auto t1 = support::Clock::now();
  d.timings.aft += support::seconds_between(t0, t1);
  ++d.timings.evaluations;
  out.ok = c.ok;
  out.message = c.message;
  out.dissipation = c.dissipation;
  out.open_points = c.open;
  out.slipping_points = c.states.slipping();
  out.states = c.states;
  out.drifting_points = c.drifting;
  out.contact_force = c.force;
  out.point_blocks.clear();
  out.fourier_dissipation = 0.0;
  for (int k : d.basis.orders()) {
    const int ia = d.basis.cosine_index(k), ib = ia + 1;
    out.fourier_dissipation += std::numbers::pi * k *
        (c.force.row(ia).dot(dg.row(ib)) - c.force.row(ib).dot(dg.row(ia)));
  }

  const MatrixXd& phi_g = d.model.gap_shapes;  // 3P × ns
  const double row_modal = 1.0 / (d.omega_ref * d.omega_ref), row_gap = 1.0 / d.g_ref;
  // Modal rows (m × ns), eq. (T-26).
  MatrixXd rm = c.force * phi_g;
  if (load.size() != 0) rm -= load * d.model.load_modal.transpose();
  d.apply_modal(eta, omega, xi, 0, rm);
  for (int j = 0; j < d.model.rigid_modes; ++j) rm(0, j) = d.omega_ref * d.omega_ref * eta(0, j);
  // Gap rows (3P × m), eq. (T-27). R0 (A N)ᵀ and R1 (A N)ᵀ once (BLAS), for R and its Ω, ξ derivatives.
  MatrixXd rg = dg.transpose() - phi_g * eta.transpose();
  const MatrixXd force_t = c.force.transpose();
  MatrixXd w0 = MatrixXd::Zero(3 * P, m), w1 = MatrixXd::Zero(3 * P, m);
  support::gemm_add_by_rows(d.model.residual_flexibility, force_t, w0, d.model.residual_inertia, w1);
  d.combine_residual(w0, w1, omega, xi, 0, rg);
  MatrixXd load_gap = MatrixXd::Zero(3 * P, m);
  d.apply_load_residual(load, omega, xi, 0, load_gap);
  rg -= load_gap;
  out.residual.resize(d.U);
  Eigen::Map<MatrixXd>(out.residual.data(), m, ns) = row_modal * rm;
  Eigen::Map<MatrixXd>(out.residual.data() + static_cast<Index>(ns) * m, m, 3 * P) = row_gap * rg.transpose();
  if (!jacobian) {
    d.timings.assembly += support::seconds_since(t1);
    return;
  }
  ++d.timings.jacobians;

  // ∂/∂Ω and ∂/∂ξ.
  for (int which = 1; which <= 2; ++which) {
    MatrixXd dm = MatrixXd::Zero(m, ns);
    d.apply_modal(eta, omega, xi, which, dm);
    for (int j = 0; j < d.model.rigid_modes; ++j) dm(0, j) = 0.0;
    MatrixXd dgap = MatrixXd::Zero(3 * P, m);
    d.combine_residual(w0, w1, omega, xi, which, dgap);
    MatrixXd dl = MatrixXd::Zero(3 * P, m);
    d.apply_load_residual(load, omega, xi, which, dl);
    dgap -= dl;
    VectorXd& v = which == 1 ? out.d_omega : out.d_xi;
    v.resize(d.U);
    Eigen::Map<MatrixXd>(v.data(), m, ns) = row_modal * dm;
    Eigen::Map<MatrixXd>(v.data() + static_cast<Index>(ns) * m, m, 3 * P) = row_gap * dgap.transpose();
  }

  if (!d.options.dense_jacobian) {
    out.jacobian.resize(0, 0);
    out.point_blocks = c.blocks;
    d.timings.assembly += support::seconds_since(t1);
    return;
  }
  out.point_blocks = c.blocks;
  MatrixXd& J = out.jacobian;
  J.setZero(d.U, d.U);
  const Index g0 = static_cast<Index>(ns) * m;  // first gap unknown
  // Modal/modal: D_j.
  for (int j = 0; j < ns; ++j) {
    const Index r = static_cast<Index>(j) * m;
    const double w2 = d.model.omega2[j], cj = d.modal_damping[j] - xi;
    J(r, r) = j < d.model.rigid_modes ? d.omega_ref * d.omega_ref : w2;
    for (int k : d.basis.orders()) {
      const int ia = d.basis.cosine_index(k), ib = ia + 1;
      const double kw = k * omega;
      J(r + ia, r + ia) = w2 - kw * kw;
      J(r + ia, r + ib) = kw * cj;
      J(r + ib, r + ib) = w2 - kw * kw;
      J(r + ib, r + ia) = -kw * cj;
    }
  }
  // Gap/modal: −Gφ_j per coefficient; gap/gap identity.
  for (int i = 0; i < 3 * P; ++i)
    for (int cc = 0; cc < m; ++cc) {
      const Index r = g0 + static_cast<Index>(i) * m + cc;
      for (int j = 0; j < ns; ++j) J(r, static_cast<Index>(j) * m + cc) = -phi_g(i, j);
      J(r, r) = 1.0;
    }
  // Contact columns, point by point: (Gφ)ᵀ B_p on the modal rows, R B_p on the gap rows.
  std::vector<ResidualCoefficients> rcs;
  for (int k : d.basis.orders()) rcs.push_back(residual_coefficients(d.model, k, omega, xi));
  const MatrixXd& R0 = d.model.residual_flexibility;
  const MatrixXd& R1 = d.model.residual_inertia;
  const double s = d.model.residual_shift;
#pragma omp parallel for schedule(dynamic, 4)
  for (int p = 0; p < P; ++p) {
    const MatrixXd& B = c.blocks[static_cast<std::size_t>(p)];
    const Index col = g0 + static_cast<Index>(3 * p) * m;
    // Rows of B for coefficient cc of the three components (3 × 3m).
    auto rows_of = [&](int cc) {
      MatrixXd r(3, 3 * m);
      for (int dd = 0; dd < 3; ++dd) r.row(dd) = B.row(dd * m + cc);
      return r;
    };
    const MatrixXd phi_p = phi_g.middleRows(3 * p, 3);  // 3 × ns
    for (int cc = 0; cc < m; ++cc) {
      const MatrixXd t = phi_p.transpose() * rows_of(cc);  // ns × 3m
      for (int j = 0; j < ns; ++j) {
        if (j < d.model.rigid_modes && cc == 0) continue;
        J.block(static_cast<Index>(j) * m + cc, col, 1, 3 * m) += t.row(j);
      }
    }
    const MatrixXd r0p = R0.middleCols(3 * p, 3), r1p = R1.middleCols(3 * p, 3);
    {
      const MatrixXd t = (r0p - s * r1p) * rows_of(0);  // 3P × 3m
      for (int i = 0; i < 3 * P; ++i) J.block(g0 + static_cast<Index>(i) * m, col, 1, 3 * m) += t.row(i);
    }
    std::size_t h = 0;
    for (int k : d.basis.orders()) {
      const int ia = d.basis.cosine_index(k), ib = ia + 1;
      const ResidualCoefficients& rc = rcs[h++];
      const MatrixXd rr = rc.c0.real() * r0p + rc.c1.real() * r1p;
      const MatrixXd ri = rc.c0.imag() * r0p + rc.c1.imag() * r1p;
      const MatrixXd ba = rows_of(ia), bb = rows_of(ib);
      const MatrixXd ta = rr * ba + ri * bb, tb = rr * bb - ri * ba;
      for (int i = 0; i < 3 * P; ++i) {
        const Index r = g0 + static_cast<Index>(i) * m;
        J.block(r + ia, col, 1, 3 * m) += ta.row(i);
        J.block(r + ib, col, 1, 3 * m) += tb.row(i);
      }
    }
  }
  J.topRows(g0) *= row_modal;
  J.bottomRows(d.U - g0) *= row_gap;
  d.timings.assembly += support::seconds_since(t1);
}

VectorXd InterfaceBalance::apply_jacobian(const InterfaceBalanceEvaluation& at, double omega,
                                          double xi, const VectorXd& v, bool single_precision) const {
  const Impl& d = *impl_;
  const int m = d.m, ns = d.ns, P = d.P;
  if (v.size() != d.U || at.point_blocks.size() != static_cast<std::size_t>(P))
    throw std::invalid_argument(fmt::format(
        "InterfaceBalance::apply_jacobian: v has {} entries (expected {}), {} point blocks (expected {}: "
        "an evaluation with the Jacobian)", v.size(), d.U, at.point_blocks.size(), P));
  const auto t0 = support::Clock::now();
  const Eigen::Map<const MatrixXd> v_eta(v.data(), m, ns);
  const Eigen::Map<const MatrixXd> v_gap(v.data() + static_cast<Index>(ns) * m, m, 3 * P);
  // W = B v per point (the directional derivative of A N), m × 3P like contact_force; point p's
  // 3m entries are contiguous in v and in W (component-major), as B_p is ordered.
  // Serial: 9m² flops per point is far below the cost of an OpenMP fork/join on a loaded machine
  // (measured 10× slower with 2 threads on the 96-point lap).
  MatrixXd w(m, 3 * P);
  for (int p = 0; p < P; ++p) {
    const Eigen::Map<const VectorXd> vp(v_gap.data() + static_cast<Index>(3 * p) * m, 3 * m);
    Eigen::Map<VectorXd>(w.data() + static_cast<Index>(3 * p) * m, 3 * m).noalias() =
        at.point_blocks[static_cast<std::size_t>(p)] * vp;
  }
  const MatrixXd& phi_g = d.model.gap_shapes;
  const double row_modal = 1.0 / (d.omega_ref * d.omega_ref), row_gap = 1.0 / d.g_ref;
  // Modal rows, linear part of (T-26): D_j v_η,j + (Gφ_j)ᵀ W; rigid modes' mean: ω_ref² v.
  MatrixXd rm = w * phi_g;
  d.apply_modal(v_eta, omega, xi, 0, rm);
  for (int j = 0; j < d.model.rigid_modes; ++j) rm(0, j) = d.omega_ref * d.omega_ref * v_eta(0, j);
  // Gap rows, linear part of (T-27): v_g − Gφ v_η + R_k W_k.
  MatrixXd rg = v_gap.transpose() - phi_g * v_eta.transpose();
  // R0 Wᵀ and R1 Wᵀ through BLAS dgemm: Eigen's own product packs the whole 3P × 3P matrix for
  // the m right-hand columns (half the time of a product on the 192-point lap).
  const MatrixXd wt = w.transpose();
  MatrixXd w0 = MatrixXd::Zero(3 * P, m), w1 = MatrixXd::Zero(3 * P, m);
  if (single_precision) {
    const Impl::SingleCopies& r = d.single_copies();
    const Eigen::MatrixXf wf = wt.cast<float>();
    Eigen::MatrixXf f0 = Eigen::MatrixXf::Zero(3 * P, m), f1 = Eigen::MatrixXf::Zero(3 * P, m);
    support::gemm_add_by_rows(r.r0, wf, f0, r.r1, f1);
    w0 = f0.cast<double>();
    w1 = f1.cast<double>();
  } else {
    support::gemm_add_by_rows(d.model.residual_flexibility, wt, w0, d.model.residual_inertia, w1);
  }
  d.combine_residual(w0, w1, omega, xi, 0, rg);
  VectorXd out(d.U);
  Eigen::Map<MatrixXd>(out.data(), m, ns) = row_modal * rm;
  Eigen::Map<MatrixXd>(out.data() + static_cast<Index>(ns) * m, m, 3 * P) = row_gap * rg.transpose();
  d.timings.products += support::seconds_since(t0);
  ++d.timings.product_calls;
  return out;
}

struct InterfaceHarmonicPreconditioner::Impl {
  int m = 0, ns = 0, n_gap = 0;  // coefficients, kept modes, 3P
  std::vector<std::vector<int>> coefficients;  // per harmonic: {0} or {a_k, b_k}
  std::vector<int> orders;                     // per harmonic: 0 (mean) or k
  std::vector<MatrixXd> blocks;
  std::vector<std::unique_ptr<support::LapackLu>> lus;
  double rcond = 0.0;
  Index global(int k, Index local) const {
    const std::vector<int>& c = coefficients[static_cast<std::size_t>(k)];
    const Index d = static_cast<Index>(c.size());
    const Index unknown = local / d;  // η_j (j < ns) or δg_i (ns + i)
    return unknown * m + c[static_cast<std::size_t>(local % d)];
  }
};

InterfaceHarmonicPreconditioner::InterfaceHarmonicPreconditioner() : impl_(std::make_unique<Impl>()) {}
InterfaceHarmonicPreconditioner::~InterfaceHarmonicPreconditioner() = default;
double InterfaceHarmonicPreconditioner::rcond() const { return impl_->rcond; }
const MatrixXd& InterfaceHarmonicPreconditioner::block(int k) const {
  return impl_->blocks.at(static_cast<std::size_t>(k));
}
Index InterfaceHarmonicPreconditioner::global_index(int k, Index local) const { return impl_->global(k, local); }

VectorXd InterfaceHarmonicPreconditioner::solve(const VectorXd& v) const {
  const Impl& d = *impl_;
  VectorXd out(v.size());
  for (std::size_t k = 0; k < d.blocks.size(); ++k) {
    const Index n = d.blocks[k].rows();
    VectorXd local(n);
    for (Index i = 0; i < n; ++i) local[i] = v[d.global(static_cast<int>(k), i)];
    const VectorXd x = d.lus[k]->solve(local);
    for (Index i = 0; i < n; ++i) out[d.global(static_cast<int>(k), i)] = x[i];
  }
  return out;
}

// J̃_k (eq. T-32c): the rows and columns of harmonic k of the Jacobian assembled in evaluate(),
// with B_p restricted to harmonic k's coefficients. Local order: η_j (j < ns) then δg_i
// (i < 3P), each with its d coefficients innermost.
std::shared_ptr<const InterfaceHarmonicPreconditioner> InterfaceBalance::harmonic_preconditioner(
    const InterfaceBalanceEvaluation& at, double omega, double xi) const {
  const Impl& d = *impl_;
  const int m = d.m, ns = d.ns, P = d.P;
  if (at.point_blocks.size() != static_cast<std::size_t>(P))
    throw std::invalid_argument(fmt::format(
        "InterfaceBalance::harmonic_preconditioner: {} point blocks, expected {} (an evaluation with the Jacobian)",
        at.point_blocks.size(), P));
  const auto t0 = support::Clock::now();
  auto pc = std::make_shared<InterfaceHarmonicPreconditioner>();
  InterfaceHarmonicPreconditioner::Impl& h = *pc->impl_;
  h.m = m;
  h.ns = ns;
  h.n_gap = 3 * P;
  h.coefficients.push_back({0});
  h.orders.push_back(0);
  for (int k : d.basis.orders()) {
    h.coefficients.push_back({d.basis.cosine_index(k), d.basis.cosine_index(k) + 1});
    h.orders.push_back(k);
  }
  const int harmonics = static_cast<int>(h.coefficients.size());
  h.blocks.resize(static_cast<std::size_t>(harmonics));
  h.lus.resize(static_cast<std::size_t>(harmonics));
  const MatrixXd& phi_g = d.model.gap_shapes;
  const MatrixXd& R0 = d.model.residual_flexibility;
  const MatrixXd& R1 = d.model.residual_inertia;
  const double row_modal = 1.0 / (d.omega_ref * d.omega_ref), row_gap = 1.0 / d.g_ref;
  std::vector<double> rconds(static_cast<std::size_t>(harmonics), 0.0);
#pragma omp parallel for schedule(dynamic, 1)
  for (int kk = 0; kk < harmonics; ++kk) {
    const std::vector<int>& idx = h.coefficients[static_cast<std::size_t>(kk)];
    const int dk = static_cast<int>(idx.size());
    const Index n = static_cast<Index>(ns + 3 * P) * dk, g0 = static_cast<Index>(ns) * dk;
    MatrixXd& J = h.blocks[static_cast<std::size_t>(kk)];
    J.setZero(n, n);
    // D_j, −Gφ, I (as in evaluate()).
    const int order = h.orders[static_cast<std::size_t>(kk)];
    const double kw = order * omega;
    for (int j = 0; j < ns; ++j) {
      const double w2 = d.model.omega2[j], cj = d.modal_damping[j] - xi;
      const Index r = static_cast<Index>(j) * dk;
      if (kk == 0) {
        J(r, r) = j < d.model.rigid_modes ? d.omega_ref * d.omega_ref : w2;
      } else {
        J(r, r) = J(r + 1, r + 1) = w2 - kw * kw;
        J(r, r + 1) = kw * cj;
        J(r + 1, r) = -kw * cj;
      }
    }
    for (int i = 0; i < 3 * P; ++i)
      for (int t = 0; t < dk; ++t) {
        const Index r = g0 + static_cast<Index>(i) * dk + t;
        for (int j = 0; j < ns; ++j) J(r, static_cast<Index>(j) * dk + t) = -phi_g(i, j);
        J(r, r) = 1.0;
      }
    // R_k as the real pair map (a, b) ↦ (Rr a + Ri b, −Ri a + Rr b) (add_complex_pair), or
    // R0 − s R1 on the mean.
    MatrixXd rr, ri;
    if (kk == 0) {
      rr = R0 - d.model.residual_shift * R1;
    } else {
      const ResidualCoefficients rc = residual_coefficients(d.model, order, omega, xi);
      rr = rc.c0.real() * R0 + rc.c1.real() * R1;
      ri = rc.c0.imag() * R0 + rc.c1.imag() * R1;
    }
    for (int p = 0; p < P; ++p) {
      const MatrixXd& B = at.point_blocks[static_cast<std::size_t>(p)];
      // b_t (3 × 3dk): rows (component c1, coefficient idx[t]), columns (c2, t2) → (3p + c2)·dk + t2.
      std::vector<MatrixXd> b(static_cast<std::size_t>(dk), MatrixXd(3, 3 * dk));
      for (int t = 0; t < dk; ++t)
        for (int c1 = 0; c1 < 3; ++c1)
          for (int c2 = 0; c2 < 3; ++c2)
            for (int t2 = 0; t2 < dk; ++t2)
              b[static_cast<std::size_t>(t)](c1, c2 * dk + t2) = B(c1 * m + idx[static_cast<std::size_t>(t)], c2 * m + idx[static_cast<std::size_t>(t2)]);
      const Index col = g0 + static_cast<Index>(3 * p) * dk;
      const MatrixXd phi_p = phi_g.middleRows(3 * p, 3).transpose();  // ns × 3
      for (int t = 0; t < dk; ++t) {
        const MatrixXd mt = phi_p * b[static_cast<std::size_t>(t)];  // ns × 3dk
        for (int j = 0; j < ns; ++j) {
          if (kk == 0 && j < d.model.rigid_modes) continue;
          J.block(static_cast<Index>(j) * dk + t, col, 1, 3 * dk) += mt.row(j);
        }
      }
      const MatrixXd rr_p = rr.middleCols(3 * p, 3);
      if (kk == 0) {
        const MatrixXd g = rr_p * b[0];  // 3P × 3
        for (int i = 0; i < 3 * P; ++i) J.block(g0 + i, col, 1, 3) += g.row(i);
      } else {
        const MatrixXd ri_p = ri.middleCols(3 * p, 3);
        const MatrixXd ga = rr_p * b[0] + ri_p * b[1], gb = rr_p * b[1] - ri_p * b[0];  // 3P × 6
        for (int i = 0; i < 3 * P; ++i) {
          J.block(g0 + 2 * i, col, 1, 6) += ga.row(i);
          J.block(g0 + 2 * i + 1, col, 1, 6) += gb.row(i);
        }
      }
    }
    J.topRows(g0) *= row_modal;
    J.bottomRows(n - g0) *= row_gap;
  }
  // Factored after the parallel loop, one block after the other: LAPACK (the serial OpenBLAS) is
  // not reentrant and must not be called from two threads at once (support/blas_gemm.hpp).
  for (int kk = 0; kk < harmonics; ++kk) {
    h.lus[static_cast<std::size_t>(kk)] = std::make_unique<support::LapackLu>(h.blocks[static_cast<std::size_t>(kk)]);
    rconds[static_cast<std::size_t>(kk)] = h.lus[static_cast<std::size_t>(kk)]->rcond();
  }
  h.rcond = *std::min_element(rconds.begin(), rconds.end());
  d.timings.preconditioner += support::seconds_since(t0);
  ++d.timings.preconditioners;
  return pc;
}

std::function<VectorXd(const VectorXd&)> InterfaceBalance::preconditioner(
    const InterfaceBalanceEvaluation& at, double omega, double xi, InterfacePreconditioner kind) const {
  InterfaceBalanceTimings* timings = &impl_->timings;
  // Applications are timed into timings().preconditioner_apply.
  const auto timed = [timings](auto inverse) {
    return [inverse = std::move(inverse), timings](const VectorXd& v) {
      const auto t0 = support::Clock::now();
      VectorXd z = inverse->solve(v);
      timings->preconditioner_apply += support::seconds_since(t0);
      ++timings->preconditioner_calls;
      return z;
    };
  };
  if (kind == InterfacePreconditioner::harmonic_blocks) return timed(harmonic_preconditioner(at, omega, xi));
  const auto t0 = support::Clock::now();
  auto local = std::make_shared<const InterfaceLocalPreconditioner>(*this, at, omega, xi);
  timings->preconditioner += support::seconds_since(t0);
  ++timings->preconditioners;
  return timed(std::move(local));
}

VectorXd InterfaceBalance::linear_solution(double omega, const VectorXd& load) const {
  const Impl& d = *impl_;
  const int m = d.m, ns = d.ns, P = d.P;
  VectorXd y = VectorXd::Zero(d.U);
  if (load.size() == 0) return y;
  Eigen::Map<MatrixXd> eta(y.data(), m, ns);
  for (int j = 0; j < ns; ++j) {
    const double fj = d.model.load_modal[j];
    if (j >= d.model.rigid_modes) eta(0, j) = fj * load[0] / d.model.omega2[j];
    for (int k : d.basis.orders()) {
      const int ia = d.basis.cosine_index(k), ib = ia + 1;
      const double kw = k * omega;
      const cd h = 1.0 / cd(d.model.omega2[j] - kw * kw, kw * d.modal_damping[j]);
      const cd x = h * fj * cd(load[ia], -load[ib]);
      eta(ia, j) = x.real();
      eta(ib, j) = -x.imag();
    }
  }
  MatrixXd gaps = d.model.gap_shapes * eta.transpose();  // 3P × m
  d.apply_load_residual(load, omega, 0.0, 0, gaps);
  Eigen::Map<MatrixXd>(y.data() + static_cast<Index>(ns) * m, m, 3 * P) = gaps.transpose();
  return y;
}

VectorXd InterfaceBalance::output_coefficients(int output, const VectorXd& y, double omega,
                                               double xi, const VectorXd& load,
                                               const MatrixXd& contact_force) const {
  const Impl& d = *impl_;
  if (output < 0 || output >= static_cast<int>(d.model.outputs.size()))
    throw std::invalid_argument(fmt::format("output_coefficients: no output {}", output));
  const InterfaceOutput& o = d.model.outputs[static_cast<std::size_t>(output)];
  const int m = d.m;
  const Eigen::Map<const MatrixXd> eta(y.data(), m, d.ns);
  VectorXd u = eta * o.modal;
  // Residual part: [c0 ρ0 + c1 ρ1]·F − [c0 r0 + c1 r1]ᵀ A N (eq. T-25 for the output functional).
  const VectorXd v0 = contact_force * o.residual0, v1 = contact_force * o.residual1;  // m
  VectorXd f0 = VectorXd::Zero(m), f1 = VectorXd::Zero(m);
  if (load.size() != 0) f0 = o.load_residual0 * load, f1 = o.load_residual1 * load;
  const MatrixXd p0 = (f0 - v0).transpose(), p1 = (f1 - v1).transpose();  // 1 × m
  MatrixXd residual = MatrixXd::Zero(1, m);
  d.combine_residual(p0, p1, omega, xi, 0, residual);
  u += residual.transpose();
  return u;
}

}  // namespace jointhb::hb
