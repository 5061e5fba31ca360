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
  MatrixXd phi_g;                        // Gφ, 3P × ns
  std::vector<std::vector<int>> groups;  // points of each group (ascending)
  std::vector<MatrixXd> e_inv;           // E_c⁻¹ per group, 3mg × 3mg (points in group order,
                                         // component-major d·m + c within a point)
  std::vector<MatrixXd> x;               // X_c = B_c E_c⁻¹
  Eigen::PartialPivLU<MatrixXd> schur;
  int singular = 0;

  // out += sign Φ_pᵀ w: (ns·m) from a point's 3m vector, out[j·m + c] += Σ_d Gφ(3p + d, j) w[d·m + c].
  void add_modal(int p, const Eigen::Ref<const VectorXd>& w, double sign, Eigen::Ref<VectorXd> out) const {
    for (int j = 0; j < ns; ++j)
      for (int d = 0; d < 3; ++d) {
        const double g = sign * phi_g(3 * p + d, j);
        if (g != 0.0) out.segment(static_cast<Index>(j) * m, m) += g * w.segment(static_cast<Index>(d) * m, m);
      }
  }
  // Φ_p η: a point's 3m vector, out[d·m + c] = Σ_j Gφ(3p + d, j) η[j·m + c].
  void point_modal(int p, const VectorXd& eta, Eigen::Ref<VectorXd> out) const {
    out.setZero();
    for (int d = 0; d < 3; ++d)
      for (int j = 0; j < ns; ++j)
        out.segment(static_cast<Index>(d) * m, m) += phi_g(3 * p + d, j) * eta.segment(static_cast<Index>(j) * m, m);
  }
};

namespace {

// Groups of up to `size` points that the residual flexibility couples most strongly: from each
// point not yet taken (in order), the untaken points q with the largest normalised coupling
// ‖R0_pq‖_F / √(‖R0_pp‖_F ‖R0_qq‖_F) join it. Geometry-free: near points couple most (R0 is an
// elastic flexibility), so a group is a neighbourhood. Deterministic.
std::vector<std::vector<int>> coupling_groups(const MatrixXd& R0, int P, int size) {
  std::vector<std::vector<int>> groups;
  if (size <= 1) {
    for (int p = 0; p < P; ++p) groups.push_back({p});
    return groups;
  }
  VectorXd self(P);
  for (int p = 0; p < P; ++p) self[p] = std::max(R0.block(3 * p, 3 * p, 3, 3).norm(), 1e-300);
  std::vector<char> taken(static_cast<std::size_t>(P), 0);
  std::vector<std::pair<double, int>> candidates;
  for (int p = 0; p < P; ++p) {
    if (taken[static_cast<std::size_t>(p)]) continue;
    taken[static_cast<std::size_t>(p)] = 1;
    std::vector<int> group{p};
    candidates.clear();
    for (int q = 0; q < P; ++q)
      if (!taken[static_cast<std::size_t>(q)])
        candidates.emplace_back(-R0.block(3 * p, 3 * q, 3, 3).norm() / std::sqrt(self[p] * self[q]), q);
    const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(size - 1), candidates.size());
    std::partial_sort(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(k), candidates.end());
    for (std::size_t i = 0; i < k; ++i) {
      group.push_back(candidates[i].second);
      taken[static_cast<std::size_t>(candidates[i].second)] = 1;
    }
    std::sort(group.begin(), group.end());
    groups.push_back(std::move(group));
  }
  return groups;
}

// The 3m × 3m map of R between points p and q on the gap rows (component-major), eq. (T-23)
// per harmonic: R0 − s R1 on the mean, [rr ri; −ri rr] on (a_k, b_k).
void residual_block(const InterfaceModel& model, const FourierBasis& basis,
                    const std::vector<detail::ResidualCoefficients>& rcs, int p, int q,
                    Eigen::Ref<MatrixXd> out) {
  const int m = basis.size();
  const Eigen::Matrix3d r0 = model.residual_flexibility.block(3 * p, 3 * q, 3, 3);
  const Eigen::Matrix3d r1 = model.residual_inertia.block(3 * p, 3 * q, 3, 3);
  out.setZero();
  const Eigen::Matrix3d mean = r0 - model.residual_shift * r1;
  for (int d1 = 0; d1 < 3; ++d1)
    for (int d2 = 0; d2 < 3; ++d2) out(d1 * m, d2 * m) = mean(d1, d2);
  std::size_t hk = 0;
  for (int k : basis.orders()) {
    const detail::ResidualCoefficients& rc = rcs[hk++];
    const Eigen::Matrix3d rr = rc.c0.real() * r0 + rc.c1.real() * r1;
    const Eigen::Matrix3d ri = rc.c0.imag() * r0 + rc.c1.imag() * r1;
    const int ia = basis.cosine_index(k), ib = ia + 1;
    for (int d1 = 0; d1 < 3; ++d1)
      for (int d2 = 0; d2 < 3; ++d2) {
        out(d1 * m + ia, d2 * m + ia) = rr(d1, d2);
        out(d1 * m + ia, d2 * m + ib) = ri(d1, d2);
        out(d1 * m + ib, d2 * m + ia) = -ri(d1, d2);
        out(d1 * m + ib, d2 * m + ib) = rr(d1, d2);
      }
  }
}

}  // namespace

