// AFT of one 3D contact point and of a whole interface (contact_point_aft.hpp; docs/theory.md §10).
#include "jointhb/hb/contact_point_aft.hpp"

#include <fmt/format.h>

#include <Eigen/SVD>

#include <cmath>
#include <exception>
#include <stdexcept>
#include <utility>

#include "jointhb/contact/periodic_state.hpp"

namespace jointhb::hb {
namespace {

using contact::ContactPoint;
using contact::Vec2;
using contact::Vec3;

// g(t_i) = g_ref + δg(t_i), i = 0..N-1.
std::vector<Vec3> absolute_path(const ContactPointReference& ref, const Eigen::MatrixXd& dg) {
  std::vector<Vec3> path(static_cast<std::size_t>(dg.rows()));
  for (Eigen::Index i = 0; i < dg.rows(); ++i) {
    path[static_cast<std::size_t>(i)] = ref.gap + dg.row(i).transpose();
  }
  return path;
}

// Normal part, shared by every branch: Δt_N,i = −p_N(g_N,i) − t_ref,N (eq. 6) and its
// Jacobian block A diag(λ p_N,i) E (the normal law has no memory).
Eigen::MatrixXd normal_block(const FourierBasis& basis, const Eigen::VectorXd& normal_stiffness) {
  return basis.to_frequency(normal_stiffness.asDiagonal() * basis.synthesis_matrix());
}

// Per-sample normal and tangential state along the path (no tangential law evaluated yet).
struct PathStates {
  std::vector<contact::TangentialState> states;
  Eigen::VectorXd normal_stiffness;  // λ p_N,i
  int open = 0;
};

PathStates path_states(const ContactPoint& point, const std::vector<Vec3>& path) {
  PathStates s;
  const auto n = static_cast<Eigen::Index>(path.size());
  s.states.reserve(path.size());
  s.normal_stiffness.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    s.states.push_back(point.tangential_state(path[static_cast<std::size_t>(i)].z()));
    s.normal_stiffness[i] = s.states.back().normal_stiffness;
    s.open += s.states.back().open ? 1 : 0;
  }
  return s;
}

// Jenkins with a gap-independent stiffness sticks throughout iff its elastic trial
// t_ref,T + k (g_T,i − g_ref,T) stays within μ p_N,i at every sample; the periodic solve then
// returns exactly that spring (anchor + elastic steps, M = I). Not valid for k = χ λ p_N: the
// elastic steps Σ k_{i+1} Δg_i do not telescope when the pressure moves.
bool sticks_as_spring(const ContactPoint& point, const ContactPointReference& ref,
                      const PathStates& s, const Eigen::MatrixXd& dg) {
  if (!point.law().sticks_below_limit() ||
      point.options().stiffness_model != contact::TangentialStiffnessModel::constant ||
      s.open > 0) {
    return false;
  }
  const double k = point.options().tangential_stiffness;
  const Vec2 t_ref = ref.traction.head<2>();
  for (Eigen::Index i = 0; i < dg.rows(); ++i) {
    const Vec2 trial = t_ref + k * dg.row(i).head<2>().transpose();
    if (!(trial.norm() <= s.states[static_cast<std::size_t>(i)].limits.slip_limit)) return false;
  }
  return true;
}

// Tangential Jacobian blocks of a shortcut: k I on (T1,T1) and (T2,T2) (A E = I), zero elsewhere.
Eigen::MatrixXd shortcut_jacobian(const FourierBasis& basis, double tangential_stiffness,
                                  const Eigen::VectorXd& normal_stiffness) {
  const int m = basis.size();
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(3 * m, 3 * m);
  j.block(0, 0, m, m).diagonal().setConstant(tangential_stiffness);
  j.block(m, m, m, m).diagonal().setConstant(tangential_stiffness);
  j.block(2 * m, 2 * m, m, m) = normal_block(basis, normal_stiffness);
  return j;
}

// The exact shortcuts: fills r and returns true when one applies.
bool try_shortcut(const ContactPoint& point, const ContactPointReference& ref,
                  const FourierBasis& basis, const PathStates& s, const Eigen::MatrixXd& dg,
                  bool jacobian, ContactPointAftResult& r) {
  const Eigen::Index n = dg.rows();
  double k = 0.0;
  if (s.open == n) {  // open throughout: no tangential traction, Δt_T = −t_ref,T
    r.shortcut = ContactPointShortcut::open;
    r.stuck = false;  // as the periodic solve reports open steps
    for (Eigen::Index i = 0; i < n; ++i)
      r.traction_samples.row(i).head<2>() = -ref.traction.head<2>();
  } else if (sticks_as_spring(point, ref, s, dg)) {
    r.shortcut = ContactPointShortcut::stuck;
    k = point.options().tangential_stiffness;
    r.traction_samples.leftCols<2>() = k * dg.leftCols<2>();  // Δt_T = k δg_T
  } else {
    return false;
  }
  if (jacobian) r.jacobian = shortcut_jacobian(basis, k, s.normal_stiffness);
  return true;
}

// The point's state over the period (hb/contact_state.hpp) from |t_T,i| = |t_ref,T + Δt_T,i| and
// the slip limits L_i = μ p_N,i of the samples (0 where open).
void classify_point_state(const ContactPoint& point, const ContactPointReference& ref, const PathStates& s,
                          const ContactStateOptions& options, ContactPointAftResult& r) {
  const auto n = static_cast<std::size_t>(r.traction_samples.rows());
  std::vector<double> magnitude(n), limit(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    magnitude[i] = std::hypot(ref.traction.x() + r.traction_samples(row, 0), ref.traction.y() + r.traction_samples(row, 1));
    limit[i] = s.states[i].open ? 0.0 : s.states[i].limits.slip_limit;
  }
  const LimitMeasures m = limit_measures(magnitude, limit, options.limit_tolerance);
  r.limit_share = m.share;
  r.limit_ratio = m.ratio;
  r.state = classify_contact_state({r.open_fraction, m.share, m.ratio, point.law().sticks_below_limit()}, options);
}

// (I − M)^+ and the projector onto its null space, as in the periodic solve.
std::pair<contact::Mat2, contact::Mat2> periodic_inverse(const contact::Mat2& monodromy) {
  Eigen::JacobiSVD<contact::Mat2> svd(contact::Mat2::Identity() - monodromy,
                                      Eigen::ComputeFullU | Eigen::ComputeFullV);
  contact::Mat2 pinv = contact::Mat2::Zero(), null = contact::Mat2::Zero();
  for (int j = 0; j < 2; ++j) {
    const Vec2 v = svd.matrixV().col(j);
    if (svd.singularValues()(j) > contact::kPeriodicSingular) {
      pinv += v * svd.matrixU().col(j).transpose() / svd.singularValues()(j);
    } else {
      null += v * v.transpose();
    }
  }
  return {pinv, null};
}

// ∂ΔT/∂δG (T-18, T-20). The tangential rows come from the linearised steps of the periodic state
// (theory §5), propagated along the 3m directions "basis function l on component d" at once:
//   δt_{i+1} = A_i δt_i + B_i (δg_T,i+1 − δg_T,i) + (c_i L'_{i+1} + d_i k'_{i+1}) δg_N,i+1,
//   (I − M) δt_0 = r_N,  null directions of I − M: the anchor δt_0 = k_0 δg_T,0 + (g_0 − g_ref)
//   k'_0 δg_N,0,
// with δg_d,i = E(i, l) for direction (d, l). This is contact::periodic_sensitivity specialised
// to that structure (rank-one forcing per step, no 3N × 3m perturbation matrix): ~5× cheaper.
// The normal rows are A diag(λ p_N,i) E in the (N, N) block only. One FFT of 7m columns.
Eigen::MatrixXd periodic_jacobian(const FourierBasis& basis,
                                  const contact::PeriodicContactResult& state) {
  const Eigen::MatrixXd et = basis.synthesis_matrix().transpose();  // m × N: column i = E(i, :)
  const Eigen::Index m = et.rows();
  const Eigen::Index n = et.cols();
  const Eigen::Index q = 3 * m;  // directions: (d, l) → d·m + l
  const contact::PeriodicStateResult& ts = state.tangential;
  // history.col(i) holds δt_i for the q directions, stored 2 × q column-major (δt of direction j
  // at rows 2j, 2j + 1): first the zero-start response, then plus Π_i δt_0.
  Eigen::MatrixXd history(2 * q, n);
  std::vector<contact::Mat2> propagator(static_cast<std::size_t>(n));
  using Rows2 = Eigen::Matrix<double, 2, Eigen::Dynamic>;
  Rows2 r = Rows2::Zero(2, q);
  contact::Mat2 pi = contact::Mat2::Identity();
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const Eigen::Index next = (i + 1) % n;
    history.col(i) = r.reshaped();
    propagator[k] = pi;
    const contact::Mat2& a = ts.d_traction[k];
    const Vec2 b1 = ts.d_slip[k].col(0), b2 = ts.d_slip[k].col(1);
    const auto kn = static_cast<std::size_t>(next);
    const Vec2 bn = ts.d_limit[k] * state.d_limit[kn] + ts.d_stiffness[k] * state.d_stiffness[kn];
    for (Eigen::Index l = 0; l < m; ++l) {
      const double de = et(l, next) - et(l, i);  // δg_{i+1} − δg_i of basis function l
      r.col(l) = Vec2(a * r.col(l) + b1 * de);
      r.col(m + l) = Vec2(a * r.col(m + l) + b2 * de);
      r.col(2 * m + l) = Vec2(a * r.col(2 * m + l) + bn * et(l, next));
    }
    pi = a * pi;
  }
  const auto [pinv, null] = periodic_inverse(pi);
  Rows2 anchor = Rows2::Zero(2, q);
  anchor.block(0, 0, 1, m) = ts.anchor_stiffness * et.col(0).transpose();
  anchor.block(1, m, 1, m) = ts.anchor_stiffness * et.col(0).transpose();
  anchor.rightCols(m) = ts.anchor_offset * (state.d_stiffness[0] * et.col(0).transpose());
  const Rows2 start = pinv * r + null * anchor;

