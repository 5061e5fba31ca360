#include "jointhb/reduction/modal_interface.hpp"

#include <fmt/format.h>

#include <map>
#include <utility>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "../support/blas_gemm.hpp"
#include "../support/numeric_constants.hpp"
#include "../support/stopwatch.hpp"
#include "jointhb/fe/rigid_body_modes.hpp"
#include "jointhb/fe/sparse_cholesky.hpp"

namespace jointhb::reduction {

namespace {

using SpMat = Eigen::SparseMatrix<double>;
using support::seconds_since;

using support::kTwoPi;

// Columns per block of the residual solves and of Wᵀ M W.
constexpr Eigen::Index kSolveBlock = 512;

// C = alpha op(A) op(B) + beta C through the BLAS (op = transpose when the flag is set).
void gemm(bool transpose_a, bool transpose_b, double alpha, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
          double beta, Eigen::MatrixXd& C) {
  const Eigen::Index m = transpose_a ? A.cols() : A.rows(), k = transpose_a ? A.rows() : A.cols();
  const Eigen::Index kb = transpose_b ? B.cols() : B.rows(), n = transpose_b ? B.rows() : B.cols();
  if (k != kb || C.rows() != m || C.cols() != n) throw std::logic_error("modal interface: gemm sizes do not match");
  if (m == 0 || n == 0) return;
  if (k == 0) {
    C *= beta;
    return;
  }
  const int im = static_cast<int>(m), in = static_cast<int>(n), ik = static_cast<int>(k);
  const int lda = static_cast<int>(std::max<Eigen::Index>(1, A.rows()));
  const int ldb = static_cast<int>(std::max<Eigen::Index>(1, B.rows()));
  const int ldc = static_cast<int>(std::max<Eigen::Index>(1, C.rows()));
  const char ta = transpose_a ? 'T' : 'N', tb = transpose_b ? 'T' : 'N';
  dgemm_(&ta, &tb, &im, &in, &ik, &alpha, A.data(), &lda, B.data(), &ldb, &beta, C.data(), &ldc);
}

// Every interface's gap operator stacked (points in interface order), columns on the free DOFs;
// columns of constrained DOFs drop out (u = 0 there).
SpMat stacked_gap_operator(const preload::PreloadModel& model, const fe::DofMap& dofs) {
  std::vector<Eigen::Triplet<double>> entries;
  int offset = 0;
  for (const preload::ContactInterface& ci : model.interfaces) {
    const SpMat& G = ci.geometry.gap_operator;
    for (int j = 0; j < G.outerSize(); ++j)
      for (SpMat::InnerIterator it(G, j); it; ++it) {
        const int free = dofs.free_of_full[static_cast<std::size_t>(it.col())];
        if (free >= 0) entries.emplace_back(offset + static_cast<int>(it.row()), free, it.value());
      }
    offset += static_cast<int>(G.rows());
  }
  SpMat G(offset, dofs.num_free());
  G.setFromTriplets(entries.begin(), entries.end());
  return G;
}

bool finite(const Eigen::VectorXd& v) { return v.array().isFinite().all(); }

// The distinct rows of G (exact equality of their entries) and, per row, the index of its distinct
// representative. Nodal integration gives every element a point at each of its nodes: the points
// of one node pair have identical rows, so the residual terms need only the distinct ones.
std::pair<SpMat, std::vector<int>> distinct_rows(const SpMat& G) {
  const Eigen::SparseMatrix<double, Eigen::RowMajor> rows = G;
  std::map<std::vector<std::pair<int, double>>, int> seen;
  std::vector<int> representative(static_cast<std::size_t>(rows.rows()));
  std::vector<Eigen::Triplet<double>> entries;
  for (int r = 0; r < rows.outerSize(); ++r) {
    std::vector<std::pair<int, double>> key;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(rows, r); it; ++it)
      if (it.value() != 0.0) key.emplace_back(static_cast<int>(it.col()), it.value());
    const auto [where, inserted] = seen.emplace(std::move(key), static_cast<int>(seen.size()));
    representative[static_cast<std::size_t>(r)] = where->second;
    if (inserted)
      for (const auto& [col, value] : where->first) entries.emplace_back(where->second, col, value);
  }
  SpMat distinct(static_cast<Eigen::Index>(seen.size()), G.cols());
  distinct.setFromTriplets(entries.begin(), entries.end());
  return {distinct, representative};
}

}  // namespace

