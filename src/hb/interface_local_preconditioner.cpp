// Point-local preconditioner of the interface harmonic balance (interface_local_preconditioner.hpp;
// docs/theory.md §11, eq. T-34).
#include "jointhb/hb/interface_local_preconditioner.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>

#include "jointhb/hb/interface_balance.hpp"
#include "residual_coefficients.hpp"

namespace jointhb::hb {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// Points per chunk of the Schur-complement sum: chunks are summed in a fixed order, so the result
// does not depend on how many threads computed them.
constexpr int kChunk = 32;
// E_p with a reciprocal condition estimate below this is left out of the preconditioner.
constexpr double kSingularRcond = 1e-13;

}  // namespace

struct InterfaceLocalPreconditioner::Impl {
  int m = 0, ns = 0, P = 0, rigid = 0;
  double omega_ref2 = 1.0, g_ref = 1.0;
  MatrixXd phi_g;                 // Gφ, 3P × ns
  std::vector<MatrixXd> e_inv;    // E_p⁻¹, 3m × 3m (component-major d·m + c)
  std::vector<MatrixXd> x;        // X_p = B_p E_p⁻¹
  Eigen::PartialPivLU<MatrixXd> schur;
  int singular = 0;

  // Φ_pᵀ w: (ns·m) from a point's 3m vector, out[j·m + c] = Σ_d Gφ(3p + d, j) w[d·m + c].
  void add_modal(int p, const VectorXd& w, double sign, Eigen::Ref<VectorXd> out) const {
    for (int j = 0; j < ns; ++j)
      for (int d = 0; d < 3; ++d) {
        const double g = sign * phi_g(3 * p + d, j);
        if (g != 0.0) out.segment(static_cast<Index>(j) * m, m) += g * w.segment(static_cast<Index>(d) * m, m);
      }
  }
  // Φ_p η: a point's 3m vector, out[d·m + c] = Σ_j Gφ(3p + d, j) η[j·m + c].
  VectorXd point_modal(int p, const VectorXd& eta) const {
    VectorXd out = VectorXd::Zero(3 * m);
    for (int d = 0; d < 3; ++d)
      for (int j = 0; j < ns; ++j)
        out.segment(static_cast<Index>(d) * m, m) += phi_g(3 * p + d, j) * eta.segment(static_cast<Index>(j) * m, m);
    return out;
  }
};

InterfaceLocalPreconditioner::~InterfaceLocalPreconditioner() = default;
int InterfaceLocalPreconditioner::singular_points() const { return impl_->singular; }