  // Samples for the analysis: column c·q + j is δt_c(t_i) along direction j (c = T1, T2), then
  // the (N, N) block diag(λ p_N,i) E; one FFT of 7m columns.
  // Column by column: the samples' columns are N doubles apart, a power of two for the usual N,
  // and storing across them in the inner loop thrashed the cache (2× the cost at N = 128).
  Eigen::MatrixXd samples(n, 7 * m);
  for (Eigen::Index j = 0; j < q; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const Vec2 dt =
          history.col(i).segment<2>(2 * j) + propagator[static_cast<std::size_t>(i)] * start.col(j);
      samples(i, j) = dt.x();
      samples(i, q + j) = dt.y();
    }
  }
  samples.rightCols(m) =
      Eigen::Map<const Eigen::VectorXd>(state.normal_stiffness.data(), n).asDiagonal() *
      basis.synthesis_matrix();
  const Eigen::MatrixXd coefficients = basis.to_frequency(samples);  // m × 7m
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(3 * m, 3 * m);
  j.topRows(m) = coefficients.leftCols(q);
  j.middleRows(m, m) = coefficients.middleCols(q, q);
  j.bottomRightCorner(m, m) = coefficients.rightCols(m);
  return j;
}

void check_inputs(const FourierBasis& basis, const Eigen::Ref<const Eigen::MatrixXd>& delta_g,
                  Eigen::Index columns, const ContactPointAftOptions& options, const char* where) {
  if (const std::string msg = options.validate(); !msg.empty()) {
    throw std::invalid_argument(fmt::format("{}: options.{}", where, msg));
  }
  if (basis.odd_only()) {
    throw std::invalid_argument(fmt::format(
        "{}: basis: odd-only bases are not valid for a contact point (the exponential normal law "
        "produces a mean shift and even harmonics); use a full basis",
        where));
  }
  if (delta_g.rows() != basis.size() || delta_g.cols() != columns) {
    throw std::invalid_argument(
        fmt::format("{}: delta_g: expected {} x {} coefficients, got {} x {}", where, basis.size(),
                    columns, delta_g.rows(), delta_g.cols()));
  }
  if (!delta_g.allFinite()) {
    throw std::invalid_argument(fmt::format("{}: delta_g: non-finite coefficient", where));
  }
}

}  // namespace

