// EPMC residual (hb/nonlinear_mode.hpp).
#include "jointhb/hb/nonlinear_mode.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace jointhb::hb {
namespace {

constexpr double kLn10 = 2.302585092994045684;

HarmonicBalanceOptions balance_options(const NonlinearModeOptions& o) {
  HarmonicBalanceOptions b;
  b.harmonics = o.harmonics;
  b.time_samples = o.time_samples;
  b.selection = o.selection;
  b.periodic_tolerance = o.periodic_tolerance;
  return b;
}

DiscreteSystem checked(DiscreteSystem s, const NonlinearModeOptions& o) {
  if (auto msg = s.validate(); !msg.empty()) throw std::invalid_argument(msg);
  if (auto msg = o.validate(s.dofs()); !msg.empty()) throw std::invalid_argument(msg);
  if (std::any_of(s.contacts.begin(), s.contacts.end(), [](const ContactElement& c) { return c.has_reference_offset(); })) {
    throw std::invalid_argument(
        "nonlinear modes: contacts must have zero reference force and slip (the amplitude "
        "scaling of the unknowns does not admit a static offset)");
  }
  return s;
}

}  // namespace

std::string NonlinearModeOptions::validate(int dofs) const {
  if (mode < 1 || mode > dofs) {
    return fmt::format("mode: must be in [1, {}], got {}", dofs, mode);
  }
  return balance_options(*this).validate();
}

NonlinearModeResidual::NonlinearModeResidual(DiscreteSystem system, NonlinearModeOptions options)
    : system_(checked(std::move(system), options)),
      options_(options),
      balance_(system_, Excitation{}, balance_options(options)) {
  const LinearModes modes = linear_modes(system_, true);
  const auto j = static_cast<Eigen::Index>(options_.mode - 1);
  phi_ = modes.shapes.col(j);
  omega_ = modes.omega[j];
  if (!(omega_ > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "mode: linear mode {} has zero frequency (a rigid-body mode): no vibration to follow",
        options_.mode));
  }
  // Sign convention: the largest component positive, so that curves of one mode agree.
  Eigen::Index k = 0;
  phi_.cwiseAbs().maxCoeff(&k);
  if (phi_[k] < 0.0) phi_ = -phi_;
  m_phi_ = system_.mass * phi_;
}

Eigen::Index NonlinearModeResidual::unknowns() const { return balance_.unknowns() + 2; }

double NonlinearModeResidual::linear_damping_ratio() const {
  if (system_.damping.nonZeros() == 0) return 0.0;
  return phi_.dot(system_.damping * phi_) / (2.0 * omega_);
}

Eigen::VectorXd NonlinearModeResidual::mode_start(const Eigen::VectorXd& shape, double omega, double xi) const {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(unknowns());
  const int a = balance_.basis().cosine_index(1);
  for (int i = 0; i < system_.dofs(); ++i) y[balance_.index(i, a)] = shape[i];
  y[unknowns() - 2] = omega;
  y[unknowns() - 1] = xi;
  return y;
}

Eigen::VectorXd NonlinearModeResidual::linear_start() const {
  return mode_start(phi_, omega_, 2.0 * linear_damping_ratio() * omega_);
}

std::optional<Eigen::VectorXd> NonlinearModeResidual::slipping_start() const {
  if (std::any_of(system_.contacts.begin(), system_.contacts.end(), [](const ContactElement& c) { return c.normal(); }))
    return std::nullopt;
  const LinearModes modes = linear_modes(system_, false);
  const auto j = static_cast<Eigen::Index>(options_.mode - 1);
  const double omega = modes.omega[j];
  if (!(omega > 1e-8 * omega_)) return std::nullopt;  // a rigid-body mode once the contacts slip
  Eigen::VectorXd shape = modes.shapes.col(j);
  if (shape.dot(m_phi_) < 0.0) shape = -shape;
  return mode_start(shape, omega, system_.damping.nonZeros() == 0 ? 0.0 : shape.dot(system_.damping * shape));
}

std::pair<Eigen::VectorXd, Eigen::VectorXd> NonlinearModeResidual::harmonic(
    const Eigen::VectorXd& x, int order) const {
  const int n = system_.dofs();
  const int m = balance_.basis().size();
  const int c = balance_.basis().cosine_index(order);
  Eigen::VectorXd a(n), b(n);
  for (int i = 0; i < n; ++i) {
    a[i] = x[static_cast<Eigen::Index>(i) * m + c];
    b[i] = x[static_cast<Eigen::Index>(i) * m + c + 1];
  }
  return {a, b};
}

Eigen::VectorXd NonlinearModeResidual::velocity_product(const SparseMatrix& a,
                                                        const Eigen::VectorXd& x) const {
  const FourierBasis& basis = balance_.basis();
  const int n = system_.dofs();
  const int m = basis.size();
  Eigen::VectorXd out = Eigen::VectorXd::Zero(x.size());
  for (int k : basis.orders()) {
    const int c = basis.cosine_index(k);
    const auto [ak, bk] = harmonic(x, k);
    const Eigen::VectorXd abk = a * bk;
    const Eigen::VectorXd aak = a * ak;
    for (int i = 0; i < n; ++i) {
      out[static_cast<Eigen::Index>(i) * m + c] = k * abk[i];
      out[static_cast<Eigen::Index>(i) * m + c + 1] = -k * aak[i];
    }
  }
  return out;
}