InterfaceLocalPreconditioner::InterfaceLocalPreconditioner(const InterfaceBalance& balance,
                                                           const InterfaceBalanceEvaluation& at,
                                                           double omega, double xi)
    : impl_(std::make_unique<Impl>()) {
  Impl& h = *impl_;
  const InterfaceModel& model = balance.model();
  const FourierBasis& basis = balance.basis();
  h.m = basis.size();
  h.ns = balance.modes();
  h.P = balance.points();
  h.rigid = model.rigid_modes;
  h.omega_ref2 = balance.reference_omega() * balance.reference_omega();
  h.g_ref = balance.reference_gap();
  h.phi_g = model.gap_shapes;
  const int m = h.m, ns = h.ns, P = h.P;
  if (at.point_blocks.size() != static_cast<std::size_t>(P))
    throw std::invalid_argument(fmt::format(
        "InterfaceLocalPreconditioner: {} point blocks, expected {} (an evaluation with the Jacobian)",
        at.point_blocks.size(), P));
  // The residual-mode coefficients (T-23) of every harmonic: R_k = Re/Im(c0) R0 + Re/Im(c1) R1.
  std::vector<detail::ResidualCoefficients> rcs;
  for (int k : basis.orders()) rcs.push_back(detail::residual_coefficients(model, k, omega, xi));
  const MatrixXd& R0 = model.residual_flexibility;
  const MatrixXd& R1 = model.residual_inertia;
  const double s = model.residual_shift;
  h.e_inv.resize(static_cast<std::size_t>(P));
  h.x.resize(static_cast<std::size_t>(P));
  std::vector<char> singular(static_cast<std::size_t>(P), 0);

#pragma omp parallel for schedule(dynamic, 8)
  for (int p = 0; p < P; ++p) {
    // R_pp as the 3m × 3m map of the gap rows (component-major), eq. (T-23) per harmonic.
    const Eigen::Matrix3d r0 = R0.block(3 * p, 3 * p, 3, 3), r1 = R1.block(3 * p, 3 * p, 3, 3);
    MatrixXd rp = MatrixXd::Zero(3 * m, 3 * m);
    const Eigen::Matrix3d mean = r0 - s * r1;
    for (int d1 = 0; d1 < 3; ++d1)
      for (int d2 = 0; d2 < 3; ++d2) rp(d1 * m, d2 * m) = mean(d1, d2);
    std::size_t hk = 0;
    for (int k : basis.orders()) {
      const detail::ResidualCoefficients& rc = rcs[hk++];
      const Eigen::Matrix3d rr = rc.c0.real() * r0 + rc.c1.real() * r1;
      const Eigen::Matrix3d ri = rc.c0.imag() * r0 + rc.c1.imag() * r1;
      const int ia = basis.cosine_index(k), ib = ia + 1;
      for (int d1 = 0; d1 < 3; ++d1)
        for (int d2 = 0; d2 < 3; ++d2) {
          rp(d1 * m + ia, d2 * m + ia) = rr(d1, d2);
          rp(d1 * m + ia, d2 * m + ib) = ri(d1, d2);
          rp(d1 * m + ib, d2 * m + ia) = -ri(d1, d2);
          rp(d1 * m + ib, d2 * m + ib) = rr(d1, d2);
        }
    }
    const MatrixXd& B = at.point_blocks[static_cast<std::size_t>(p)];
    const MatrixXd e = MatrixXd::Identity(3 * m, 3 * m) + rp * B;
    const Eigen::PartialPivLU<MatrixXd> lu(e);
    if (!(lu.rcond() > kSingularRcond) || !e.allFinite()) {
      singular[static_cast<std::size_t>(p)] = 1;
      h.e_inv[static_cast<std::size_t>(p)] = MatrixXd::Identity(3 * m, 3 * m);
      h.x[static_cast<std::size_t>(p)] = B;
      continue;
    }
    h.e_inv[static_cast<std::size_t>(p)] = lu.inverse();
    h.x[static_cast<std::size_t>(p)] = B * h.e_inv[static_cast<std::size_t>(p)];
  }
  h.singular = static_cast<int>(std::count(singular.begin(), singular.end(), 1));

  // S = D + Σ_p Φ_pᵀ X_p Φ_p (ns·m square, index j·m + c), summed by chunks in a fixed order.
  const Index n = static_cast<Index>(ns) * m;
  const int chunks = (P + kChunk - 1) / kChunk;
  std::vector<MatrixXd> partial(static_cast<std::size_t>(chunks));
#pragma omp parallel for schedule(dynamic, 1)
  for (int ch = 0; ch < chunks; ++ch) {
    MatrixXd& sum = partial[static_cast<std::size_t>(ch)];
    sum.setZero(n, n);
    Eigen::Matrix3d xc;
    for (int p = ch * kChunk; p < std::min(P, (ch + 1) * kChunk); ++p) {
      const MatrixXd& X = h.x[static_cast<std::size_t>(p)];
      const Eigen::Matrix<double, 3, Eigen::Dynamic> gp = h.phi_g.middleRows(3 * p, 3);  // 3 × ns
      for (int c1 = 0; c1 < m; ++c1)
        for (int c2 = 0; c2 < m; ++c2) {
          for (int d1 = 0; d1 < 3; ++d1)
            for (int d2 = 0; d2 < 3; ++d2) xc(d1, d2) = X(d1 * m + c1, d2 * m + c2);
          if (xc.isZero(0.0)) continue;
          const MatrixXd t = gp.transpose() * xc * gp;  // ns × ns
          for (int j1 = 0; j1 < ns; ++j1)
            for (int j2 = 0; j2 < ns; ++j2) sum(static_cast<Index>(j1) * m + c1, static_cast<Index>(j2) * m + c2) += t(j1, j2);
        }
    }
  }
  MatrixXd S = MatrixXd::Zero(n, n);
  for (const MatrixXd& part : partial) S += part;
  // Rigid modes have no static equation: their mean row is ω_ref² η (as in evaluate()).
  for (int j = 0; j < h.rigid; ++j) S.row(static_cast<Index>(j) * m).setZero();
  // D_j on η_j's coefficients (unscaled rows, as in evaluate()).
  const VectorXd c = model.rayleigh_mass + model.rayleigh_stiffness * model.omega2.array();
  for (int j = 0; j < ns; ++j) {
    const Index r = static_cast<Index>(j) * m;
    const double w2 = model.omega2[j], cj = c[j] - xi;
    S(r, r) += j < h.rigid ? h.omega_ref2 : w2;
    for (int k : basis.orders()) {
      const int ia = basis.cosine_index(k), ib = ia + 1;
      const double kw = k * omega;
      S(r + ia, r + ia) += w2 - kw * kw;
      S(r + ia, r + ib) += kw * cj;
      S(r + ib, r + ib) += w2 - kw * kw;
      S(r + ib, r + ia) += -kw * cj;
    }
  }
  h.schur.compute(S);
}

VectorXd InterfaceLocalPreconditioner::solve(const VectorXd& v) const {
  const Impl& h = *impl_;
  const int m = h.m, ns = h.ns, P = h.P;
  const Index g0 = static_cast<Index>(ns) * m, len = 3 * static_cast<Index>(m);
  // Unscaled right-hand side: the rows of evaluate() are divided by ω_ref² (modal) and g_ref (gaps).
  VectorXd r_eta = h.omega_ref2 * v.head(g0);
  std::vector<VectorXd> t(static_cast<std::size_t>(P));
  for (int p = 0; p < P; ++p) {
    const VectorXd rg = h.g_ref * v.segment(g0 + p * len, len);
    t[static_cast<std::size_t>(p)] = h.e_inv[static_cast<std::size_t>(p)] * rg;
    VectorXd xr = h.x[static_cast<std::size_t>(p)] * rg;
    if (h.rigid > 0) {
      VectorXd contribution = VectorXd::Zero(g0);
      h.add_modal(p, xr, -1.0, contribution);
      for (int j = 0; j < h.rigid; ++j) contribution[static_cast<Index>(j) * m] = 0.0;
      r_eta += contribution;
    } else {
      h.add_modal(p, xr, -1.0, r_eta);
    }
  }
  const VectorXd eta = h.schur.solve(r_eta);
  VectorXd out(v.size());
  out.head(g0) = eta;
  for (int p = 0; p < P; ++p)
    out.segment(g0 + p * len, len) =
        t[static_cast<std::size_t>(p)] + h.e_inv[static_cast<std::size_t>(p)] * h.point_modal(p, eta);
  return out;
}

}  // namespace jointhb::hb