std::string ContactPointAftOptions::validate() const {
  if (!(periodic_tolerance > 0.0 && periodic_tolerance <= 1e-3)) {
    return fmt::format("periodic_tolerance must lie in (0, 1e-3], got {}", periodic_tolerance);
  }
  if (max_iterations < 1) return fmt::format("max_iterations must be >= 1, got {}", max_iterations);
  if (!(drift_limit >= 0.0) || !std::isfinite(drift_limit))
    return fmt::format("drift_limit must be finite and >= 0, got {}", drift_limit);
  if (!(drift_ratio >= 0.0 && drift_ratio <= 0.1))
    return fmt::format("drift_ratio must be in [0, 0.1], got {}", drift_ratio);
  if (const std::string e = states.validate(); !e.empty()) return "states: " + e;
  return {};
}

std::vector<ContactPointReference> contact_point_references(const Eigen::VectorXd& gap,
                                                            const Eigen::VectorXd& traction) {
  if (gap.size() % 3 != 0 || traction.size() != gap.size()) {
    throw std::invalid_argument(fmt::format(
        "contact_point_references: gap ({}) and traction ({}) must both have 3P entries",
        gap.size(), traction.size()));
  }
  std::vector<ContactPointReference> refs(static_cast<std::size_t>(gap.size() / 3));
  for (std::size_t p = 0; p < refs.size(); ++p) {
    const auto i = static_cast<Eigen::Index>(3 * p);
    refs[p].gap = gap.segment<3>(i);
    refs[p].traction = traction.segment<3>(i);
  }
  return refs;
}

