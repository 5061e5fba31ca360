#include "jointhb/reduction/craig_bampton.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "../support/blas_gemm.hpp"
#include "../support/sparse_norm.hpp"
#include "../support/stopwatch.hpp"
#include "jointhb/fe/sparse_cholesky.hpp"

namespace jointhb::reduction {

namespace {

using SpMat = Eigen::SparseMatrix<double>;
using support::seconds_since;

// The block A(rows, cols) of a sparse matrix, with rows/cols given as "position in the block or
// −1" for every index of A.
SpMat block(const SpMat& A, const std::vector<int>& row_position, int rows,
            const std::vector<int>& col_position, int cols) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int j = 0; j < A.outerSize(); ++j) {
    for (SpMat::InnerIterator it(A, j); it; ++it) {
      const int r = row_position[static_cast<std::size_t>(it.row())];
      const int c = col_position[static_cast<std::size_t>(it.col())];
      if (r >= 0 && c >= 0) entries.emplace_back(r, c, it.value());
    }
  }
  SpMat B(rows, cols);
  B.setFromTriplets(entries.begin(), entries.end());
  return B;
}

Eigen::MatrixXd symmetric_part(const Eigen::MatrixXd& A) { return 0.5 * (A + A.transpose()); }

}  // namespace

std::string CraigBamptonOptions::validate() const {
  if (!(cutoff_hz > 0.0) || !std::isfinite(cutoff_hz))
    return fmt::format("cutoff_hz: must be a finite number > 0, got {}", cutoff_hz);
  if (initial_count < 1) return fmt::format("initial_count: must be >= 1, got {}", initial_count);
  if (max_modes < 1) return fmt::format("max_modes: must be >= 1, got {}", max_modes);
  return modal.validate();
}

