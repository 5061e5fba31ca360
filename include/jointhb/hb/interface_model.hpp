#pragma once
// A preloaded linear structure seen from its contact points: the model that harmonic balance of a
// finite-element joint works on (docs/theory.md §11, eq. T-22 to T-25; built by
// reduction/modal_interface.hpp).
//
// The structure about its preloaded state obeys
//   M ü + C u̇ + K_s u + Gᵀ A Δt(G u) = f(t),                                              (T-22)
// with G the interface gap operator (3P rows: t1, t2, n per point), A the point areas and Δt the
// change of contact traction from the preloaded one. Split Δt = C_pre δg + N(δg), C_pre the
// preloaded ("stuck") contact tangent: the linear part K_t = K_s + Gᵀ A C_pre G is diagonalised by
// its modes φ_j (φᵀMφ = 1, ω_j²), with Rayleigh damping C = a M + b K_t (modal c_j = a + b ω_j²).
// The n_s lowest modes are kept as unknowns (η_j); the others respond quasi-statically with a
// first-order dynamic correction. For harmonic k at frequency Ω (EPMC: damping c − ξ),
//   h_r = 1 / (ω_r² − (kΩ)² + i kΩ (c_r − ξ)) ≈ 1/(β μ_r) − w/(β² μ_r²),                   (T-23)
//   μ_r = ω_r² − s,  β = 1 + i kΩ b,  w = s β − (kΩ)² + i kΩ (a − ξ),
// exact to O(w²/μ_r²), s a shift (s < 0 for a free-free structure). So the residual modes enter
// through two 3P × 3P matrices, Ω-independent:
//   R0 = Σ_r Gφ_r φ_rᵀGᵀ / μ_r,   R1 = Σ_r Gφ_r φ_rᵀGᵀ / μ_r²,                          (T-24)
// and the interface gaps are
//   δg_k = Σ_{j kept} Gφ_j η_jk + Σ_r Gφ_r h_r,k φ_rᵀ (f_k − Gᵀ A N_k).                     (T-25)
// The same expansion gives the load's and the output DOFs' residual parts.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/hb/contact_point_aft.hpp"

namespace jointhb::hb {

/// The contact points of one interface (points [first, first + count) of the model).
struct InterfaceGroup {
  std::string name;
  contact::ContactPoint law;
  int first = 0;
  int count = 0;
};

/// A DOF (or any linear functional of u) reported by the analyses: u_o = cᵀ u.
struct InterfaceOutput {
  std::string name;               ///< e.g. "node 123 z"
  Eigen::VectorXd modal;          ///< cᵀ φ_j, kept modes (n_s)
  Eigen::VectorXd residual0;      ///< Σ_r (cᵀφ_r) Gφ_r / μ_r   (3P)
  Eigen::VectorXd residual1;      ///< Σ_r (cᵀφ_r) Gφ_r / μ_r²  (3P)
  double load_residual0 = 0.0;    ///< Σ_r (cᵀφ_r)(φ_rᵀ f) / μ_r
  double load_residual1 = 0.0;    ///< Σ_r (cᵀφ_r)(φ_rᵀ f) / μ_r²
};

struct InterfaceModel {
  // --- kept modes of (K_t, M), ascending; the first `rigid_modes` are rigid-body modes ----------
  Eigen::VectorXd omega2;          ///< ω_j² [rad²/s²] (n_s); rigid-body modes: set to exactly 0
  int rigid_modes = 0;             ///< leading kept modes that are rigid-body modes (G φ = 0)
  Eigen::MatrixXd gap_shapes;      ///< Gφ_j, 3P × n_s [m per unit η]
  double rayleigh_mass = 0.0;      ///< a [1/s]:  C = a M + b K_t
  double rayleigh_stiffness = 0.0; ///< b [s]
  // --- residual (not kept) modes, eq. (T-24) ----------------------------------------------------
  double residual_shift = 0.0;           ///< s [rad²/s²]
  Eigen::MatrixXd residual_flexibility;  ///< R0 (3P × 3P, symmetric) [m/N]
  Eigen::MatrixXd residual_inertia;      ///< R1 (3P × 3P, symmetric) [m s²/N]
  // --- contact points ----------------------------------------------------------------------------
  std::vector<InterfaceGroup> groups;            ///< cover points 0..P−1 in order
  std::vector<ContactPointReference> references; ///< preloaded (g_pre, t_pre), P
  Eigen::VectorXd areas;                         ///< A_p [m²], P
  std::vector<Eigen::Matrix3d> stuck_tangents;   ///< C_pre per point (the tangent inside K_t)
  // --- one load shape f (the excitation scales it) and the reported outputs ------------------------
  std::string load_name;
  Eigen::VectorXd load_modal;      ///< φ_jᵀ f (n_s)
  Eigen::VectorXd load_residual0;  ///< Σ_r Gφ_r (φ_rᵀ f) / μ_r  (3P)
  Eigen::VectorXd load_residual1;  ///< Σ_r Gφ_r (φ_rᵀ f) / μ_r² (3P)
  std::vector<InterfaceOutput> outputs;

  [[nodiscard]] int num_modes() const { return static_cast<int>(omega2.size()); }
  [[nodiscard]] int num_points() const { return static_cast<int>(areas.size()); }
  /// Empty when consistent (sizes, finite values, groups covering the points, areas > 0,
  /// ω² ≥ 0, rigid modes first); otherwise what is wrong.
  [[nodiscard]] std::string validate() const;
};

}  // namespace jointhb::hb