std::string ModalInterfaceOptions::validate() const {
  if (!(cutoff_hz > 0.0) || !std::isfinite(cutoff_hz))
    return fmt::format("cutoff_hz: must be a finite number > 0, got {}", cutoff_hz);
  if (initial_count < 1) return fmt::format("initial_count: must be >= 1, got {}", initial_count);
  if (max_modes < 1) return fmt::format("max_modes: must be >= 1, got {}", max_modes);
  if (!(rigid_tolerance_hz >= 0.0) || !std::isfinite(rigid_tolerance_hz))
    return fmt::format("rigid_tolerance_hz: must be a finite number >= 0, got {}", rigid_tolerance_hz);
  if (!(rayleigh_mass >= 0.0) || !std::isfinite(rayleigh_mass))
    return fmt::format("rayleigh_mass: must be a finite number >= 0, got {}", rayleigh_mass);
  if (!(rayleigh_stiffness >= 0.0) || !std::isfinite(rayleigh_stiffness))
    return fmt::format("rayleigh_stiffness: must be a finite number >= 0, got {}", rayleigh_stiffness);
  if (std::string problem = modal.validate(); !problem.empty()) return "modal." + problem;
  return {};
}

std::string ModalInterfaceResult::brief() const {
  const hb::InterfaceModel& m = model;
  return fmt::format("{} kept modes ({} rigid) of {} computed{}{}, {} contact points ({} distinct) in {} groups, {} "
                     "outputs, {:.2f} s (modes {:.2f}, factor {:.2f}, residual {:.2f})",
                     kept_modes, m.rigid_modes, modes.eigenvalues.size(),
                     kept_modes > 0 ? fmt::format(", up to {:.6g} Hz", modes.frequencies_hz[kept_modes - 1]) : "",
                     truncated_by_max_modes ? " (max_modes reached before the cutoff)" : "", m.num_points(),
                     distinct_gap_rows / 3, m.groups.size(), m.outputs.size(), seconds, modes_seconds,
                     factor_seconds, residual_seconds);
}