InterfaceLocalPreconditioner::~InterfaceLocalPreconditioner() = default;
int InterfaceLocalPreconditioner::singular_points() const { return impl_->singular; }
int InterfaceLocalPreconditioner::groups() const { return static_cast<int>(impl_->groups.size()); }

InterfaceLocalPreconditioner::InterfaceLocalPreconditioner(const InterfaceBalance& balance,
                                                           const InterfaceBalanceEvaluation& at,
                                                           double omega, double xi, int group_size)
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
  if (group_size < 1) throw std::invalid_argument(fmt::format("InterfaceLocalPreconditioner: group_size must be ≥ 1, got {}", group_size));
  std::vector<detail::ResidualCoefficients> rcs;
  for (int k : basis.orders()) rcs.push_back(detail::residual_coefficients(model, k, omega, xi));
  h.groups = coupling_groups(model.residual_flexibility, P, group_size);
  const int G = static_cast<int>(h.groups.size());
  h.e_inv.resize(static_cast<std::size_t>(G));
  h.x.resize(static_cast<std::size_t>(G));
  std::vector<int> singular(static_cast<std::size_t>(G), 0);
  const Index len = 3 * static_cast<Index>(m);

#pragma omp parallel for schedule(dynamic, 4)
  for (int c = 0; c < G; ++c) {
    const std::vector<int>& g = h.groups[static_cast<std::size_t>(c)];
    const Index n = static_cast<Index>(g.size()) * len;
    // E_c = I + R_cc B_c, B_c = blockdiag(B_p), R_cc the group's block of R (T-23 per harmonic).
    MatrixXd e = MatrixXd::Identity(n, n);
    MatrixXd bc = MatrixXd::Zero(n, n);
    MatrixXd rpq(len, len);
    for (std::size_t a = 0; a < g.size(); ++a) {
      const MatrixXd& B = at.point_blocks[static_cast<std::size_t>(g[a])];
      bc.block(static_cast<Index>(a) * len, static_cast<Index>(a) * len, len, len) = B;
      for (std::size_t b = 0; b < g.size(); ++b) {
        residual_block(model, basis, rcs, g[a], g[b], rpq);
        e.block(static_cast<Index>(a) * len, static_cast<Index>(b) * len, len, len).noalias() +=
            rpq * at.point_blocks[static_cast<std::size_t>(g[b])];
      }
    }
    const Eigen::PartialPivLU<MatrixXd> lu(e);
    if (!(lu.rcond() > kSingularRcond) || !e.allFinite()) {
      singular[static_cast<std::size_t>(c)] = static_cast<int>(g.size());
      h.e_inv[static_cast<std::size_t>(c)] = MatrixXd::Identity(n, n);
      h.x[static_cast<std::size_t>(c)] = bc;
      continue;
    }
    h.e_inv[static_cast<std::size_t>(c)] = lu.inverse();
    h.x[static_cast<std::size_t>(c)] = bc * h.e_inv[static_cast<std::size_t>(c)];
  }
  for (int v : singular) h.singular += v;

  // S = D + Σ_c Φ_cᵀ X_c Φ_c (ns·m square, index j·m + c), summed by chunks in a fixed order.
  const Index n = static_cast<Index>(ns) * m;
  const int chunks = (G + kChunk - 1) / kChunk;
  std::vector<MatrixXd> partial(static_cast<std::size_t>(chunks));
