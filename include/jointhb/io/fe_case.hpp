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
//          preload: 10e3}                  # head/nut: optional inner_radius (a washer's annulus)
//     constraints: [{node_set: lower.xmin, fix: [x, y, z]}]
//     ties: [{name: glue, slave: upper.zmin, master: lower.zmax, penalty_factor: 1e3}]
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
#include "jointhb/study/study.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/pipeline/fe_analysis.hpp"
#include "jointhb/pipeline/fe_model.hpp"
#include "jointhb/preload/preload_solver.hpp"

namespace jointhb::io {

/// An interface as read: what the case file says (echoed in summary.json) and what was built.
struct FeInterfaceSpec {
  std::string name, bottom, top, integration, law;
  std::string meshes;  ///< "matching", "non-matching" or "automatic" (as written in the case)
  double pressure = 0.0, decay = 0.0, mu = 0.0, exponent = 0.0, stiffness_ratio = 0.0,
         tangential_stiffness = 0.0;
  double cutoff_gap = 0.0;        ///< g_c of the exponential law (0: none)
  double normal_stiffness = 0.0;  ///< k_N of the linear normal law (0: exponential law)
  bool frictionless = false;      ///< law: frictionless (μ = 0; `law` holds "jenkins")
  int faces = 0;  ///< zero-thickness elements built
};

/// A case as read: the model and the analyses (the pipeline's typed inputs, pipeline/fe_model.hpp
/// and fe_analysis.hpp) plus what only the reader knows.
struct FeCase : pipeline::FeModel, pipeline::FeAnalysis {
  std::vector<FeInterfaceSpec> interface_specs;  ///< same order as interfaces
  std::vector<std::string> constraint_sets;      ///< node set names of the constraints (echo)
  std::vector<std::string> tie_sources;          ///< per tie: "model.ties[i]" or the deck's "FILE:LINE"
  /// fit: the identification (jointhb fit; the parameters are the pipeline's). Not part of any
  /// stage key.
  std::optional<FitSection> fit;
  /// study: a parameter study of this case (`jointhb study`, docs/studies.md). Not part of any
  /// stage key.
  std::optional<study::StudySpec> study;
  std::vector<std::string> warnings;             ///< e.g. mesh cards that were skipped
  std::string source;
};

/// Reads an FE case. Throws InputError "FILE:LINE:COL: key 'a.b': constraint" for every problem
/// of the case file, including those found while building the model (an unknown surface, meshes
/// that do not match, a bolt footprint with no face, an inverted element); errors inside an
/// imported mesh file name that file and its line.
FeCase read_fe_case(const std::filesystem::path& file);
FeCase parse_fe_case(const std::string& text, const std::string& file_name);

/// The preload model of a case (pipeline/fe_model.hpp): its mesh by pointer, `c` must outlive it.
using pipeline::preload_model;

}  // namespace jointhb::io
