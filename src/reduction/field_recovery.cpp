#include "jointhb/reduction/field_recovery.hpp"

#include <fmt/format.h>

#include <complex>
#include <stdexcept>

namespace jointhb::reduction {

Eigen::MatrixXd FieldRecovery::displacement(const hb::FourierBasis& basis, double omega, const Eigen::MatrixXd& eta,
                                            const Eigen::MatrixXd& contact_force,
                                            const Eigen::VectorXd& load) const {
  if (empty()) throw std::invalid_argument("field recovery: empty (keep_field_recovery was not set)");
  const Eigen::Index m = basis.size(), P3 = static_cast<Eigen::Index>(column_of_row.size());
  if (eta.rows() != m || eta.cols() != modes.cols())
    throw std::invalid_argument(fmt::format("field recovery: eta is {} x {}, expected {} x {}", eta.rows(), eta.cols(), m,
                                            modes.cols()));
  if (contact_force.rows() != m || contact_force.cols() != P3)
    throw std::invalid_argument(fmt::format("field recovery: contact_force is {} x {}, expected {} x {}",
                                            contact_force.rows(), contact_force.cols(), m, P3));
  if (load.size() != 0 && load.size() != m)
    throw std::invalid_argument(fmt::format("field recovery: load has {} coefficients, expected {}", load.size(), m));
  // Z (A N)ᵀ over the distinct columns: rows that share a column add their forces.
  Eigen::MatrixXd force(residual.cols(), m);
  force.setZero();
  for (Eigen::Index row = 0; row < P3; ++row)
    force.row(column_of_row[static_cast<std::size_t>(row)]) += contact_force.col(row).transpose();
  Eigen::MatrixXd quasi_static = -residual * force;  // n × m
  if (load.size() != 0) quasi_static += load_residual * load.transpose();
  Eigen::MatrixXd u = modes * eta.transpose();  // n × m
  if (basis.has_mean()) u.col(0) += quasi_static.col(0);
  for (int k : basis.orders()) {
    // a − i b ↦ (a − i b)/β, β = 1 + i kΩ b_R
    const int ia = basis.cosine_index(k), ib = ia + 1;
    const std::complex<double> inv_beta = 1.0 / std::complex<double>(1.0, k * omega * rayleigh_stiffness);
    u.col(ia) += inv_beta.real() * quasi_static.col(ia) + inv_beta.imag() * quasi_static.col(ib);
    u.col(ib) += inv_beta.real() * quasi_static.col(ib) - inv_beta.imag() * quasi_static.col(ia);
  }
  Eigen::MatrixXd full = Eigen::MatrixXd::Zero(num_full, m);
  for (std::size_t i = 0; i < full_of_free.size(); ++i) full.row(full_of_free[i]) = u.row(static_cast<Eigen::Index>(i));
  return full;
}

FieldRecovery FieldRecovery::merged(const std::vector<int>& patch_of_point, const std::vector<double>& point_weights,
                                    int patches) const {
  const std::size_t P = column_of_row.size() / 3;
  if (patch_of_point.size() != P || point_weights.size() != P)
    throw std::invalid_argument(fmt::format("field recovery: {} patch indices and {} weights for {} points",
                                            patch_of_point.size(), point_weights.size(), P));
  FieldRecovery r = *this;
  r.residual = Eigen::MatrixXd::Zero(residual.rows(), 3 * static_cast<Eigen::Index>(patches));
  r.column_of_row.resize(3 * static_cast<std::size_t>(patches));
  for (int c = 0; c < 3 * patches; ++c) r.column_of_row[static_cast<std::size_t>(c)] = c;
  for (std::size_t p = 0; p < P; ++p) {
    const int c = patch_of_point[p];
    if (c < 0 || c >= patches) throw std::invalid_argument(fmt::format("field recovery: point {} in patch {}", p, c));
    for (int d = 0; d < 3; ++d)
      r.residual.col(3 * c + d) += point_weights[p] * residual.col(column_of_row[3 * p + static_cast<std::size_t>(d)]);
  }
  return r;
}

}  // namespace jointhb::reduction