CraigBamptonModel craig_bampton(const SpMat& K, const SpMat& M, std::vector<int> boundary,
                                const CraigBamptonOptions& options) {
  const auto start = support::Clock::now();
  if (const std::string problem = options.validate(); !problem.empty())
    throw std::invalid_argument("Craig-Bampton options: " + problem);
  const int n = static_cast<int>(K.rows());
  if (K.cols() != n || M.rows() != n || M.cols() != n)
    throw std::invalid_argument(fmt::format("Craig-Bampton: K is {}x{} and M {}x{}; both must be square and of one size",
                                            K.rows(), K.cols(), M.rows(), M.cols()));
  std::sort(boundary.begin(), boundary.end());
  if (!boundary.empty() && (boundary.front() < 0 || boundary.back() >= n))
    throw std::invalid_argument(fmt::format("Craig-Bampton: boundary DOF outside [0, {})", n));
  if (std::adjacent_find(boundary.begin(), boundary.end()) != boundary.end())
    throw std::invalid_argument("Craig-Bampton: a boundary DOF is listed twice");

  CraigBamptonModel r;
  r.boundary = boundary;
  std::vector<int> b_pos(static_cast<std::size_t>(n), -1), i_pos(static_cast<std::size_t>(n), -1);
  for (std::size_t k = 0; k < boundary.size(); ++k) b_pos[static_cast<std::size_t>(boundary[k])] = static_cast<int>(k);
  for (int d = 0; d < n; ++d)
    if (b_pos[static_cast<std::size_t>(d)] < 0) {
      i_pos[static_cast<std::size_t>(d)] = static_cast<int>(r.interior.size());
      r.interior.push_back(d);
    }
  const int nb = static_cast<int>(boundary.size()), ni = static_cast<int>(r.interior.size());
  if (ni == 0) throw std::invalid_argument("Craig-Bampton: every DOF is a boundary DOF; nothing to reduce");

  const SpMat K_ii = block(K, i_pos, ni, i_pos, ni), K_ib = block(K, i_pos, ni, b_pos, nb);
  const SpMat M_ii = block(M, i_pos, ni, i_pos, ni), M_ib = block(M, i_pos, ni, b_pos, nb);
  // The boundary-row blocks stored column-major as well: Eigen's fast sparse × dense path.
  const SpMat K_bi = block(K, b_pos, nb, i_pos, ni), M_bi = block(M, b_pos, nb, i_pos, ni);
  const Eigen::MatrixXd K_bb = Eigen::MatrixXd(block(K, b_pos, nb, b_pos, nb));
  const Eigen::MatrixXd M_bb = Eigen::MatrixXd(block(M, b_pos, nb, b_pos, nb));

  // K_ii's factor, for the constraint modes below.
  auto t = support::Clock::now();
  // The cg backend's near-null space (given on K's rows) restricted to the interior rows.
  modal::ModalOptions interior_modal = options.modal;
  if (interior_modal.iterative.near_null_space.rows() == n) {
    Eigen::MatrixXd interior_null(ni, interior_modal.iterative.near_null_space.cols());
    for (int k = 0; k < ni; ++k)
      interior_null.row(k) = options.modal.iterative.near_null_space.row(r.interior[static_cast<std::size_t>(k)]);
    interior_modal.iterative.near_null_space = std::move(interior_null);
  }
  fe::SparseCholesky factor(fe::SparseCholesky::Options{.backend = interior_modal.linear_solver,
                                                        .iterative = interior_modal.iterative});
  try {
    factor.compute(K_ii);
  } catch (const std::runtime_error& error) {
    throw std::runtime_error(std::string("Craig-Bampton: the interior stiffness K_ii is not positive definite (is some "
                                         "part held neither by the boundary nor by other stiffness?): ") + error.what());
  }
  r.factor_seconds = seconds_since(t);

  // Fixed-interface modes up to the cutoff: double the count until the last one lies above it.
  t = support::Clock::now();
  const double cutoff_lambda = std::pow(2.0 * 3.141592653589793 * options.cutoff_hz, 2);
  modal::ModalOptions mo = interior_modal;
  mo.count = std::min({options.initial_count, options.max_modes, ni - 1});
  modal::ModalResult modes;
  for (;;) {
    modes = modal::compute_modes(K_ii, M_ii, mo);
    if (modes.termination != Termination::converged)
      throw std::runtime_error("Craig-Bampton: fixed-interface modes: " + modes.message);
    const bool above = modes.eigenvalues[modes.eigenvalues.size() - 1] > cutoff_lambda;
    if (above || mo.count >= std::min(options.max_modes, ni - 1)) {
      r.truncated_by_max_modes = !above;
      break;
    }
    mo.count = std::min({2 * mo.count, options.max_modes, ni - 1});
  }
  Eigen::Index kept = 0;
  while (kept < modes.eigenvalues.size() && modes.eigenvalues[kept] <= cutoff_lambda) ++kept;
  r.normal_modes = modes.shapes.leftCols(kept);
  r.normal_eigenvalues = modes.eigenvalues.head(kept);
  r.normal_frequencies_hz = modes.frequencies_hz.head(kept);
  r.modes_seconds = seconds_since(t);

  // A part held by nothing in the interior (e.g. joined to the boundary parts by bolts only
  // along one axis) has rigid fixed-interface modes: λ_1 at round-off level, ε ‖K_ii‖/‖M_ii‖,
  // where CHOLMOD may still find tiny positive pivots. Elastic modes lie far above 1e-13 of
  // ‖K_ii‖₁/‖M_ii‖₁ (the square of the mesh's highest frequency).
  if (modes.eigenvalues[0] < 1e-13 * support::norm1(K_ii) / support::norm1(M_ii))
    throw std::runtime_error(fmt::format(
        "Craig-Bampton: the interior stiffness K_ii is not positive definite: a fixed-interface mode at "
        "{:.3g} Hz is a rigid-body motion (is some part held neither by the boundary nor by other stiffness?)",
        modes.frequencies_hz[0]));

  // Constraint modes Ψ = −K_ii⁻¹ K_ib (CB-1): one blocked solve.
  t = support::Clock::now();
  r.constraint_modes = -factor.solve(Eigen::MatrixXd(K_ib));
  r.constraint_seconds = seconds_since(t);

  // Projection (CB-2).
  t = support::Clock::now();
  const int m = static_cast<int>(kept), size = nb + m;
  const Eigen::MatrixXd& Psi = r.constraint_modes;
  // C = M_bi + Ψᵀ M_ii (nb × n_i): M_r's boundary block is M_bb + C Ψ + (M_bi Ψ)ᵀ and its
  // coupling block C Φ. C Ψ is the O(n_i nb²) product that dominates for large interfaces.
  const Eigen::MatrixXd coupling = Eigen::MatrixXd(M_bi) + (M_ii * Psi).transpose();
  const Eigen::MatrixXd MbiPsi = M_bi * Psi;
  r.stiffness = Eigen::MatrixXd::Zero(size, size);
  r.mass = Eigen::MatrixXd::Zero(size, size);
  r.stiffness.topLeftCorner(nb, nb) = symmetric_part(K_bb + Eigen::MatrixXd(K_bi * Psi));
  r.stiffness.bottomRightCorner(m, m) = r.normal_eigenvalues.asDiagonal();
  Eigen::MatrixXd Mbb = M_bb + MbiPsi.transpose();
  support::gemm_add(coupling, Psi, Mbb);  // + C Ψ, the O(n_i nb²) product, through the BLAS
  r.mass.topLeftCorner(nb, nb) = symmetric_part(Mbb);
  const Eigen::MatrixXd Mbm = coupling * r.normal_modes;
  r.mass.topRightCorner(nb, m) = Mbm;
  r.mass.bottomLeftCorner(m, nb) = Mbm.transpose();
  r.mass.bottomRightCorner(m, m).setIdentity();
  r.projection_seconds = seconds_since(t);
  r.seconds = seconds_since(start);
  return r;
}

