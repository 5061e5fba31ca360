#pragma once
// A finite-element model of a bolted assembly as typed values, and the keys of the stages built
// on it (docs/pipeline.md). The case reader (io/fe_case.hpp) fills one from a case file; code and
// Python build one from a mesh and values.

#include <string>
#include <vector>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/material.hpp"
#include "jointhb/fe/mesh.hpp"
#include "jointhb/fe/static_load.hpp"
#include "jointhb/fe/tie.hpp"
#include "jointhb/pipeline/fe_analysis.hpp"
#include "jointhb/preload/bolt.hpp"
#include "jointhb/preload/preload_solver.hpp"

namespace jointhb::pipeline {

struct FeModel {
  fe::Mesh mesh;
  std::vector<fe::Material> material_per_part;        ///< Mesh::parts order
  std::vector<preload::ContactInterface> interfaces;  ///< zero-thickness interfaces with their law
  std::vector<preload::Bolt> bolts;
  std::vector<fe::FixedNodes> constraints;            ///< empty: free-free (the preload adds 3-2-1)
  fe::StaticLoads loads;  ///< nodal forces and pressures of the preload, besides the bolts
  std::vector<fe::Tie> ties;  ///< bonded surfaces: K_tie joins the structure's stiffness (fe/tie.hpp)
};

/// Part of every stage key: bump when a stage computes something different for the same typed
/// inputs, so that results stored by an older build miss.
inline constexpr int fe_stage_version = 2;

/// Keys of the stages (32 hex digits each, pipeline/fingerprint.hpp), hashed from typed values:
///   model   = fe_stage_version + the program version + the mesh (coordinates; per element its
///             type, part and nodes) + the materials + per interface its points (position, frame,
///             area), node pairs, gap operator and contact law (every option, the law's name and
///             exponent) + per bolt everything but its name (the footprints' inner radii
///             only when one is > 0, eq. B-4) + the constraints + the static
///             load vector (only when there are static loads) + per tie its gap operator, point
///             areas and penalty (only when there are ties: other models keep their keys);
///   preload = model + the preload options that can change the result (not `progress`);
///   modes   = preload + the modal options.
/// Names, node/element sets and surfaces do not enter (they change no result); a damping or a
/// dynamics setting enters none of them.
struct FeStageKeys {
  std::string model, preload, modes;
};
[[nodiscard]] FeStageKeys fe_stage_keys(const FeModel& model, const FeAnalysis& analysis);

/// The preload model: the mesh (by pointer: `model` must outlive it), the assembled structure
/// (fe::assemble) with the ties' stiffness added to K_s (so that the preload, the modes, the
/// condensation and the time integration all see it), interfaces, bolts, constraints and ties.
[[nodiscard]] preload::PreloadModel preload_model(const FeModel& model);

/// The exponent n of a Gaul–Mayer law, 0 for a law without one (Jenkins).
[[nodiscard]] double law_exponent(const contact::ContactPoint& law);

}  // namespace jointhb::pipeline