ModalInterfaceResult build_modal_interface(const preload::PreloadModel& model, const preload::PreloadResult& preload,
                                           const ModalLoad& load, const std::vector<ModalOutputSpec>& outputs,
                                           const ModalInterfaceOptions& options) {
  const auto start = support::Clock::now();
  if (const std::string problem = options.validate(); !problem.empty())
    throw std::invalid_argument("modal interface options: " + problem);
  if (model.mesh == nullptr) throw std::invalid_argument("modal interface: model.mesh: the model has no mesh");
  if (model.interfaces.empty())
    throw std::invalid_argument("modal interface: model.interfaces: the model has no contact interface");
  if (preload.interfaces.size() != model.interfaces.size())
    throw std::invalid_argument(fmt::format("modal interface: preload.interfaces: the preload has {} interfaces, the model {}",
                                            preload.interfaces.size(), model.interfaces.size()));
  if (!preload.status().ok())
    throw std::invalid_argument("modal interface: preload.termination: the preload did not converge (" + preload.message + ")");
  const int num_full = model.mesh->num_dofs();
  if (preload.displacement.size() != num_full)
    throw std::invalid_argument(fmt::format("modal interface: preload.displacement: {} entries, the mesh has {} DOFs",
                                            preload.displacement.size(), num_full));
  if (load.force.size() != num_full)
    throw std::invalid_argument(fmt::format("modal interface: load.force ('{}'): {} entries, the mesh has {} DOFs",
                                            load.name, load.force.size(), num_full));
  if (!finite(load.force)) throw std::invalid_argument(fmt::format("modal interface: load.force ('{}'): not finite", load.name));
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    if (outputs[k].functional.size() != num_full)
      throw std::invalid_argument(fmt::format("modal interface: outputs[{}].functional ('{}'): {} entries, the mesh has {} DOFs",
                                              k, outputs[k].name, outputs[k].functional.size(), num_full));
    if (!finite(outputs[k].functional))
      throw std::invalid_argument(
          fmt::format("modal interface: outputs[{}].functional ('{}'): not finite", k, outputs[k].name));
  }
  for (std::size_t i = 0; i < model.interfaces.size(); ++i) {
    const preload::ContactInterface& ci = model.interfaces[i];
    const auto P = static_cast<Eigen::Index>(ci.geometry.points.size());
    const fe::InterfaceContactState& state = preload.interfaces[i].state;
    if (state.gap.size() != 3 * P || state.traction.size() != 3 * P)
      throw std::invalid_argument(fmt::format("modal interface: preload.interfaces[{}].state ('{}'): {} gaps for {} points",
                                              i, ci.geometry.name, state.gap.size() / 3, P));
    if (ci.geometry.gap_operator.rows() != 3 * P || ci.geometry.gap_operator.cols() != num_full)
      throw std::invalid_argument(fmt::format("modal interface: model.interfaces[{}].geometry.gap_operator ('{}'): {} x {}, "
                                              "expected {} x {}", i, ci.geometry.name, ci.geometry.gap_operator.rows(),
                                              ci.geometry.gap_operator.cols(), 3 * P, num_full));
  }

  ModalInterfaceResult r;
  hb::InterfaceModel& im = r.model;
  im.rayleigh_mass = options.rayleigh_mass;
  im.rayleigh_stiffness = options.rayleigh_stiffness;
  const double s = options.modal.shift;
  im.residual_shift = s;

  // The dynamics keep every DOF not held by the user: the preload's 3-2-1 support of a free-free
  // assembly only removed the rigid-body motions from the static solve.
  const fe::DofMap dofs = fe::DofMap::from_fixed_nodes(model.mesh->num_nodes(), model.constraints);
  const int n = dofs.num_free();
  if (n < 2) throw std::invalid_argument("modal interface: the model has fewer than 2 free DOFs");
  const SpMat K = dofs.restrict(preload::dynamic_stiffness(model, preload.displacement));
  const SpMat M = dofs.restrict(model.structure.mass);

  // ---- modes up to the cutoff: double the count until the last one lies above it --------------
  auto t = support::Clock::now();
  const double cutoff_lambda = std::pow(kTwoPi * options.cutoff_hz, 2);
  modal::ModalOptions mo = options.modal;
  mo.iterative = fe::with_rigid_body_modes(mo.iterative, mo.linear_solver, *model.mesh, dofs);
  mo.count = std::min({options.initial_count, options.max_modes, n - 1});
  for (;;) {
    if (mo.ncv != 0 && mo.ncv <= mo.count) mo.ncv = std::min(n, 2 * mo.count + 1);  // a fixed ncv must exceed count
    r.modes = modal::compute_modes(K, M, mo);
    if (r.modes.termination != Termination::converged)
      throw std::runtime_error("modal interface: modes of the stuck tangent: " + r.modes.message);
    const bool above = r.modes.eigenvalues[r.modes.eigenvalues.size() - 1] > cutoff_lambda;
    if (above || mo.count >= std::min(options.max_modes, n - 1)) {
      r.truncated_by_max_modes = !above;
      break;
    }
    mo.count = std::min({2 * mo.count, options.max_modes, n - 1});
  }
  Eigen::Index kept = 0;
  while (kept < r.modes.eigenvalues.size() && r.modes.eigenvalues[kept] <= cutoff_lambda) ++kept;
  r.kept_modes = static_cast<int>(kept);
  for (Eigen::Index j = 0; j < kept; ++j)
    if (r.modes.frequencies_hz[j] <= -options.rigid_tolerance_hz)
      throw std::runtime_error(fmt::format(
          "modal interface: mode {} of the stuck tangent has a negative eigenvalue ({:.6g} Hz beyond the rigid-body "
          "tolerance {:.6g} Hz): K_t is not positive semi-definite", j + 1, r.modes.frequencies_hz[j],
          options.rigid_tolerance_hz));
  int rigid = 0;
  while (rigid < kept && std::abs(r.modes.frequencies_hz[rigid]) < options.rigid_tolerance_hz) ++rigid;
  const Eigen::MatrixXd Phi = r.modes.shapes.leftCols(kept);
  im.omega2 = r.modes.eigenvalues.head(kept);
  im.omega2.head(rigid).setZero();  // after everything that could use the computed λ (nothing below does)
  im.rigid_modes = rigid;
  r.modes_seconds = seconds_since(t);

  // ---- contact data ---------------------------------------------------------------------------
  const SpMat G = stacked_gap_operator(model, dofs);
  const auto rows = static_cast<Eigen::Index>(G.rows());
  const Eigen::Index P = rows / 3;
  im.areas.resize(P);
  im.references.reserve(static_cast<std::size_t>(P));
  im.stuck_tangents.reserve(static_cast<std::size_t>(P));
  int first = 0;
  for (std::size_t i = 0; i < model.interfaces.size(); ++i) {
    const preload::ContactInterface& ci = model.interfaces[i];
    const fe::InterfaceContactState& state = preload.interfaces[i].state;
    const int count = ci.geometry.num_points();
    im.groups.push_back(hb::InterfaceGroup{ci.geometry.name, ci.law, first, count});
    const std::vector<hb::ContactPointReference> refs = hb::contact_point_references(state.gap, state.traction);
    im.references.insert(im.references.end(), refs.begin(), refs.end());
    const std::vector<Eigen::Matrix3d> tangents = preload::stuck_tangents(ci, state.gap);
    im.stuck_tangents.insert(im.stuck_tangents.end(), tangents.begin(), tangents.end());
    for (int p = 0; p < count; ++p) im.areas[first + p] = ci.geometry.points[static_cast<std::size_t>(p)].area;
    first += count;
  }
  im.gap_shapes = G * Phi;

  // ---- S = K_t − sM, factored once ------------------------------------------------------------
  t = support::Clock::now();
  fe::SparseCholesky factor(fe::SparseCholesky::Options{.backend = mo.linear_solver, .iterative = mo.iterative});
  try {
    factor.compute(SpMat(K - s * M));
  } catch (const std::runtime_error& error) {
    throw std::runtime_error(fmt::format("modal interface: K_t - s M (s = {:.6g} rad^2/s^2, modal.shift) is not positive "
                                         "definite (the shift must lie below the lowest eigenvalue): {}", s, error.what()));
  }
  r.factor_seconds = seconds_since(t);

  // ---- residual terms: one blocked deflated solve [Gᵀ | f | c_1 … c_k] ------------------------
  t = support::Clock::now();
  const Eigen::VectorXd f = dofs.restrict(load.force);
  const auto num_out = static_cast<Eigen::Index>(outputs.size());
  std::vector<Eigen::VectorXd> c;
  c.reserve(outputs.size());
  for (const ModalOutputSpec& o : outputs) c.push_back(dofs.restrict(o.functional));
  // Only the distinct rows of G are solved for; the duplicates are copies (exact).
  // (named members, not a structured binding: a lambda below captures `rep`, which C++20 allows
  // for bindings but Clang before 16 does not)
  const std::pair<SpMat, std::vector<int>> distinct_split = distinct_rows(G);
  const SpMat& Gd = distinct_split.first;
  const std::vector<int>& rep = distinct_split.second;
  const Eigen::Index distinct = Gd.rows();
  r.distinct_gap_rows = static_cast<int>(distinct);
  const Eigen::Index width = distinct + 1 + num_out, col_f = distinct;
  // W = S⁻¹ [Gdᵀ | f | c_1 … c_k], solved in blocks of columns so that no dense copy of the whole
  // right-hand side exists beside W (at 50 000 DOFs and 5 000 distinct rows each is 2 GB).
  Eigen::MatrixXd W(n, width);
  {
    const SpMat Gdt = Gd.transpose();
    for (Eigen::Index from = 0; from < width; from += kSolveBlock) {
      const Eigen::Index cols = std::min(kSolveBlock, width - from);
      Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, cols);
      for (Eigen::Index j = from; j < from + cols; ++j) {
        if (j < distinct) B.col(j - from) = Gdt.col(j);
        else if (j == col_f) B.col(j - from) = f;
        else B.col(j - from) = c[static_cast<std::size_t>(j - col_f - 1)];
      }
      W.middleCols(from, cols) = factor.solve(B);
    }
  }
  // Deflation W ← (I − ΦΦᵀM) W, twice: the second pass removes what round-off left of the kept
  // modes (the kept part dominates S⁻¹Gᵀ, the residual part is what is wanted).
  const Eigen::MatrixXd MPhi = M * Phi;
  Eigen::MatrixXd coefficients(kept, width);
  for (int pass = 0; pass < 2; ++pass) {
    gemm(true, false, 1.0, MPhi, W, 0.0, coefficients);  // ΦᵀM W
    gemm(false, false, -1.0, Phi, coefficients, 1.0, W);  // W −= Φ (ΦᵀM W)
  }
  // Q = Wᵀ M W (R1, load and output first-order terms; O(n · width²), the largest cost of the
  // condensation of a fine interface), by blocks of columns of M W, each only down to its own
  // diagonal block: Q is symmetric, the rest is mirrored (half the flops).
  Eigen::MatrixXd Q(width, width);
  for (Eigen::Index from = 0; from < width; from += kSolveBlock) {
    const Eigen::Index cols = std::min(kSolveBlock, width - from), upto = from + cols;
    const Eigen::MatrixXd MWb = M * W.middleCols(from, cols);
    // Q(0:upto, from:upto) = W(:, 0:upto)ᵀ (M W)(:, from:upto)
    const int rows_q = static_cast<int>(upto), cols_q = static_cast<int>(cols), inner = static_cast<int>(n);
    const double one = 1.0, zero = 0.0;
    const char ta = 'T', tb = 'N';
    const int ld = static_cast<int>(std::max<Eigen::Index>(1, n)), ldc = static_cast<int>(width);
    dgemm_(&ta, &tb, &rows_q, &cols_q, &inner, &one, W.data(), &ld, MWb.data(), &ld, &zero, Q.data() + from * width,
           &ldc);
  }
  for (Eigen::Index j = 0; j < width; ++j)
    for (Eigen::Index i = (j / kSolveBlock + 1) * kSolveBlock; i < width; ++i) Q(i, j) = Q(j, i);
  // G W on the distinct rows only (R0, load and output quasi-static terms); row i of G W is row
  // rep[i] of Gd W.
  const Eigen::MatrixXd GdW = Gd * W;
  const auto GW = [&](Eigen::Index column) {
    Eigen::VectorXd v(rows);
    for (Eigen::Index i = 0; i < rows; ++i) v[i] = GdW(rep[static_cast<std::size_t>(i)], column);
    return v;
  };

  // Expand the distinct columns: R0 = G Z, R1 = Zᵀ M Z with Z's column j = distinct column rep[j],
  // symmetrised in place (no temporaries: at 20 000 gap rows each matrix is 3.4 GB).
  Eigen::MatrixXd& R0 = im.residual_flexibility;
  Eigen::MatrixXd& R1 = im.residual_inertia;
  R0.resize(rows, rows);
  R1.resize(rows, rows);
  Eigen::VectorXd q_f(rows);
  for (Eigen::Index j = 0; j < rows; ++j) {
    const int dj = rep[static_cast<std::size_t>(j)];
    for (Eigen::Index i = 0; i < rows; ++i) R0(i, j) = GdW(rep[static_cast<std::size_t>(i)], dj);
    q_f[j] = Q(dj, col_f);
    for (Eigen::Index i = 0; i < rows; ++i) R1(i, j) = Q(rep[static_cast<std::size_t>(i)], dj);
  }
  constexpr Eigen::Index kTile = 64;  // tiles, so that the transposed reads stay in cache
  for (Eigen::Index j0 = 0; j0 < rows; j0 += kTile)
    for (Eigen::Index i0 = j0; i0 < rows; i0 += kTile)
      for (Eigen::Index j = j0; j < std::min(rows, j0 + kTile); ++j)
        for (Eigen::Index i = std::max(i0, j + 1); i < std::min(rows, i0 + kTile); ++i) {
          R0(i, j) = R0(j, i) = 0.5 * (R0(i, j) + R0(j, i));
          R1(i, j) = R1(j, i) = 0.5 * (R1(i, j) + R1(j, i));
        }
  im.load_name = load.name;
  im.load_modal = Phi.transpose() * f;
  im.load_residual0 = GW(col_f);
  im.load_residual1 = q_f;
  for (Eigen::Index k = 0; k < num_out; ++k) {
    const Eigen::Index col = col_f + 1 + k;
    hb::InterfaceOutput o;
    o.name = outputs[static_cast<std::size_t>(k)].name;
    o.modal = Phi.transpose() * c[static_cast<std::size_t>(k)];
    o.residual0 = GW(col);
    o.residual1.resize(rows);
    for (Eigen::Index i = 0; i < rows; ++i) o.residual1[i] = Q(rep[static_cast<std::size_t>(i)], col);
    o.load_residual0 = c[static_cast<std::size_t>(k)].dot(W.col(col_f));
    o.load_residual1 = Q(col, col_f);
    im.outputs.push_back(std::move(o));
  }
  if (options.keep_field_recovery) {
    FieldRecovery& fr = r.recovery;
    fr.modes = Phi;
    fr.load_residual = W.col(col_f);
    W.conservativeResize(Eigen::NoChange, distinct);  // the solves for Gdᵀ: kept, not copied
    fr.residual = std::move(W);
    fr.column_of_row = rep;
    fr.full_of_free = dofs.full_of_free;
    fr.num_full = num_full;
    fr.rayleigh_stiffness = options.rayleigh_stiffness;
  }
  r.residual_seconds = seconds_since(t);

  if (const std::string problem = im.validate(); !problem.empty())
    throw std::runtime_error("modal interface: the model built is inconsistent: " + problem);
  r.seconds = seconds_since(start);
  return r;
}

}  // namespace jointhb::reduction
