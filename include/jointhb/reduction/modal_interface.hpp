#pragma once
// The preloaded structure seen from its contact points in modal coordinates: builds the
// hb::InterfaceModel of hb/interface_model.hpp (docs/theory.md §11, eq. T-22 to T-25).
//
// Matrices (free DOFs: the user constraints only; a free-free assembly keeps ALL DOFs, the 3-2-1
// support of the preload solve carries no load and is not a support of the dynamics):
//   K_t = K_s + Σ_b k_b b bᵀ + Σ_I G_Iᵀ A_I C_pre,I G_I   (preload::dynamic_stiffness),  M.
// Modes K_t φ = ω² M φ, φᵀMφ = 1 (ARPACK shift-invert, modal/modes.hpp), computed with a count
// that doubles until the last one lies above cutoff_hz; the n_s modes with f ≤ cutoff_hz are kept.
// Kept modes below rigid_tolerance_hz are rigid-body modes (a free-free assembly has 6): their ω²
// is set to exactly 0 and they lead the list.
//
// Residual (not kept) modes r respond quasi-statically with a first-order dynamic correction,
//   h_r = 1/(ω_r² − Ω² + iΩ(a + bω_r²)) = 1/(βμ_r + w) ≈ 1/(βμ_r) − w/(β²μ_r²),            (T-23)
//   μ_r = ω_r² − s,  β = 1 + iΩb,  w = sβ − Ω² + iΩa,
// so they enter through   R0 = Σ_r Gφ_rφ_rᵀGᵀ/μ_r,   R1 = Σ_r Gφ_rφ_rᵀGᵀ/μ_r²             (T-24)
// (G: every interface's gap operator stacked, 3P rows). The sums over the residual modes are
// never formed mode by mode: with S = K_t − sM (SPD for s below the lowest eigenvalue; s < 0 for
// a free-free structure; s = options.modal.shift) factored once by CHOLMOD,
//   S⁻¹ = Σ_all φφᵀ/μ,   so   Z = S⁻¹Gᵀ  (one blocked solve, 3P right-hand sides),
// and deflating the kept modes (M-orthogonal projection, applied twice for round-off),
//   Z_res = Z − Φ(ΦᵀMZ) = Σ_r φ_r φ_rᵀGᵀ/μ_r,
//   R0 = G Z_res,   R1 = Z_resᵀ M Z_res        (both symmetrised).
// The load f and every output functional c (u_o = cᵀu) go through the same deflated solve:
//   z_f, z_c:   load_residual0 = G z_f,  load_residual1 = Z_resᵀM z_f,
//               output residual0 = G z_c,  residual1 = Z_resᵀM z_c,
//               output load_residual0 = cᵀz_f,  load_residual1 = z_cᵀM z_f,
// and load_modal = Φᵀf, output modal = Φᵀc, gap_shapes = GΦ. The deflation needs no μ_j of the
// kept modes, so zeroing the rigid-body ω² afterwards changes nothing in the residual terms.
// Accuracy: the neglected term of (T-23) is w²/(β³μ_r³): the error of a receptance below the
// cutoff falls roughly like (Ω²/μ_cutoff)² relative to the residual part (tested).
// Cost: modes + one factorisation of S + (3P_d + 1 + outputs) solves + O(n (3P_d)²) for R1 (BLAS),
// P_d the distinct points (G's identical rows, the node pairs of nodal integration, are solved
// once: a third to a quarter of P); memory: two dense n × 3P_d blocks.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "jointhb/hb/interface_model.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/field_recovery.hpp"

namespace jointhb::reduction {

struct ModalInterfaceOptions {
  /// Keep the modes of K_t with f ≤ cutoff_hz (> 0). The count grows by doubling from
  /// initial_count (as craig_bampton does) until the last computed mode lies above the cutoff or
  /// max_modes modes are computed (then truncated_by_max_modes is set).
  double cutoff_hz = 0.0;
  int initial_count = 20;  ///< ≥ 1
  int max_modes = 400;     ///< ≥ 1
  /// [Hz] ≥ 0: kept modes with |f| below this are rigid-body modes (ω² set to exactly 0, counted
  /// in rigid_modes; they must be the leading modes).
  double rigid_tolerance_hz = 1.0;
  double rayleigh_mass = 0.0;       ///< a ≥ 0 [1/s], copied into the model
  double rayleigh_stiffness = 0.0;  ///< b ≥ 0 [s], copied into the model
  /// ARPACK settings (count is set by the doubling; a fixed ncv ≤ count is raised to
  /// 2·count + 1). Its shift is also the residual shift s: K_t − sM must be positive definite
  /// (s < 0 for a free-free structure).
  modal::ModalOptions modal{};
  /// Keep Φ and the deflated solves Z, z_f for full-field output (ModalInterfaceResult::recovery,
  /// reduction/field_recovery.hpp, eq. T-33). Memory: n × (n_s + 3P_d + 1) doubles.
  bool keep_field_recovery = false;

  /// Empty when valid, else "field: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

/// The excitation shape f (full mesh DOFs, 3N; entries at constrained DOFs are ignored).
struct ModalLoad {
  std::string name;
  Eigen::VectorXd force;
};

/// A reported output u_o = cᵀu, c over the full mesh DOFs (3N), e.g. a unit vector at one DOF.
struct ModalOutputSpec {
  std::string name;
  Eigen::VectorXd functional;
};

struct ModalInterfaceResult {
  hb::InterfaceModel model;
  modal::ModalResult modes;  ///< every computed mode (frequencies, residuals) for reporting
  int kept_modes = 0;
  bool truncated_by_max_modes = false;  ///< max_modes reached before a mode above the cutoff
  /// Distinct rows of G solved for (3 per node pair with nodal integration: the points of one node
  /// pair have identical rows, and their residual terms are copies).
  int distinct_gap_rows = 0;
  /// Full-field recovery (T-33), when options.keep_field_recovery; empty otherwise.
  FieldRecovery recovery;
  double modes_seconds = 0, factor_seconds = 0, residual_seconds = 0, seconds = 0;

  /// One line: kept modes (rigid), frequency range, points, timings.
  [[nodiscard]] std::string brief() const;
};

/// Builds the model above from the preloaded state. Throws std::invalid_argument on invalid
/// options, a model without mesh or interfaces, a preload that did not converge or does not match
/// the model, or load/output vectors of the wrong size (the message names the field);
/// std::runtime_error when the modes fail, K_t − sM is not positive definite, or a kept mode has
/// a negative eigenvalue beyond the rigid-body tolerance.
[[nodiscard]] ModalInterfaceResult build_modal_interface(const preload::PreloadModel& model,
                                                         const preload::PreloadResult& preload,
                                                         const ModalLoad& load,
                                                         const std::vector<ModalOutputSpec>& outputs,
                                                         const ModalInterfaceOptions& options);

}  // namespace jointhb::reduction
