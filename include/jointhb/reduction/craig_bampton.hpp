#pragma once
// Craig–Bampton reduction (fixed-interface component mode synthesis; Craig & Bampton, AIAA J.
// 6(7), 1968): the boundary DOFs b are kept physical, the interior DOFs i are represented by the
// static constraint modes Ψ and m fixed-interface normal modes Φ:
//
//   u = [u_b; u_i] = T [u_b; η],   T = [I 0; Ψ Φ],   Ψ = −K_ii⁻¹ K_ib,                 (CB-1)
//   K_ii Φ = M_ii Φ Λ,  Φᵀ M_ii Φ = I,
//
//   K_r = Tᵀ K T = [K_bb + K_bi Ψ   0;  0   Λ]                                          (CB-2)
//   M_r = Tᵀ M T = [M_bb + M_bi Ψ + Ψᵀ M_ib + Ψᵀ M_ii Ψ   (M_bi + Ψᵀ M_ii) Φ;  sym.   I]
//
// (the off-diagonal block of K_r vanishes because K_ii Ψ + K_ib = 0). K_bb + K_bi Ψ is the Guyan
// (Schur-complement) stiffness of the boundary.
//
// Use for bolted joints: take the boundary as every DOF of the nodes of the zero-thickness
// elements and reduce the structure *without* the contact stiffness. The contact tangent (and
// any other matrix acting on boundary DOFs only) then adds to the boundary block of K_r exactly:
// Ψ and Φ do not depend on it. The reduction error comes from the truncation of Φ alone and
// decreases as the cutoff rises (Craig & Bampton; validated in tests/unit/reduction).
//
// Cost: one CHOLMOD factorisation of K_ii, nb solves for Ψ (one blocked call), the ARPACK
// shift-invert solve for Φ (second factorisation of K_ii − σM_ii), and the dense products
// Ψᵀ (M_ii Ψ), O(n_i n_b²) flops, which dominate for large interfaces.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "jointhb/modal/modes.hpp"

namespace jointhb::reduction {

struct CraigBamptonOptions {
  /// Keep the fixed-interface modes with f ≤ cutoff_hz (> 0). The mode count grows by doubling
  /// from `initial_count` until the last mode computed lies above the cutoff or `max_modes`
  /// modes are kept (then `truncated_by_max_modes` is set).
  double cutoff_hz = 0.0;
  int initial_count = 20;  ///< ≥ 1
  int max_modes = 400;     ///< ≥ 1
  /// ARPACK settings for the fixed-interface problem (count is set by the doubling above). The
  /// default negative shift also suits interiors that are not held by the boundary (a part
  /// joined only through bolts: rigid-body fixed-interface modes at λ ≈ 0 are kept as modes).
  modal::ModalOptions modal{};

  /// Empty when valid, else "field: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

struct CraigBamptonModel {
  std::vector<int> boundary;  ///< DOF indices (into K's rows), ascending: reduced coordinates 0…nb−1
  std::vector<int> interior;  ///< the other DOFs, ascending
  Eigen::MatrixXd stiffness;  ///< K_r, (nb + m)², eq. (CB-2), symmetric
  Eigen::MatrixXd mass;       ///< M_r, (nb + m)², eq. (CB-2), symmetric
  Eigen::MatrixXd constraint_modes;  ///< Ψ, n_i × nb
  Eigen::MatrixXd normal_modes;      ///< Φ, n_i × m, M_ii-normalised
  Eigen::VectorXd normal_eigenvalues;    ///< Λ [rad²/s²], ascending
  Eigen::VectorXd normal_frequencies_hz; ///< of the kept fixed-interface modes
  bool truncated_by_max_modes = false;   ///< the cutoff was not reached within max_modes
  double factor_seconds = 0.0, constraint_seconds = 0.0, modes_seconds = 0.0,
         projection_seconds = 0.0, seconds = 0.0;

  [[nodiscard]] int num_boundary() const { return static_cast<int>(boundary.size()); }
  [[nodiscard]] int num_modes() const { return static_cast<int>(normal_modes.cols()); }
  [[nodiscard]] int size() const { return num_boundary() + num_modes(); }

  /// The full DOF vector u = T q of eq. (CB-1) for reduced coordinates q = [u_b; η].
  [[nodiscard]] Eigen::VectorXd expand(const Eigen::Ref<const Eigen::VectorXd>& q) const;
  /// Tᵀ f: a full force vector as reduced generalised forces.
  [[nodiscard]] Eigen::VectorXd project(const Eigen::Ref<const Eigen::VectorXd>& f) const;
  /// One line: "nb … boundary DOFs + m … modes ≤ … Hz, … s".
  [[nodiscard]] std::string brief() const;
};

/// Reduces (K, M) (square, same size, symmetric, both triangles stored) to the `boundary` DOFs
/// (any order, no duplicates, indices in [0, n)) plus fixed-interface modes up to the cutoff.
/// Throws std::invalid_argument on invalid options or indices, std::runtime_error when K_ii is
/// singular (an interior part neither held by the boundary nor by other stiffness: the message
/// says so) or the fixed-interface eigenproblem fails.
[[nodiscard]] CraigBamptonModel craig_bampton(const Eigen::SparseMatrix<double>& K,
                                              const Eigen::SparseMatrix<double>& M,
                                              std::vector<int> boundary,
                                              const CraigBamptonOptions& options);

}  // namespace jointhb::reduction
