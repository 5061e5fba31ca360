// Hill's method for the stability of harmonic-balance solutions (hb/hill_stability.hpp).
#include "jointhb/hb/hill_stability.hpp"

#include "../support/lapack_eig.hpp"
#include "hill_companion.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>

namespace jointhb::hb {
namespace {

using cd = std::complex<double>;

// kron(A, I_m) in the DOF-major layout: entry (i·m + j, k·m + j) = A_ik.
Eigen::MatrixXd kron_identity(const Eigen::MatrixXd& a, int m) {
  const Eigen::Index n = a.rows();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n * m, n * m);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index k = 0; k < n; ++k) {
      if (a(i, k) == 0.0) continue;
      for (int j = 0; j < m; ++j) out(i * m + j, k * m + j) = a(i, k);
    }
  }
  return out;
}

// The companion matrix of Δ(λ) = J + λΔ₁ + λ²Δ₂ (eq. T-36), with Δ₂⁻¹ = M⁻¹ ⊗ I:
//   [ 0                 I                           ]
//   [ −(M⁻¹ ⊗ I) J     −(M⁻¹C ⊗ I) − 2 (I ⊗ D_Ω)   ].
Eigen::MatrixXd companion_matrix(const DiscreteSystem& system, const FourierBasis& basis,
                                 const Eigen::MatrixXd& jacobian, double omega) {
  const int n = system.dofs();
  const int m = basis.size();
  const Eigen::Index size = static_cast<Eigen::Index>(n) * m;
  const Eigen::MatrixXd mass = Eigen::MatrixXd(system.mass);
  const Eigen::MatrixXd mass_inverse = mass.llt().solve(Eigen::MatrixXd::Identity(n, n));
  Eigen::MatrixXd damping = Eigen::MatrixXd::Zero(n, n);
  if (system.damping.rows() == n) damping = Eigen::MatrixXd(system.damping);

  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * size, 2 * size);
  a.topRightCorner(size, size).setIdentity();
  a.bottomLeftCorner(size, size).noalias() = -kron_identity(mass_inverse, m) * jacobian;
  Eigen::MatrixXd first = -kron_identity(mass_inverse * damping, m);
  const Eigen::MatrixXd d = detail::time_derivative(basis, omega);
  for (int i = 0; i < n; ++i) first.block(static_cast<Eigen::Index>(i) * m, static_cast<Eigen::Index>(i) * m, m, m) -= 2.0 * d;
  a.bottomRightCorner(size, size) = first;
  return a;
}

// k̄ of eq. T-37: the weighted mean harmonic index of P (the first N entries of an eigenvector) in
// the complex basis e^{ikΩt}, c_{±k} = (a_k ∓ i b_k) / 2.
double harmonic_centre(const FourierBasis& basis, int dofs, const Eigen::VectorXcd& v) {
  const int m = basis.size();
  const cd i(0.0, 1.0);
  double weighted = 0.0;
  double total = 0.0;
  for (int dof = 0; dof < dofs; ++dof) {
    const Eigen::Index o = static_cast<Eigen::Index>(dof) * m;
    if (basis.has_mean()) total += std::norm(v[o]);
    for (int h : basis.orders()) {
      const int a = basis.cosine_index(h);
      const double plus = std::norm(0.5 * (v[o + a] - i * v[o + a + 1]));
      const double minus = std::norm(0.5 * (v[o + a] + i * v[o + a + 1]));
      weighted += h * (plus - minus);
      total += plus + minus;
    }
  }
  return total > 0.0 ? weighted / total : 0.0;
}

// The multiplier outside the unit circle closest to it, or 0 when there is none. (The tolerance
// that counted the unstable multipliers is not stored: any |ρ| > 1 qualifies, the caller already
// knows the counts differ.)
cd crossing_multiplier(const FloquetResult& r) {
  cd best = 0.0;
  for (const cd& rho : r.multipliers) {
    const double a = std::abs(rho);
    if (a > 1.0 && (best == 0.0 || a < std::abs(best))) best = rho;
  }
  return best;
}

}  // namespace

std::string HillOptions::validate() const {
  if (!(unstable_tolerance > 0.0 && unstable_tolerance <= 1e-2)) {
    return fmt::format("unstable_tolerance: must be in (0, 1e-2], got {}", unstable_tolerance);
  }
  return {};
}

std::string to_string(Bifurcation b) {
  switch (b) {
    case Bifurcation::none: return "none";
    case Bifurcation::fold: return "fold";
    case Bifurcation::branch_point: return "branch_point";
    case Bifurcation::period_doubling: return "period_doubling";
    case Bifurcation::neimark_sacker: return "neimark_sacker";
    case Bifurcation::reversal: return "reversal";
  }
  return "none";
}

FloquetResult hill_floquet(const DiscreteSystem& system, const FourierBasis& basis,
                           const Eigen::MatrixXd& jacobian, double omega,
                           const HillOptions& options) {
  if (auto msg = options.validate(); !msg.empty()) throw std::invalid_argument(msg);
  const int n = system.dofs();
  const Eigen::Index size = static_cast<Eigen::Index>(n) * basis.size();
  if (jacobian.rows() != size || jacobian.cols() != size) {
    throw std::invalid_argument(fmt::format("hill_floquet: the Jacobian is {} × {}, expected {} × {}",
                                            jacobian.rows(), jacobian.cols(), size, size));
  }
  if (basis.odd_only()) {
    throw std::invalid_argument("hill_floquet: the basis must hold every harmonic 0..H");
  }
  FloquetResult out;
  if (!jacobian.allFinite() || !(omega > 0.0) || !std::isfinite(omega)) {
    out.message = "the Jacobian or Ω is not finite";
    return out;
  }
  return detail::floquet_from_companion(companion_matrix(system, basis, jacobian, omega), basis, n,
                                        omega, options);
}

