#pragma once
// The bolted lap joint of cases/05-bolted-lap/case.yaml as case-file text, with the mesh and the
// few settings the finite-element studies vary; shared by lap_preload_sweep, fe_scaling and
// condensed_modes. Embedded rather than read from cases/ so that a study does not follow later
// edits of the shipped case. Parse it with io::parse_fe_case(text, name).

#include <fmt/format.h>

#include <string>

namespace jointhb::validation {

struct LapCaseOptions {
  int nx = 40, ny = 12, nz = 2;       ///< divisions of each plate: 100 mm, 30 mm, 4 mm (case 05)
  double youngs_modulus = 70.0e9;     ///< [Pa]
  double pressure = 1.0e6;            ///< p_N0 [Pa] of eq. (6)
  double footprint_radius = 0.0045;   ///< bolt head and nut [m]
  double preload = 5000.0;            ///< per bolt [N]
  double tolerance = 1.0e-9;          ///< analysis.preload.tolerance
  int modes = 20;                     ///< analysis.modes.count
  double shift_hz = 10.0;             ///< analysis.modes.shift_hz = −shift_hz
};

inline std::string lap_case_yaml(const LapCaseOptions& o = {}) {
  return fmt::format(R"(model:
  type: fe
  materials:
    aluminium: {{youngs_modulus: {E}, poissons_ratio: 0.33, density: 2700.0}}
  parts:
    - name: lower
      material: aluminium
      element: C3D8I
      box: {{origin: [0.0, 0.0, 0.0], size: [0.100, 0.030, 0.004], divisions: [{nx}, {ny}, {nz}]}}
    - name: upper
      material: aluminium
      element: C3D8I
      box: {{origin: [0.060, 0.0, 0.004], size: [0.100, 0.030, 0.004], divisions: [{nx}, {ny}, {nz}]}}
  interfaces:
    - name: lap
      bottom: lower.zmax
      top: upper.zmin
      region: {{min: [0.060, 0.0, 0.0039], max: [0.100, 0.030, 0.0041]}}
      integration: nodal
      contact: {{pressure: {p0}, decay: 1.0e6, mu: 0.3, law: gaul-mayer, n: 0.3333333333333333, stiffness_ratio: 0.8}}
  bolts:
    - {{name: bolt-1, point: [0.070, 0.015, 0.0], direction: [0.0, 0.0, 1.0], head: {{surface: upper.zmax, radius: {r}}}, nut: {{surface: lower.zmin, radius: {r}}}, stiffness: 5.0e8, preload: {P}}}
    - {{name: bolt-2, point: [0.090, 0.015, 0.0], direction: [0.0, 0.0, 1.0], head: {{surface: upper.zmax, radius: {r}}}, nut: {{surface: lower.zmin, radius: {r}}}, stiffness: 5.0e8, preload: {P}}}
analysis:
  preload: {{load_steps: 4, tolerance: {tol}}}
  modes: {{count: {count}, shift_hz: -{shift}}}
)",
                     fmt::arg("E", o.youngs_modulus), fmt::arg("nx", o.nx), fmt::arg("ny", o.ny),
                     fmt::arg("nz", o.nz), fmt::arg("p0", o.pressure), fmt::arg("r", o.footprint_radius),
                     fmt::arg("P", o.preload), fmt::arg("tol", o.tolerance), fmt::arg("count", o.modes),
                     fmt::arg("shift", o.shift_hz));
}

}  // namespace jointhb::validation
