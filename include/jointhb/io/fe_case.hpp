#pragma once
// The finite-element case: parts (generated boxes or imported .inp / .msh meshes) with
// materials, zero-thickness interfaces between matching surfaces with their contact law, bolts,
// constraints, and the analyses (preloaded static state, modes about it). Schema: docs/case-files.md
// §"Finite-element cases".
//
//   model:
//     type: fe
//     materials: {aluminium: {youngs_modulus: 70e9, poissons_ratio: 0.33, density: 2700}}
//     parts:
//       - {name: lower, material: aluminium, element: C3D8I,
//          box: {origin: [0, 0, 0], size: [0.12, 0.04, 0.005], divisions: [24, 8, 2]}}
//       - {mesh: plates.inp, materials: {PLATE: aluminium}}      # parts = the mesh's parts
//     interfaces:
//       - {name: lap, bottom: lower.zmax, top: upper.zmin, region: {min: [...], max: [...]},
//          integration: nodal, contact: {pressure: 1e6, decay: 2e5, mu: 0.3, law: gaul-mayer,
//          n: 0.333, stiffness_ratio: 0.8}}
//     bolts:
//       - {name: b1, point: [x, y, z], direction: [0, 0, 1], head: {surface: upper.zmax,
//          radius: 0.005}, nut: {surface: lower.zmin, radius: 0.005}, stiffness: 3e8,
//          preload: 10e3}
//     constraints: [{node_set: lower.xmin, fix: [x, y, z]}]
//   analysis:
//     preload: {load_steps: 4, tolerance: 1e-9}
//     modes: {count: 10, shift_hz: -1}
//     nonlinear_modes / frf with damping, reduction, excitation, outputs: fe_dynamics_case.hpp

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/fe/material.hpp"
#include "jointhb/fe/mesh.hpp"
#include "jointhb/io/fe_dynamics_case.hpp"
#include "jointhb/io/fit_section.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/preload/preload_solver.hpp"

namespace jointhb::io {

/// An interface as read: what the case file says (echoed in summary.json) and what was built.
struct FeInterfaceSpec {
  std::string name, bottom, top, integration, law;
  double pressure = 0.0, decay = 0.0, mu = 0.0, exponent = 0.0, stiffness_ratio = 0.0,
         tangential_stiffness = 0.0;
  int faces = 0;  ///< zero-thickness elements built
};

struct FeCase {
  fe::Mesh mesh;
  std::vector<fe::Material> material_per_part;   ///< Mesh::parts order
  std::vector<preload::ContactInterface> interfaces;
  std::vector<FeInterfaceSpec> interface_specs;  ///< same order
  std::vector<preload::Bolt> bolts;
  std::vector<fe::FixedNodes> constraints;
  std::vector<std::string> constraint_sets;      ///< node set names of the constraints (echo)
  preload::PreloadOptions preload;               ///< analysis.preload (defaults when absent)
  bool preload_requested = false;                ///< analysis.preload present (or implied by modes)
  std::optional<modal::ModalOptions> modes;      ///< analysis.modes
  /// analysis.nonlinear_modes / frf with their settings (fe_dynamics_case.hpp); they need the
  /// preload and the modes, which then run with defaults when not given.
  std::optional<FeDynamicsSpec> dynamics;
  /// fit: the identification (jointhb fit; io/fe_fit_parameters.hpp names the parameters). Not
  /// part of any stage key.
  std::optional<FitSection> fit;
  std::vector<std::string> warnings;             ///< e.g. mesh cards that were skipped
  std::string source;
  /// Keys of the stage cache (io/stage_cache.hpp), 32 hex digits each, computed by the reader:
  ///   model   = the `model:` node (its YAML tree: keys, values, order; not comments, quoting or
  ///             flow/block style) + the bytes of every imported mesh file + fe_fingerprint_version
  ///             + the program version;
  ///   preload = model + the `analysis.preload` node (or "defaults" when absent);
  ///   modes   = preload + the `analysis.modes` node (or "absent").
  /// Other analysis keys (the dynamic stages) do not enter them.
  struct Fingerprints {
    std::string model, preload, modes;
  } fingerprints;
};

/// Part of every FE stage key: bump when the reader or a solver computes something different for
/// the same case file (so that results cached by an older build are not reused).
inline constexpr int fe_fingerprint_version = 1;

/// Reads an FE case. Throws InputError "FILE:LINE:COL: key 'a.b': constraint" for every problem
/// of the case file, including those found while building the model (an unknown surface, meshes
/// that do not match, a bolt footprint with no face, an inverted element); errors inside an
/// imported mesh file name that file and its line.
FeCase read_fe_case(const std::filesystem::path& file);
FeCase parse_fe_case(const std::string& text, const std::string& file_name);

/// The preload model of a case: its mesh (by pointer: `c` must outlive the model), the assembled
/// structure (fe::assemble), interfaces, bolts and constraints.
preload::PreloadModel preload_model(const FeCase& c);

}  // namespace jointhb::io