namespace detail {

Eigen::MatrixXd time_derivative(const FourierBasis& basis, double omega) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(basis.size(), basis.size());
  for (int h : basis.orders()) {
    const int a = basis.cosine_index(h);
    d(a, a + 1) = h * omega;
    d(a + 1, a) = -h * omega;
  }
  return d;
}

FloquetResult floquet_from_companion(const Eigen::MatrixXd& companion, const FourierBasis& basis,
                                     int n, double omega, const HillOptions& options) {
  FloquetResult out;
  if (!companion.allFinite() || !(omega > 0.0) || !std::isfinite(omega)) {
    out.message = "the companion matrix or Ω is not finite";
    return out;
  }
  const Eigen::Index size = static_cast<Eigen::Index>(n) * basis.size();
  const support::EigenDecomposition eig = support::eigen_decomposition(companion);
  if (!eig.ok) {
    out.message = "the eigensolver (LAPACK dgeev) did not converge";
    return out;
  }

  // Keep the 2n most centred eigenvalues (eq. T-37); ties by |Im λ|.
  const Eigen::Index all = eig.values.size();
  std::vector<double> centre(static_cast<std::size_t>(all));
  for (Eigen::Index j = 0; j < all; ++j)
    centre[static_cast<std::size_t>(j)] =
        std::abs(harmonic_centre(basis, n, eig.vectors.col(j).head(size)));
  std::vector<Eigen::Index> order(static_cast<std::size_t>(all));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
    const double ca = centre[static_cast<std::size_t>(a)], cb = centre[static_cast<std::size_t>(b)];
    if (ca != cb) return ca < cb;
    return std::abs(eig.values[a].imag()) < std::abs(eig.values[b].imag());
  });
  const Eigen::Index kept = std::min<Eigen::Index>(2 * n, all);
  out.kept_centre = centre[static_cast<std::size_t>(order[static_cast<std::size_t>(kept - 1)])];
  out.rejected_centre =
      kept < all ? centre[static_cast<std::size_t>(order[static_cast<std::size_t>(kept)])] : 0.0;

  // ρ = e^{λT} (eq. T-38), sorted by |ρ| descending.
  const double period = 2.0 * std::numbers::pi / omega;
  std::vector<std::pair<cd, cd>> pairs;
  for (Eigen::Index j = 0; j < kept; ++j) {
    const cd lambda = eig.values[order[static_cast<std::size_t>(j)]];
    // Re λT beyond ~700 overflows e^{λT}: cap the modulus (such a point is violently unstable).
    const double log_modulus = std::min(lambda.real() * period, 690.0);
    pairs.emplace_back(lambda, std::polar(std::exp(log_modulus), lambda.imag() * period));
  }
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const auto& a, const auto& b) { return std::abs(a.second) > std::abs(b.second); });
  out.exponents.resize(kept);
  out.multipliers.resize(kept);
  for (Eigen::Index j = 0; j < kept; ++j) {
    out.exponents[j] = pairs[static_cast<std::size_t>(j)].first;
    out.multipliers[j] = pairs[static_cast<std::size_t>(j)].second;
    const double a = std::abs(out.multipliers[j]);
    out.max_multiplier = std::max(out.max_multiplier, a);
    if (a > 1.0 + options.unstable_tolerance) ++out.unstable;
  }
  out.ok = true;
  return out;
}

}  // namespace detail

Bifurcation classify_bifurcation(const FloquetResult& before, const FloquetResult& after,
                                 bool turned) {
  if (turned) {
    // A fold changes the count of unstable multipliers by one (ρ passes +1); a turn without that
    // is the continuation reversing along the branch.
    return before.ok && after.ok && before.unstable == after.unstable ? Bifurcation::reversal
                                                                       : Bifurcation::fold;
  }
  if (!before.ok || !after.ok || before.unstable == after.unstable) return Bifurcation::none;
  const FloquetResult& less_stable = after.unstable > before.unstable ? after : before;
  const cd rho = crossing_multiplier(less_stable);
  if (rho == 0.0) return Bifurcation::none;
  if (std::abs(rho.imag()) <= 1e-6 * std::abs(rho)) {
    return rho.real() > 0.0 ? Bifurcation::branch_point : Bifurcation::period_doubling;
  }
  return Bifurcation::neimark_sacker;
}

HillStability::HillStability(const HarmonicBalance& balance, HillOptions options)
    : balance_(balance), options_(options) {
  if (auto msg = options_.validate(); !msg.empty()) throw std::invalid_argument(msg);
  if (balance_.basis().odd_only()) {
    HarmonicBalanceOptions o = balance_.options();
    o.selection = HarmonicSelection::all;
    full_ = std::make_unique<HarmonicBalance>(balance_.system(), Excitation{}, o);
  }
}

HillStability::~HillStability() = default;
HillStability::HillStability(HillStability&&) noexcept = default;

FloquetResult HillStability::evaluate(const Eigen::VectorXd& coefficients, double omega) const {
  const HarmonicBalance& b = full_ ? *full_ : balance_;
  const Eigen::VectorXd x =
      full_ ? transfer_coefficients(balance_.basis(), b.basis(), coefficients, b.system().dofs())
            : coefficients;
  HarmonicBalanceEvaluation ev;
  b.evaluate(x, omega, true, ev);
  if (!ev.ok) {
    FloquetResult r;
    r.message = "the Jacobian could not be evaluated: " + ev.message;
    return r;
  }
  return hill_floquet(b.system(), b.basis(), ev.d_coefficients, omega, options_);
}

}  // namespace jointhb::hb
