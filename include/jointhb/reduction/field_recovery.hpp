#pragma once
// Full-field displacements of a harmonic-balance solution on the modal/interface model
// (hb/interface_model.hpp; docs/theory.md §11, eq. T-33).
//
// The model's unknowns are the kept modal coordinates η_j and the interface gaps; every other
// DOF follows from eq. (T-25) with the gap operator G replaced by the identity:
//   u_k = Σ_{j kept} φ_j η_jk + Σ_r φ_r h_r,k φ_rᵀ (f_k − Gᵀ A N_k),
// and with the leading (quasi-static) term of the residual modes' receptance (T-23),
// h_r,k ≈ 1/(β_k μ_r), β_k = 1 + i kΩ b,
//   u_k = Φ η_k + β_k⁻¹ (z_f F_k − Z (A N)_kᵀ),                                            (T-33)
// where Z = (I − ΦΦᵀM) S⁻¹Gᵀ and z_f = (I − ΦΦᵀM) S⁻¹ f are the deflated solves that
// reduction/modal_interface.hpp makes anyway for R0 = G Z (kept when
// ModalInterfaceOptions::keep_field_recovery is set). β_k⁻¹ multiplies the complex pair
// (a_k − i b_k) of harmonic k; the mean (k = 0) has β = 1. The neglected first-order term
// −w/(β²μ_r²) is what R1 adds to the gaps: so G u_k differs from the solution's gaps by
// R1-sized terms, O((kΩ)²/μ_cutoff) relative to the residual part (tested).
//
// Memory: Φ (n × n_s) and Z over the distinct contact rows (n × 3P_d), the same two dense blocks
// the condensation already holds.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "jointhb/hb/fourier.hpp"

namespace jointhb::reduction {

struct FieldRecovery {
  Eigen::MatrixXd modes;          ///< Φ on the free DOFs (n × n_s), M-normalised
  Eigen::MatrixXd residual;       ///< Z's distinct columns (n × R)
  std::vector<int> column_of_row; ///< contact row 3p + d → column of `residual` (3P entries)
  Eigen::VectorXd load_residual;  ///< z_f (n)
  std::vector<int> full_of_free;  ///< free DOF → mesh DOF
  int num_full = 0;               ///< mesh DOFs (3N)
  double rayleigh_stiffness = 0.0;  ///< b of C = a M + b K_t [s]

  [[nodiscard]] bool empty() const { return modes.size() == 0; }
  [[nodiscard]] int points() const { return static_cast<int>(column_of_row.size() / 3); }

  /// Mesh-DOF coefficients (3N × m, zero at constrained DOFs) of eq. (T-33):
  ///   eta (m × n_s), contact_force = A N (m × 3P) of an evaluation at the solution, load F (m or
  ///   empty), Ω [rad/s]. Throws std::invalid_argument on inconsistent sizes or an empty recovery.
  [[nodiscard]] Eigen::MatrixXd displacement(const hb::FourierBasis& basis, double omega,
                                             const Eigen::MatrixXd& eta,
                                             const Eigen::MatrixXd& contact_force,
                                             const Eigen::VectorXd& load) const;

  /// The recovery of a model whose contact points were merged (reduction/contact_patches.hpp):
  /// patch c's column is Σ_{p∈c} ω_p Z_p (the force A_c N_c is shared as ω_p A_c N_c, eq. T-31).
  /// `patch_of_point` and `point_weights` have P entries. Throws std::invalid_argument on sizes.
  [[nodiscard]] FieldRecovery merged(const std::vector<int>& patch_of_point,
                                     const std::vector<double>& point_weights, int patches) const;
};

}  // namespace jointhb::reduction
