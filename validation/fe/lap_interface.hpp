#pragma once
// The bolted lap of lap_case.hpp (one element through each plate) condensed to its modal/interface
// model as validation/fe/lap_damping does: the structure and preload through the pipeline object
// (as `jointhb run`), kept modes up to 20 f_1, 0.5 % stiffness-proportional damping at f_1, the
// load and the output "drive z" at the free end (0.160, 0.015, 0.008). Shared by interface_scaling
// and interface_stability.

#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "../../src/support/stopwatch.hpp"
#include "jointhb/fe/mesh.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"
#include "jointhb/reduction/modal_interface.hpp"
#include "lap_case.hpp"

namespace jointhb::validation {

struct LapInterface {
  hb::InterfaceModel model;
  double f1 = 0.0, seconds = 0.0;  ///< the first elastic kept mode [Hz]; time to build [s]
  int kept_modes = 0;
};

/// The mesh node nearest to x.
inline int nearest_node(const fe::Mesh& mesh, const Eigen::Vector3d& x) {
  int best = 0;
  for (int i = 1; i < mesh.num_nodes(); ++i)
    if ((mesh.coordinates.col(i) - x).norm() < (mesh.coordinates.col(best) - x).norm()) best = i;
  return best;
}

/// The lap with nx × ny × 1 elements per plate (4 · (0.4 nx) · ny contact points, nodal
/// integration per overlap face corner); footprint_radius [m] of the bolt heads and nuts must reach
/// a face centre (6 mm for 10 mm elements).
inline LapInterface lap_interface(int nx, int ny, double footprint_radius = 0.0045) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  LapInterface out;
  const auto t0 = support::Clock::now();
  LapCaseOptions lo;
  lo.nx = nx;
  lo.ny = ny;
  lo.nz = 1;
  lo.footprint_radius = footprint_radius;
  const io::FeCase c = io::parse_fe_case(lap_case_yaml(lo), "lap.yaml");
  // The condensation below keeps its own cutoff and damping rule (a probe model for f_1).
  pipeline::FePipeline pipe(c, c);
  const preload::PreloadModel& model = pipe.structure();
  const preload::PreloadResult& p = pipe.preload();
  if (!p.status().ok()) throw std::runtime_error("lap_interface: preload: " + p.message);
  const int n = c.mesh.num_dofs();
  const int drive = nearest_node(c.mesh, {0.160, 0.015, 0.008});
  const reduction::ModalLoad load{"end force", Eigen::VectorXd::Unit(n, 3 * drive + 2)};
  const std::vector<reduction::ModalOutputSpec> outputs{{"drive z", Eigen::VectorXd::Unit(n, 3 * drive + 2)}};
  reduction::ModalInterfaceOptions mo;
  mo.modal.shift = -std::pow(two_pi * 10.0, 2);
  mo.cutoff_hz = 3000.0;  // f_1 ≈ 960 Hz on the case's mesh, higher on coarser ones
  const reduction::ModalInterfaceResult probe = reduction::build_modal_interface(model, p, load, outputs, mo);
  if (probe.model.num_modes() <= probe.model.rigid_modes)
    throw std::runtime_error("lap_interface: no elastic mode below the probe's cutoff: " + probe.brief());
  const double f1 = std::sqrt(probe.model.omega2[probe.model.rigid_modes]) / two_pi;
  mo.cutoff_hz = 20.0 * f1;
  mo.rayleigh_stiffness = 2.0 * 0.005 / (two_pi * f1);
  reduction::ModalInterfaceResult mi = reduction::build_modal_interface(model, p, load, outputs, mo);
  out.model = std::move(mi.model);
  out.kept_modes = mi.kept_modes;
  out.f1 = std::sqrt(out.model.omega2[out.model.rigid_modes]) / two_pi;
  out.seconds = support::seconds_since(t0);
  return out;
}

}  // namespace jointhb::validation