ContactPointAftResult evaluate_contact_point(const contact::ContactPoint& point,
                                             const ContactPointReference& reference,
                                             const FourierBasis& basis,
                                             const Eigen::Ref<const Eigen::MatrixXd>& delta_g,
                                             const ContactPointAftOptions& options) {
  check_inputs(basis, delta_g, 3, options, "evaluate_contact_point");
  if (!reference.gap.allFinite() || !reference.traction.allFinite()) {
    throw std::invalid_argument("evaluate_contact_point: reference: non-finite gap or traction");
  }
  const Eigen::MatrixXd dg = basis.to_time(delta_g);  // δg(t_i), N × 3
  const Eigen::Index n = dg.rows();
  const std::vector<Vec3> path = absolute_path(reference, dg);
  const PathStates s = path_states(point, path);

  ContactPointAftResult r;
  r.open_fraction = static_cast<double>(s.open) / static_cast<double>(n);
  r.traction_samples.resize(n, 3);
  // Δt_N,i = −p_N(g_N,i) − t_ref,N (T-17, normal row), identical on every branch, formed as
  // −[p_N(g_ref + δg_N,i) − p_N(g_ref)] − [t_ref,N + p_N(g_ref)] so that a tiny δg keeps its
  // relative accuracy (the second bracket is zero for a reference taken from the law).
  const contact::NormalLaw& normal = point.options().normal;
  const double reference_mismatch = reference.traction.z() + normal.pressure(reference.gap.z());
  for (Eigen::Index i = 0; i < n; ++i) {
    r.traction_samples(i, 2) = -normal.pressure_change(reference.gap.z(), dg(i, 2)) - reference_mismatch;
  }

  const bool shortcut =
      options.use_shortcuts && try_shortcut(point, reference, basis, s, dg, options.jacobian, r);
  if (!shortcut) {
    contact::PeriodicStateOptions po;
    po.tolerance = options.periodic_tolerance;
    po.max_iterations = options.max_iterations;
    po.reference_traction = reference.traction.head<2>();
    po.reference_slip = reference.gap.head<2>();
    po.keep_step_derivatives = options.jacobian;
    const contact::PeriodicContactResult state = point.periodic(path, po);
    for (Eigen::Index i = 0; i < n; ++i) {
      r.traction_samples.row(i).head<2>() =
          (state.tangential.traction[static_cast<std::size_t>(i)] - reference.traction.head<2>())
              .transpose();
    }
    r.dissipation = state.tangential.dissipation;
    r.stuck = state.tangential.stuck;
    r.iterations = state.tangential.iterations;
    r.converged = state.tangential.termination == Termination::converged;
    r.drift = state.tangential.residual;
    if (!r.converged && (options.drift_limit > 0.0 || options.drift_ratio > 0.0)) {
      const Eigen::MatrixXd t = r.traction_samples.leftCols<2>();
      const double loop = (t.rowwise() - t.colwise().mean()).rowwise().norm().maxCoeff();
      r.drifting = r.drift <= options.drift_limit + options.drift_ratio * loop;
      r.converged = r.drifting;
    }
    if (!r.converged) r.message = state.tangential.message;
    if (options.jacobian) r.jacobian = periodic_jacobian(basis, state);
  }
  r.traction = basis.to_frequency(r.traction_samples);
  classify_point_state(point, reference, s, options.states, r);
  return r;
}