void NonlinearModeResidual::evaluate(const Eigen::VectorXd& y, double lambda, bool jacobian,
                                     Evaluation& out) const {
  const Eigen::Index nx = balance_.unknowns();
  if (y.size() != nx + 2) {
    throw std::invalid_argument(
        fmt::format("NonlinearModeResidual::evaluate: {} unknowns, expected {}", y.size(), nx + 2));
  }
  const double q = std::pow(10.0, lambda);
  const Eigen::VectorXd xh = y.head(nx);
  const double omega = y[nx];
  const double xi = y[nx + 1];
  HarmonicBalanceEvaluation hb;
  balance_.evaluate(q * xh, omega, jacobian, hb);
  out.ok = hb.ok;
  out.message = hb.message;
  out.fourier_dissipation = hb.fourier_dissipation;
  out.contacts = hb.contacts;

  // R̂ = R(q X̂)/q − ξ Ω V_M X̂   (V_M: velocity blocks of M)
  const Eigen::VectorXd vm = velocity_product(system_.mass, xh);
  const Eigen::VectorXd r1 = hb.residual / q;
  out.residual.resize(nx + 2);
  out.residual.head(nx) = r1 - xi * omega * vm;

  const FourierBasis& basis = balance_.basis();
  const int n = system_.dofs();
  const int m = basis.size();
  const int c1 = basis.cosine_index(1);
  const auto [a1, b1] = harmonic(xh, 1);
  const Eigen::VectorXd ma1 = system_.mass * a1;
  const Eigen::VectorXd mb1 = system_.mass * b1;
  out.residual[nx] = a1.dot(ma1) + b1.dot(mb1) - 1.0;
  out.residual[nx + 1] = b1.dot(m_phi_);
  if (!out.residual.allFinite() && out.ok) {
    out.ok = false;
    out.message = "non-finite residual";
  }
  if (!jacobian) return;

  out.d_state = Eigen::MatrixXd::Zero(nx + 2, nx + 2);
  auto jx = out.d_state.topLeftCorner(nx, nx);
  jx = hb.d_coefficients;
  // −ξ Ω V_M as a matrix: (i, a_k) ← k M_ij b_k,j ; (i, b_k) ← −k M_ij a_k,j
  const SparseMatrix& mass = system_.mass;
  for (int k : basis.orders()) {
    const int c = basis.cosine_index(k);
    for (int col = 0; col < mass.outerSize(); ++col) {
      for (SparseMatrix::InnerIterator it(mass, col); it; ++it) {
        const Eigen::Index i = it.row() * m;
        const Eigen::Index j = it.col() * m;
        jx(i + c, j + c + 1) -= xi * omega * k * it.value();
        jx(i + c + 1, j + c) += xi * omega * k * it.value();
      }
    }
  }
  out.d_state.col(nx).head(nx) = hb.d_omega / q - xi * vm;
  out.d_state.col(nx + 1).head(nx) = -omega * vm;
  for (int i = 0; i < n; ++i) {
    const Eigen::Index a = static_cast<Eigen::Index>(i) * m + c1;
    out.d_state(nx, a) = 2.0 * ma1[i];
    out.d_state(nx, a + 1) = 2.0 * mb1[i];
    out.d_state(nx + 1, a + 1) = m_phi_[i];
  }
  out.d_parameter = Eigen::VectorXd::Zero(nx + 2);
  out.d_parameter.head(nx) = (hb.d_coefficients * xh - r1) * kLn10;
}

NonlinearModeState NonlinearModeResidual::state(const Eigen::VectorXd& y, double lambda,
                                                const Evaluation* at_point) const {
  const Eigen::Index nx = balance_.unknowns();
  const double q = std::pow(10.0, lambda);
  NonlinearModeState s;
  s.amplitude = q;
  s.omega = y[nx];
  s.damping_ratio = y[nx + 1] / (2.0 * s.omega);
  Evaluation here;
  if (at_point == nullptr) {
    evaluate(y, lambda, false, here);
    at_point = &here;
  }
  s.dissipation = at_point->fourier_dissipation;
  for (const auto& c : at_point->contacts) s.states.add(c.state);
  const int slipping = s.states.slipping();
  s.slipping_points = slipping;
  s.slip_fraction = at_point->contacts.empty() ? 0.0
                                               : static_cast<double>(slipping) /
                                                     static_cast<double>(at_point->contacts.size());
  // Works over one period: ∮ ẋᵀ A ẋ dt = π Ω Σ_k k² (a_kᵀ A a_k + b_kᵀ A b_k), summed on the
  // normalised shape X̂ (x = q X̂) and scaled by q² afterwards.
  const Eigen::VectorXd x_hat = y.head(nx);
  double em = 0.0, ec = 0.0;
  for (int k : balance_.basis().orders()) {
    const auto [ak, bk] = harmonic(x_hat, k);
    em += k * k * (ak.dot(system_.mass * ak) + bk.dot(system_.mass * bk));
    if (system_.damping.nonZeros()) {
      ec += k * k * (ak.dot(system_.damping * ak) + bk.dot(system_.damping * bk));
    }
  }
  s.injected_energy = y[nx + 1] * std::numbers::pi * s.omega * em * q * q;
  s.viscous_dissipation = std::numbers::pi * s.omega * ec * q * q;
  // ζ_E = (W_D + W_visc) / (4π E), E = ½ Ω² q², with W_visc/q² from X̂ and W_D divided by q twice,
  // so that no q² under- or overflows where the ratio itself is representable (at q = 1e-300
  // ζ_E is the viscous share, its limit, not 0/0).
  s.damping_ratio_energy = ((s.dissipation / q) / q + std::numbers::pi * s.omega * ec) /
                           (2.0 * std::numbers::pi * s.omega * s.omega);
  return s;
}

}  // namespace jointhb::hb
