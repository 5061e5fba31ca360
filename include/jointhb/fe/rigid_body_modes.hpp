#pragma once
// The six rigid-body motions of a 3D solid, the near-null space of its stiffness matrix: what an
// algebraic multigrid preconditioner (PETSc's GAMG, fe/petsc_solvers.hpp) must reproduce on its
// coarse grids to converge on elasticity in a number of iterations independent of the mesh size
// (Vaněk, Mandel, Brezina, Computing 56 (1996) 179-196, §4: the smoothed-aggregation tentative
// prolongator is built from these vectors).
//
// Translations t_d = e_d at every node, rotations r_a = e_a × (x − c) about the centroid c, with
// x − c scaled by the mesh's size so that all six have comparable norms. Restricted to the free
// DOFs of `dofs` (a clamped node drops its rows), they stay what GAMG needs: low energy away from
// the constraints. One set for the whole mesh, also for an assembly of parts on soft interfaces:
// GAMG's aggregates do not cross the weak interface couplings, and on each aggregate these six span
// the same space as the part's own rigid motions would. (Six separate vectors per part, zero outside
// it, make GAMG's tentative prolongator rank-deficient on every aggregate, and its coarse problem
// singular: tried on case 07, "DIVERGED_INDEFINITE_PC".)

#include <Eigen/Core>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/mesh.hpp"
#include "jointhb/fe/sparse_cholesky.hpp"

namespace jointhb::fe {

/// 3·num_nodes × 6 (DOF 3i+d, Mesh's numbering): three translations then three rotations.
[[nodiscard]] Eigen::MatrixXd rigid_body_modes(const Mesh& mesh);

/// The same restricted to the free DOFs of `dofs` (dofs.num_free() × 6).
[[nodiscard]] Eigen::MatrixXd rigid_body_modes(const Mesh& mesh, const DofMap& dofs);

/// `settings` with its near-null space set to the rigid-body modes on `dofs` when `backend` is the
/// cg one and none is set (what every FE stage that solves with K does before it builds its solver).
[[nodiscard]] IterativeSettings with_rigid_body_modes(IterativeSettings settings, LinearSolver backend,
                                                      const Mesh& mesh, const DofMap& dofs);

}  // namespace jointhb::fe