InterfaceAftResult evaluate_interface_aft(std::span<const contact::ContactPoint> points,
                                          std::span<const ContactPointReference> references,
                                          const FourierBasis& basis,
                                          const Eigen::Ref<const Eigen::MatrixXd>& delta_g,
                                          const ContactPointAftOptions& options,
                                          std::span<const double> areas) {
  const auto np = static_cast<Eigen::Index>(references.size());
  const char* where = "evaluate_interface_aft";
  check_inputs(basis, delta_g, 3 * np, options, where);
  if (points.size() != 1 && static_cast<Eigen::Index>(points.size()) != np) {
    throw std::invalid_argument(
        fmt::format("{}: points: expected 1 (shared) or P = {} contact points, got {}", where, np,
                    points.size()));
  }
  if (!areas.empty() && static_cast<Eigen::Index>(areas.size()) != np) {
    throw std::invalid_argument(
        fmt::format("{}: areas: expected 0 or P = {} entries, got {}", where, np, areas.size()));
  }
  for (const double a : areas) {
    if (!(a > 0.0 && std::isfinite(a))) {
      throw std::invalid_argument(
          fmt::format("{}: areas: every area must be > 0 and finite", where));
    }
  }

  InterfaceAftResult r;
  r.points.resize(static_cast<std::size_t>(np));
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(np));
  // Each point is independent and writes only its own slot: the result does not depend on the
  // number of threads or on the schedule. Exceptions must not leave the parallel region.
#pragma omp parallel for schedule(dynamic, 4)
  for (Eigen::Index p = 0; p < np; ++p) {
    const auto k = static_cast<std::size_t>(p);
    try {
      const contact::ContactPoint& point = points.size() == 1 ? points[0] : points[k];
      r.points[k] = evaluate_contact_point(point, references[k], basis,
                                           delta_g.middleCols(3 * p, 3), options);
    } catch (...) {
      errors[k] = std::current_exception();
    }
  }
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }

  // Reductions in point order.
  r.traction.resize(basis.size(), 3 * np);
  for (Eigen::Index p = 0; p < np; ++p) {
    const auto k = static_cast<std::size_t>(p);
    const ContactPointAftResult& q = r.points[k];
    r.traction.middleCols(3 * p, 3) = q.traction;
    r.dissipation += (areas.empty() ? 1.0 : areas[k]) * q.dissipation;
    r.open_points += q.open_fraction == 1.0 ? 1 : 0;
    r.stuck_points += q.stuck ? 1 : 0;
    r.states.add(q.state);
    if (!q.converged && r.converged) {
      r.converged = false;
      r.message = fmt::format("points[{}]: periodic state not converged{}", p,
                              q.message.empty() ? "" : ": " + q.message);
    }
  }
  return r;
}

}  // namespace jointhb::hb