Eigen::VectorXd CraigBamptonModel::expand(const Eigen::Ref<const Eigen::VectorXd>& q) const {
  if (q.size() != size())
    throw std::invalid_argument(fmt::format("Craig-Bampton expand: q has {} entries, the model {}", q.size(), size()));
  const int nb = num_boundary();
  const Eigen::VectorXd u_i = constraint_modes * q.head(nb) + normal_modes * q.tail(num_modes());
  Eigen::VectorXd u(static_cast<Eigen::Index>(boundary.size() + interior.size()));
  for (int k = 0; k < nb; ++k) u[boundary[static_cast<std::size_t>(k)]] = q[k];
  for (std::size_t k = 0; k < interior.size(); ++k) u[interior[k]] = u_i[static_cast<Eigen::Index>(k)];
  return u;
}

Eigen::VectorXd CraigBamptonModel::project(const Eigen::Ref<const Eigen::VectorXd>& f) const {
  const auto n = static_cast<Eigen::Index>(boundary.size() + interior.size());
  if (f.size() != n)
    throw std::invalid_argument(fmt::format("Craig-Bampton project: f has {} entries, the model {}", f.size(), n));
  Eigen::VectorXd f_b(num_boundary()), f_i(static_cast<Eigen::Index>(interior.size()));
  for (int k = 0; k < num_boundary(); ++k) f_b[k] = f[boundary[static_cast<std::size_t>(k)]];
  for (std::size_t k = 0; k < interior.size(); ++k) f_i[static_cast<Eigen::Index>(k)] = f[interior[k]];
  Eigen::VectorXd q(size());
  q.head(num_boundary()) = f_b + constraint_modes.transpose() * f_i;
  q.tail(num_modes()) = normal_modes.transpose() * f_i;
  return q;
}

std::string CraigBamptonModel::brief() const {
  return fmt::format("{} boundary DOFs + {} fixed-interface modes{}{}, {:.2f} s (factor {:.2f}, constraint modes {:.2f}, "
                     "modes {:.2f}, projection {:.2f})",
                     num_boundary(), num_modes(),
                     num_modes() > 0 ? fmt::format(" ≤ {:.6g} Hz", normal_frequencies_hz[num_modes() - 1]) : "",
                     truncated_by_max_modes ? " (max_modes reached before the cutoff)" : "", seconds, factor_seconds,
                     constraint_seconds, modes_seconds, projection_seconds);
}

}  // namespace jointhb::reduction
