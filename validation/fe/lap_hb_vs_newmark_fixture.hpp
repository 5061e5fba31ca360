#pragma once
// (Header of the lap_hb_vs_newmark study, also used by lap_convergence.)
// The preloaded, free-free bolted lap of lap_case.hpp with its drive point (vertical force at the
// free end of the upper plate, x = 160 mm) and its modal/interface model: the setup shared by
// lap_hb_vs_newmark and lap_convergence (the pattern of lap_damping.cpp).

#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/modal_interface.hpp"
#include "lap_case.hpp"
#include "lap_interface.hpp"  // nearest_node

namespace jointhb::validation {

struct LapFixture {
  io::FeCase c;
  std::unique_ptr<pipeline::FePipeline> pipe;  ///< structure and preload, as `jointhb run` computes them
  preload::PreloadModel model;                 ///< copies of the pipeline's (the mesh is the pipeline's)
  preload::PreloadResult preload;
  int drive_node = 0;
  [[nodiscard]] int drive_dof() const { return 3 * drive_node + 2; }
};

/// nx × ny × nz per plate; footprint_radius [m] must reach the nodes next to the bolt axis
/// (4.5 mm for 5 mm elements, 6 mm for 10 mm elements).
inline std::unique_ptr<LapFixture> make_lap_fixture(int nx, int ny, int nz, double footprint_radius) {
  auto f = std::make_unique<LapFixture>();
  LapCaseOptions lo;
  lo.nx = nx;
  lo.ny = ny;
  lo.nz = nz;
  lo.footprint_radius = footprint_radius;
  f->c = io::parse_fe_case(lap_case_yaml(lo), "lap.yaml");
  f->pipe = std::make_unique<pipeline::FePipeline>(f->c, f->c);
  f->model = f->pipe->structure();
  f->preload = f->pipe->preload();
  f->drive_node = nearest_node(f->c.mesh, {0.160, 0.015, 0.008});
  return f;
}

/// The first elastic frequency f_1 [Hz] of K_t (ARPACK, as build_modal_interface computes it).
inline double first_elastic_hz(const LapFixture& f) {
  const int n = f.c.mesh.num_dofs();
  const reduction::ModalLoad load{"end force", Eigen::VectorXd::Unit(n, f.drive_dof())};
  reduction::ModalInterfaceOptions mo;
  mo.modal.shift = -std::pow(2.0 * std::numbers::pi * 10.0, 2);
  mo.cutoff_hz = 5000.0;  // above f_1 of every mesh used (≈ 960 Hz at 20 × 6 × 1)
  const auto probe = reduction::build_modal_interface(f.model, f.preload, load, {}, mo);
  return std::sqrt(probe.model.omega2[probe.model.rigid_modes]) / (2.0 * std::numbers::pi);
}

/// Modal/interface model with the kept modes up to cutoff_factor × f_1, Rayleigh C = b K_t, the
/// drive-point force as load and the drive-point z displacement as output 0.
inline reduction::ModalInterfaceResult lap_modal_model(const LapFixture& f, double f1_hz,
                                                       double cutoff_factor, double rayleigh_b) {
  const int n = f.c.mesh.num_dofs();
  const reduction::ModalLoad load{"end force", Eigen::VectorXd::Unit(n, f.drive_dof())};
  const std::vector<reduction::ModalOutputSpec> outputs{{"drive z", Eigen::VectorXd::Unit(n, f.drive_dof())}};
  reduction::ModalInterfaceOptions mo;
  mo.modal.shift = -std::pow(2.0 * std::numbers::pi * 10.0, 2);
  mo.cutoff_hz = cutoff_factor * f1_hz;
  mo.rayleigh_stiffness = rayleigh_b;
  return reduction::build_modal_interface(f.model, f.preload, load, outputs, mo);
}

}  // namespace jointhb::validation
