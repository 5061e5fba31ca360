// Static loads in the preload (fe/static_load.hpp, eq. (P-1) of preload/preload_solver.hpp): a
// block on symmetry supports under a uniform pressure is in uniaxial stress, which trilinear and
// serendipity elements reproduce exactly — u_z = −p z / E, u_x = ν p x / E, u_y = ν p y / E.
#include <gtest/gtest.h>

#include <cmath>

#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/preload/preload_solver.hpp"

namespace fe = jointhb::fe;
namespace pl = jointhb::preload;

namespace {

struct Block {
  fe::Mesh mesh;
  pl::PreloadModel model;
};

// 40 × 30 × 20 mm steel block with its xmin, ymin and zmin sides on symmetry supports.
void build(Block& b, fe::ElementType type) {
  fe::BoxOptions o;
  o.part = "block";
  o.size = {0.04, 0.03, 0.02};
  o.divisions = {4, 3, 2};
  o.type = type;
  b.mesh = fe::box_mesh(o);
  b.model.mesh = &b.mesh;
  b.model.structure = fe::assemble(b.mesh, {fe::Material{"steel", 210e9, 0.3, 7850.0}});
  for (const auto& [side, axis] : {std::pair{"block.xmin", 0}, {"block.ymin", 1}, {"block.zmin", 2}}) {
    fe::FixedNodes f;
    f.nodes = b.mesh.node_sets.at(side);
    f.directions = {axis == 0, axis == 1, axis == 2};
    b.model.constraints.push_back(f);
  }
}

TEST(PreloadStaticLoads, UniformPressureGivesTheUniaxialStressState) {
  for (fe::ElementType type : {fe::ElementType::hex8, fe::ElementType::hex8_incompatible, fe::ElementType::hex20}) {
    Block b;
    build(b, type);
    const double p = 5e7, E = 210e9, nu = 0.3;
    b.model.loads.pressures.push_back({"top", b.mesh.surfaces.at("block.zmax"), p});
    pl::PreloadOptions options;
    options.load_steps = 1;
    const pl::PreloadResult r = pl::solve_preload(b.model, options);
    ASSERT_TRUE(r.status().ok()) << r.status().brief();
    double worst = 0.0;
    for (int i = 0; i < b.mesh.num_nodes(); ++i) {
      const Eigen::Vector3d x = b.mesh.coordinates.col(i);
      const Eigen::Vector3d exact(nu * p * x.x() / E, nu * p * x.y() / E, -p * x.z() / E);
      worst = std::max(worst, (r.displacement.segment<3>(3 * i) - exact).norm());
    }
    EXPECT_LT(worst, 1e-10 * p * 0.02 / E) << fe::abaqus_name(type);
  }
}

TEST(PreloadStaticLoads, NodalForcesAddUpWithThePressure) {
  // The same resultant as nodal forces on the top corner nodes of a single hex8 element block:
  // the consistent loads of a uniform pressure on a one-element face are pA/4 per corner.
  Block a, b;
  build(a, fe::ElementType::hex8);
  build(b, fe::ElementType::hex8);
  const double p = 2e7;
  a.model.loads.pressures.push_back({"top", a.mesh.surfaces.at("block.zmax"), p});
  // Per top node: the sum of the pA_e/4 shares of its elements (A_e = 0.01 × 0.01 m²).
  const double share = p * 0.01 * 0.01 / 4.0;
  for (int node : b.mesh.node_sets.at("block.zmax")) {
    const Eigen::Vector3d x = b.mesh.coordinates.col(node);
    const int nx = (x.x() < 1e-12 || x.x() > 0.04 - 1e-12) ? 1 : 2;
    const int ny = (x.y() < 1e-12 || x.y() > 0.03 - 1e-12) ? 1 : 2;
    b.model.loads.forces.push_back({"corner", {node}, Eigen::Vector3d(0.0, 0.0, -share * nx * ny)});
  }
  pl::PreloadOptions options;
  options.load_steps = 2;
  const pl::PreloadResult ra = pl::solve_preload(a.model, options);
  const pl::PreloadResult rb = pl::solve_preload(b.model, options);
  ASSERT_TRUE(ra.status().ok() && rb.status().ok());
  EXPECT_LT((ra.displacement - rb.displacement).cwiseAbs().maxCoeff(), 1e-12 * ra.displacement.cwiseAbs().maxCoeff());
}

TEST(PreloadStaticLoads, AFreeFreeModelRefusesUnbalancedLoads) {
  Block b;
  build(b, fe::ElementType::hex8);
  b.model.constraints.clear();
  b.model.loads.pressures.push_back({"top", b.mesh.surfaces.at("block.zmax"), 1e6});
  try {
    (void)pl::solve_preload(b.model, {});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("resultant force of 1200 N"), std::string::npos) << e.what();
  }
  // Equal and opposite pressures on two opposite sides are self-equilibrated: accepted.
  b.model.loads.pressures.push_back({"bottom", b.mesh.surfaces.at("block.zmin"), 1e6});
  const pl::PreloadResult r = pl::solve_preload(b.model, {});
  EXPECT_TRUE(r.status().ok()) << r.status().brief();
  EXPECT_LT(r.support_reaction, 1e-9);
}

}  // namespace