#pragma omp parallel for schedule(dynamic, 1)
  for (int ch = 0; ch < chunks; ++ch) {
    MatrixXd& sum = partial[static_cast<std::size_t>(ch)];
    sum.setZero(n, n);
    Eigen::Matrix3d xc;
    for (int c = ch * kChunk; c < std::min(G, (ch + 1) * kChunk); ++c) {
      const std::vector<int>& g = h.groups[static_cast<std::size_t>(c)];
      const MatrixXd& X = h.x[static_cast<std::size_t>(c)];
      for (std::size_t a = 0; a < g.size(); ++a)
        for (std::size_t b = 0; b < g.size(); ++b) {
          const Eigen::Matrix<double, 3, Eigen::Dynamic> ga = h.phi_g.middleRows(3 * g[a], 3);  // 3 × ns
          const Eigen::Matrix<double, 3, Eigen::Dynamic> gb = h.phi_g.middleRows(3 * g[b], 3);
          const Index ra = static_cast<Index>(a) * len, cb = static_cast<Index>(b) * len;
          for (int c1 = 0; c1 < m; ++c1)
            for (int c2 = 0; c2 < m; ++c2) {
              for (int d1 = 0; d1 < 3; ++d1)
                for (int d2 = 0; d2 < 3; ++d2) xc(d1, d2) = X(ra + d1 * m + c1, cb + d2 * m + c2);
              if (xc.isZero(0.0)) continue;
              const MatrixXd t = ga.transpose() * xc * gb;  // ns × ns
              for (int j1 = 0; j1 < ns; ++j1)
                for (int j2 = 0; j2 < ns; ++j2)
                  sum(static_cast<Index>(j1) * m + c1, static_cast<Index>(j2) * m + c2) += t(j1, j2);
            }
        }
    }
  }
  MatrixXd S = MatrixXd::Zero(n, n);
  for (const MatrixXd& part : partial) S += part;
  // Rigid modes have no static equation: their mean row is ω_ref² η (as in evaluate()).
  for (int j = 0; j < h.rigid; ++j) S.row(static_cast<Index>(j) * m).setZero();
  // D_j on η_j's coefficients (unscaled rows, as in evaluate()).
  const VectorXd cj = model.rayleigh_mass + model.rayleigh_stiffness * model.omega2.array();
  for (int j = 0; j < ns; ++j) {
    const Index r = static_cast<Index>(j) * m;
    const double w2 = model.omega2[j], cjx = cj[j] - xi;
    S(r, r) += j < h.rigid ? h.omega_ref2 : w2;
    for (int k : basis.orders()) {
      const int ia = basis.cosine_index(k), ib = ia + 1;
      const double kw = k * omega;
      S(r + ia, r + ia) += w2 - kw * kw;
      S(r + ia, r + ib) += kw * cjx;
      S(r + ib, r + ib) += w2 - kw * kw;
      S(r + ib, r + ia) += -kw * cjx;
    }
  }
  h.schur.compute(S);
}

VectorXd InterfaceLocalPreconditioner::solve(const VectorXd& v) const {
  const Impl& h = *impl_;
  const int m = h.m, ns = h.ns;
  const Index g0 = static_cast<Index>(ns) * m, len = 3 * static_cast<Index>(m);
  // Unscaled right-hand side: the rows of evaluate() are divided by ω_ref² (modal) and g_ref (gaps).
  VectorXd r_eta = h.omega_ref2 * v.head(g0);
  VectorXd contribution = VectorXd::Zero(g0);
  std::vector<VectorXd> t(h.groups.size());
  for (std::size_t c = 0; c < h.groups.size(); ++c) {
    const std::vector<int>& g = h.groups[c];
    VectorXd rg(static_cast<Index>(g.size()) * len);
    for (std::size_t a = 0; a < g.size(); ++a)
      rg.segment(static_cast<Index>(a) * len, len) = h.g_ref * v.segment(g0 + g[a] * len, len);
    t[c] = h.e_inv[c] * rg;
    const VectorXd xr = h.x[c] * rg;
    for (std::size_t a = 0; a < g.size(); ++a) h.add_modal(g[a], xr.segment(static_cast<Index>(a) * len, len), -1.0, contribution);
  }
  for (int j = 0; j < h.rigid; ++j) contribution[static_cast<Index>(j) * m] = 0.0;
  const VectorXd eta = h.schur.solve(r_eta + contribution);
  VectorXd out(v.size());
  out.head(g0) = eta;
  for (std::size_t c = 0; c < h.groups.size(); ++c) {
    const std::vector<int>& g = h.groups[c];
    VectorXd phi_eta(static_cast<Index>(g.size()) * len);
    for (std::size_t a = 0; a < g.size(); ++a) h.point_modal(g[a], eta, phi_eta.segment(static_cast<Index>(a) * len, len));
    const VectorXd z = t[c] + h.e_inv[c] * phi_eta;
    for (std::size_t a = 0; a < g.size(); ++a) out.segment(g0 + g[a] * len, len) = z.segment(static_cast<Index>(a) * len, len);
  }
  return out;
}

}  // namespace jointhb::hb
