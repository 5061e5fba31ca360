#pragma once
// Interface reduction by contact patches: the contact points of an hb::InterfaceModel merged into
// square patches of the interface plane, each patch one contact point of the reduced model
// (docs/theory.md §11, eq. T-31). The dense harmonic-balance system has 3 P m unknowns of the gaps
// (m Fourier coefficients), and its LU costs O((3 P m)³): merging k points per patch divides that
// by k³ while the structure, the preloaded state and the linear (stuck) model stay exact.
//
// With W (3P_c × 3P) the load-weighted mean over a patch, W(3c+d, 3p+d) = ω_p = A_p p_p / Σ A p
// (the preloaded pressure p_p; area weights where a patch carries no pressure), the patch's gap is
// g_c = W g and its traction is shared in proportion to the pressure, A N = Wᵀ A_c N_c (the same
// virtual work; A_c = Σ A_p). Area weights were tried first: a patch that holds an opening edge
// point and a pressed neighbour then "opens" under the mean of their normal motions, and on the
// lap 5 mm patches softened ten times too early; with load weights the points that carry no
// load do not move the patch. Every linear term of the model follows:
//   gap_shapes_c = W Gφ,   R0_c = W R0 Wᵀ,   R1_c = W R1 Wᵀ,   load_residual_c = W load_residual,
//   output residual_c = W residual,   areas_c = A_c,                                        (T-31)
// and the patch's reference state is the area mean of its points' preloaded tractions (so the
// patch carries the same static force) with the normal gap at which the law gives that mean
// pressure, p_N(g_ref,c) = p̄_c, and the tangential gap averaged with W. Its stuck tangent C_c is
// the law's at that reference. The linear part of the balance keeps the fine K_t (the modes and
// residual flexibilities are not recomputed), so at small amplitude the reduced model is the fine
// one exactly (N_c = ΔT_c − C_c δg_c → 0); what is approximated is the nonlinear deviation, which
// a patch evaluates once at its mean gap and mean pressure instead of at each point: slip that
// starts at the low-pressure rim of a patch is smeared over it. The error is measured against the
// node pairs (validation/fe/lap_damping, tests/unit/reduction/contact_patches_test.cpp).
//
// Patches: per interface (group), the square cells of edge `size` in the (t1, t2) coordinates of
// the points' local frames, from the interface's smallest coordinates. Points of one patch must
// share their frame (flat interfaces): a patch that mixes frames is an error (curved interfaces
// need a smaller size or none). Size 0 merges coincident points only: exact, and what the
// pipeline does by default (the 192 nodal points of the coarse lap are 63 node pairs).

#include <string>
#include <vector>

#include "jointhb/hb/interface_model.hpp"
#include "jointhb/preload/preload_solver.hpp"

namespace jointhb::reduction {

struct ContactPatchOptions {
  /// [m] ≥ 0: edge of the square patches; 0: merge only coincident points with the same frame,
  /// which is exact (nodal integration puts one point of every element at each of its nodes:
  /// coincident points have identical gap-operator rows, so identical gaps and tractions).
  double size = 0.0;
  [[nodiscard]] std::string validate() const;
};

struct ContactPatchResult {
  hb::InterfaceModel model;          ///< the reduced model (P_c points)
  std::vector<int> patch_of_point;   ///< fine point → patch (size P)
  std::vector<double> point_weights; ///< ω_p of eq. (T-31) (size P; each patch's sum to 1)
  int fine_points = 0, patches = 0;
  double seconds = 0.0;
};

/// Merges the contact points of `model` (built from `fe` by build_modal_interface: same
/// interfaces, same point order) into patches. Throws std::invalid_argument on invalid options, a
/// model that does not match `fe`, or a patch whose points have different frames.
[[nodiscard]] ContactPatchResult merge_contact_patches(const hb::InterfaceModel& model,
                                                       const preload::PreloadModel& fe,
                                                       const ContactPatchOptions& options);

}  // namespace jointhb::reduction
