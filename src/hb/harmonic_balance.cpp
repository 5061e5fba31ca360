#include "jointhb/hb/harmonic_balance.hpp"

#include "../support/stopwatch.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "jointhb/hb/contact_aft.hpp"

namespace jointhb::hb {
namespace {

using support::Clock;
using support::seconds_since;
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr int kMaxHarmonics = 1024;
constexpr int kMaxTimeSamples = 1 << 20;

}  // namespace

bool is_symmetric(const DiscreteSystem& system, const Excitation& excitation) {
  if (excitation.has_static_part()) return false;
  for (const auto& f : excitation.forces) {
    if (f.harmonic % 2 == 0) return false;
  }
  for (const auto& c : system.contacts) {
    if (!c.odd()) return false;
  }
  return true;
}

double fourier_work(const FourierBasis& basis, const Eigen::VectorXd& force,
                    const Eigen::VectorXd& gap) {
  double w = 0.0;
  for (int k : basis.orders()) {
    const int a = basis.cosine_index(k);
    w += k * (force[a] * gap[a + 1] - force[a + 1] * gap[a]);
  }
  return std::numbers::pi * w;
}

std::string HarmonicBalanceOptions::validate() const {
  if (harmonics < 1 || harmonics > kMaxHarmonics) {
    return fmt::format("harmonics: must be in [1, {}], got {}", kMaxHarmonics, harmonics);
  }
  if (time_samples < 2 * harmonics + 2 || time_samples > kMaxTimeSamples) {
    return fmt::format("time_samples: must be in [2 harmonics + 2 = {}, {}], got {}",
                       2 * harmonics + 2, kMaxTimeSamples, time_samples);
  }
  if (!(periodic_tolerance > 0.0 && periodic_tolerance <= 1e-3)) {
    return fmt::format("periodic_tolerance: must be in (0, 1e-3], got {}", periodic_tolerance);
  }
  return {};
}

struct HarmonicBalance::Impl {
  DiscreteSystem system;
  Excitation excitation;
  HarmonicBalanceOptions options;
  FourierBasis basis;
  std::vector<std::shared_ptr<const contact::TangentialLaw>> laws;
  Eigen::VectorXd forcing;  // F_ex
  mutable HarmonicBalanceTimings timings;

  Impl(DiscreteSystem s, Excitation e, HarmonicBalanceOptions o, bool odd)
      : system(std::move(s)),
        excitation(std::move(e)),
        options(o),
        basis(o.harmonics, o.time_samples, odd) {}

  [[nodiscard]] int n() const { return system.dofs(); }
  [[nodiscard]] int m() const { return basis.size(); }

  // Adds the sparse matrix `a` times `factor` into the (DOF-major) block pattern of coefficient
  // rows `row_c` and columns `col_c` of a dense n·m × n·m matrix.
  void scatter(const SparseMatrix& a, double factor, int row_c, int col_c,
               Eigen::MatrixXd& j) const {
    if (factor == 0.0 || a.nonZeros() == 0) return;
    const int mm = m();
    for (int col = 0; col < a.outerSize(); ++col) {
      for (SparseMatrix::InnerIterator it(a, col); it; ++it) {
        j(it.row() * mm + row_c, it.col() * mm + col_c) += factor * it.value();
      }
    }
  }

  // S(Ω) into j (∂R/∂Ω = S'(Ω) X is formed directly as a vector in evaluate).
  void assemble_linear(double omega, Eigen::MatrixXd& j) const {
    const SparseMatrix& k = system.stiffness;
    const SparseMatrix& mass = system.mass;
    const SparseMatrix& c = system.damping;
    if (basis.has_mean()) scatter(k, 1.0, 0, 0, j);
    for (int h : basis.orders()) {
      const int a = basis.cosine_index(h);
      const double w = h * omega;
      // S_k: [K − w² M, w C; −w C, K − w² M]
      for (int p = 0; p < 2; ++p) {
        scatter(k, 1.0, a + p, a + p, j);
        scatter(mass, -w * w, a + p, a + p, j);
      }
      scatter(c, w, a, a + 1, j);
      scatter(c, -w, a + 1, a, j);
    }
  }

