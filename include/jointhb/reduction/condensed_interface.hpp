#pragma once
// The preloaded finite-element model condensed to its contact interfaces (docs/reduction.md §5):
// Craig–Bampton (reduction/craig_bampton.hpp) of the structure plus bolt springs, with the
// boundary = every DOF of every node of the zero-thickness elements, and the contact points
// carried over with their preloaded state. Reduced coordinates q = [u_b; η]; the gaps of all
// interface points are g = g_pre + G_r q (G_r: the gap operator on the reduced coordinates), and
// the contact forces enter as G_rᵀ A t. The stuck contact tangent adds to the boundary block:
//
//   K_stuck = K_r + G_rᵀ A C_pre G_r,   C_pre = diag(k_T(p_pre), k_T(p_pre), λ p_pre)    (P-2)
//
// so the linear modes of (K_stuck, M_r) approximate those of the full preloaded model; their
// error comes from the truncation of the fixed-interface modes alone.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/craig_bampton.hpp"

namespace jointhb::reduction {

/// The contact points of one interface in the condensed model.
struct CondensedInterface {
  std::string name;
  Eigen::SparseMatrix<double> gap_operator;  ///< G_r: 3P × size(), rows (t1, t2, n) per point
  Eigen::VectorXd areas;                     ///< A_p [m²], P
  Eigen::VectorXd reference_gap;             ///< g_pre, 3P (local frames)
  Eigen::VectorXd reference_traction;        ///< t_pre, 3P (t_N = −p_N)
  std::vector<Eigen::Matrix3d> stuck_tangents;  ///< C_pre per point
};

struct CondensedModel {
  CraigBamptonModel cb;                       ///< of K_structure + K_bolts (no contact)
  fe::DofMap dofs;                            ///< full ↔ free DOFs (constraints removed)
  std::vector<CondensedInterface> interfaces;
  Eigen::MatrixXd stuck_stiffness;            ///< K_r + Σ G_rᵀ A C_pre G_r (dense, size())
  double seconds = 0.0;

  [[nodiscard]] int size() const { return cb.size(); }
  /// Full-model displacement (all mesh DOFs, zeros at constraints) of reduced coordinates q.
  [[nodiscard]] Eigen::VectorXd expand(const Eigen::Ref<const Eigen::VectorXd>& q) const;
};

/// Condenses the preloaded `model` about `preload` (its displacement and interface states).
/// Throws std::invalid_argument when the model has no interface or the preload does not match it,
/// and what craig_bampton() throws.
[[nodiscard]] CondensedModel condense(const preload::PreloadModel& model,
                                      const preload::PreloadResult& preload,
                                      const CraigBamptonOptions& options);

}  // namespace jointhb::reduction