  // Coefficients of a contact's gap g = x_a − x_b from X.
  [[nodiscard]] Eigen::VectorXd gap_coefficients(const Eigen::VectorXd& x,
                                                 const ContactElement& c) const {
    Eigen::VectorXd g = x.segment(static_cast<Eigen::Index>(c.dof_a) * m(), m());
    if (c.dof_b >= 0) g -= x.segment(static_cast<Eigen::Index>(c.dof_b) * m(), m());
    return g;
  }

  // Adds +v to DOF a's coefficients and −v to DOF b's.
  void scatter_force(const ContactElement& c, const Eigen::VectorXd& v, Eigen::VectorXd& r) const {
    r.segment(static_cast<Eigen::Index>(c.dof_a) * m(), m()) += v;
    if (c.dof_b >= 0) r.segment(static_cast<Eigen::Index>(c.dof_b) * m(), m()) -= v;
  }

  void scatter_block(const ContactElement& c, const Eigen::MatrixXd& d, Eigen::MatrixXd& j) const {
    const Eigen::Index a = static_cast<Eigen::Index>(c.dof_a) * m();
    j.block(a, a, m(), m()) += d;
    if (c.dof_b < 0) return;
    const Eigen::Index b = static_cast<Eigen::Index>(c.dof_b) * m();
    j.block(b, b, m(), m()) += d;
    j.block(a, b, m(), m()) -= d;
    j.block(b, a, m(), m()) -= d;
  }
};

HarmonicBalance::HarmonicBalance(DiscreteSystem system, Excitation excitation,
                                 HarmonicBalanceOptions options) {
  if (auto msg = system.validate(); !msg.empty()) throw std::invalid_argument(msg);
  if (auto msg = options.validate(); !msg.empty()) throw std::invalid_argument(msg);
  const int n = system.dofs();
  if (excitation.static_force.size() != 0 && excitation.static_force.size() != n) {
    throw std::invalid_argument(fmt::format("excitation.static_force: must have {} entries, got {}",
                                            n, excitation.static_force.size()));
  }
  const bool symmetric = is_symmetric(system, excitation);
  if (options.selection == HarmonicSelection::odd && !symmetric) {
    throw std::invalid_argument(
        "harmonic_selection: odd harmonics only need a symmetric case (no static force, odd "
        "forcing harmonics, zero contact reference force and slip, no normal element)");
  }
  const bool odd = options.selection == HarmonicSelection::odd ||
                   (options.selection == HarmonicSelection::automatic && symmetric);
  impl_ = std::make_unique<Impl>(std::move(system), std::move(excitation), options, odd);
  Impl& p = *impl_;
  for (const auto& c : p.system.contacts) p.laws.push_back(DiscreteSystem::make_law(c));

  p.forcing = Eigen::VectorXd::Zero(unknowns());
  for (const auto& f : p.excitation.forces) {
    const int a = p.basis.cosine_index(f.harmonic);
    if (f.dof < 0 || f.dof >= n) {
      throw std::invalid_argument(fmt::format("excitation: dof {} outside [0, {}]", f.dof, n - 1));
    }
    if (a < 0) {
      throw std::invalid_argument(
          fmt::format("excitation: forcing harmonic {} is not in the harmonic basis (H = {}{})",
                      f.harmonic, p.basis.harmonics(), p.basis.odd_only() ? ", odd only" : ""));
    }
    p.forcing[index(f.dof, a)] += f.amplitude;
  }
  if (p.excitation.has_static_part()) {
    for (int i = 0; i < n; ++i) p.forcing[index(i, 0)] += p.excitation.static_force[i];
  }
}

HarmonicBalance::~HarmonicBalance() = default;
HarmonicBalance::HarmonicBalance(HarmonicBalance&&) noexcept = default;
HarmonicBalance& HarmonicBalance::operator=(HarmonicBalance&&) noexcept = default;

const FourierBasis& HarmonicBalance::basis() const { return impl_->basis; }
const DiscreteSystem& HarmonicBalance::system() const { return impl_->system; }
const HarmonicBalanceOptions& HarmonicBalance::options() const { return impl_->options; }
Eigen::Index HarmonicBalance::unknowns() const {
  return static_cast<Eigen::Index>(impl_->n()) * impl_->m();
}
Eigen::Index HarmonicBalance::index(int dof, int coefficient) const {
  return static_cast<Eigen::Index>(dof) * impl_->m() + coefficient;
}

void HarmonicBalance::evaluate(const Eigen::VectorXd& x, double omega, bool jacobian,
                               HarmonicBalanceEvaluation& out) const {
  const Impl& p = *impl_;
  const Eigen::Index size = unknowns();
  if (x.size() != size) {
    throw std::invalid_argument(
        fmt::format("HarmonicBalance::evaluate: {} coefficients, expected {}", x.size(), size));
  }
  auto start = Clock::now();
  out.ok = true;
  out.message.clear();
  out.dissipation = 0.0;
  out.fourier_dissipation = 0.0;
  const int n = p.n();
  const int m = p.m();

  // Linear part S(Ω) X, DOF-major: row i of the n × m view holds DOF i's coefficients.
  const Eigen::Map<const RowMajor> xm(x.data(), n, m);
  const RowMajor kx = p.system.stiffness * xm;
  const RowMajor mx = p.system.mass * xm;
  RowMajor cx = RowMajor::Zero(n, m);
  if (p.system.damping.nonZeros() > 0) cx = p.system.damping * xm;
  RowMajor r = kx;
  RowMajor dr = RowMajor::Zero(n, m);
  for (int h : p.basis.orders()) {
    const int a = p.basis.cosine_index(h);
    const double w = h * omega;
    r.col(a) += -w * w * mx.col(a) + w * cx.col(a + 1);
    r.col(a + 1) += -w * w * mx.col(a + 1) - w * cx.col(a);
    dr.col(a) = -2.0 * h * w * mx.col(a) + h * cx.col(a + 1);
    dr.col(a + 1) = -2.0 * h * w * mx.col(a + 1) - h * cx.col(a);
  }
  out.residual = Eigen::Map<const Eigen::VectorXd>(r.data(), size) - p.forcing;
  if (jacobian) {
    out.d_omega = Eigen::Map<const Eigen::VectorXd>(dr.data(), size);
    out.d_coefficients.setZero(size, size);
    p.assemble_linear(omega, out.d_coefficients);
  }
  p.timings.assembly += seconds_since(start);

  // Contact forces by AFT: gaps of all contacts to the time domain in one batched transform.
  start = Clock::now();
  const auto nc = static_cast<Eigen::Index>(p.system.contacts.size());
  out.contacts.assign(static_cast<std::size_t>(nc), ContactDiagnostics{});
  if (nc > 0) {
    Eigen::MatrixXd gaps(m, nc);
    for (Eigen::Index c = 0; c < nc; ++c) {
      gaps.col(c) = p.gap_coefficients(x, p.system.contacts[static_cast<std::size_t>(c)]);
    }
    const Eigen::MatrixXd gap_samples = p.basis.to_time(gaps);
    Eigen::MatrixXd force_samples(p.basis.time_samples(), nc);
    std::vector<Eigen::MatrixXd> blocks(static_cast<std::size_t>(nc));
    ContactAftOptions ao;
    ao.periodic_tolerance = p.options.periodic_tolerance;
    ao.skip_stuck = p.options.skip_stuck_contacts;
    ao.jacobian = jacobian;
    for (Eigen::Index c = 0; c < nc; ++c) {
      const auto k = static_cast<std::size_t>(c);
      ContactAftResult a =
          evaluate_contact(p.system.contacts[k], *p.laws[k], p.basis, gap_samples.col(c), ao);
      force_samples.col(c) = a.force_samples;
      blocks[k] = std::move(a.d_force);
      ContactDiagnostics& d = out.contacts[k];
      d.dissipation = a.dissipation;
      d.stuck = a.stuck;
      d.state = a.state;
      d.limit_ratio = a.limit_ratio;
      d.skipped = a.skipped;
      d.iterations = a.iterations;
      d.converged = a.converged;
      out.dissipation += a.dissipation;
      if (!a.converged && out.ok) {
        out.ok = false;
        out.message = fmt::format("contacts[{}]: periodic state not converged{}", c,
                                  a.message.empty() ? "" : ": " + a.message);
      }
    }
    const Eigen::MatrixXd forces = p.basis.to_frequency(force_samples);
    p.timings.aft += seconds_since(start);
    start = Clock::now();
    for (Eigen::Index c = 0; c < nc; ++c) {
      const auto k = static_cast<std::size_t>(c);
      p.scatter_force(p.system.contacts[k], forces.col(c), out.residual);
      const double w = fourier_work(p.basis, forces.col(c), gaps.col(c));
      out.contacts[k].fourier_dissipation = w;
      out.fourier_dissipation += w;
      if (jacobian) p.scatter_block(p.system.contacts[k], blocks[k], out.d_coefficients);
    }
    p.timings.assembly += seconds_since(start);
  }
  ++p.timings.evaluations;
  if (jacobian) ++p.timings.jacobians;
  if (!out.residual.allFinite() && out.ok) {
    out.ok = false;
    out.message = "non-finite residual";
  }
}

const Eigen::VectorXd& HarmonicBalance::forcing() const { return impl_->forcing; }

Eigen::VectorXd HarmonicBalance::stuck_solution(double omega, double forcing_scale) const {
  const Impl& p = *impl_;
  const Eigen::Index size = unknowns();
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(size, size);
  p.assemble_linear(omega, j);
  Eigen::VectorXd rhs = forcing_scale * p.forcing;
  const int m = p.m();
  for (const auto& c : p.system.contacts) {
    p.scatter_block(c, c.stiffness * Eigen::MatrixXd::Identity(m, m), j);
    if (p.basis.has_mean()) {
      // F = F_ref + k (g − g_ref): the constant part moves to the right-hand side.
      Eigen::VectorXd constant = Eigen::VectorXd::Zero(m);
      constant[0] = c.reference_force - c.stiffness * c.reference_slip;
      p.scatter_force(c, -constant, rhs);
    }
  }
  return j.partialPivLu().solve(rhs);
}

Eigen::VectorXd HarmonicBalance::time_history(const Eigen::VectorXd& x, int dof) const {
  const Impl& p = *impl_;
  return p.basis.to_time(x.segment(index(dof, 0), p.m()));
}

double HarmonicBalance::fundamental_amplitude(const Eigen::VectorXd& x, int dof) const {
  const int a = impl_->basis.cosine_index(1);
  if (a < 0) return 0.0;
  return std::hypot(x[index(dof, a)], x[index(dof, a + 1)]);
}

double HarmonicBalance::max_slip_ratio(const Eigen::VectorXd& x) const {
  const FourierBasis& basis = impl_->basis;
  const Eigen::Index m = basis.size();
  double worst = 0.0;
  for (const ContactElement& c : impl_->system.contacts) {
    if (c.normal()) continue;  // elastic: no stick range (overflow shows as non-finite forces)
    Eigen::VectorXd g = x.segment(index(c.dof_a, 0), m);
    if (c.dof_b >= 0) g -= x.segment(index(c.dof_b, 0), m);
    worst = std::max(worst, basis.peak_magnitude(g) * c.stiffness / c.slip_limit());
  }
  return worst;
}

HarmonicBalanceTimings HarmonicBalance::timings() const { return impl_->timings; }
void HarmonicBalance::reset_timings() { impl_->timings = {}; }

}  // namespace jointhb::hb
