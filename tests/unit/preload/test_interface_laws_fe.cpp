// The linear penalty and frictionless interface laws in a finite-element model: two stacked
// blocks, the lower one clamped, pressed together by a pressure on the upper one. With a stiff
// linear interface in stick the modes tend to those of the one-piece block (the interface becomes
// a rigid tie as k → ∞, the error falls like 1/k); with a frictionless one the upper block has
// exactly three free mechanisms (two slides and the turn about the normal): three zero modes.
#include <gtest/gtest.h>

#include <cmath>

#include "jointhb/contact/harmonic_loop.hpp"
#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"

namespace jointhb::pipeline {
namespace {

constexpr double kE = 70e9, kH = 0.01;  // aluminium; each block 20 × 20 × 10 mm

fe::Material aluminium() { return {"aluminium", kE, 0.33, 2700.0}; }

FeAnalysis modes_analysis(int count) {
  FeAnalysis a;
  a.preload.load_steps = 2;
  a.preload_requested = true;
  modal::ModalOptions m;
  m.count = count;
  m.shift = -std::pow(2.0 * M_PI * 1.0, 2);
  a.modes = m;
  return a;
}

// The stacked blocks with the interface law `normal` and friction μ (0: frictionless).
FeModel stacked(const contact::NormalLaw& normal, double mu, double kt) {
  FeModel model;
  fe::BoxOptions lower;
  lower.part = "lower";
  lower.size = {0.02, 0.02, kH};
  lower.divisions = {4, 4, 2};
  fe::BoxOptions upper = lower;
  upper.part = "upper";
  upper.origin = {0.0, 0.0, kH};
  model.mesh = fe::box_mesh(lower);
  fe::append(model.mesh, fe::box_mesh(upper));
  model.material_per_part = {aluminium(), aluminium()};
  fe::InterfaceOptions io;
  io.name = "joint";
  io.bottom_surface = "lower.zmax";
  io.top_surface = "upper.zmin";
  contact::ContactPointOptions o;
  o.normal = normal;
  o.friction_coefficient = mu;
  o.stiffness_model = contact::TangentialStiffnessModel::constant;
  o.tangential_stiffness = kt;
  model.interfaces.push_back({fe::build_interface(model.mesh, io),
                              contact::ContactPoint(o, contact::make_tangential_law("jenkins", 0.0))});
  fe::FixedNodes clamp;
  clamp.nodes = model.mesh.node_sets.at("lower.zmin");
  model.constraints.push_back(clamp);
  model.loads.pressures.push_back({"press", model.mesh.surfaces.at("upper.zmax"), 1e6});
  return model;
}

contact::NormalLaw linear(double stiffness) {
  contact::NormalLaw law;
  law.kind = contact::NormalLawKind::linear;
  law.penalty_stiffness = stiffness;
  return law;
}

TEST(InterfaceLawsFe, StiffLinearInterfaceInStickTendsToTheOnePieceBlock) {
  FeModel one;
  fe::BoxOptions block;
  block.part = "block";
  block.size = {0.02, 0.02, 2.0 * kH};
  block.divisions = {4, 4, 4};
  one.mesh = fe::box_mesh(block);
  one.material_per_part = {aluminium()};
  fe::FixedNodes clamp;
  clamp.nodes = one.mesh.node_sets.at("block.zmin");
  one.constraints.push_back(clamp);
  FePipeline reference(one, modes_analysis(6));
  const Eigen::VectorXd f_ref = reference.modes().frequencies_hz;

  std::vector<double> errors;
  for (double factor : {1e2, 1e3}) {
    const double k = factor * kE / kH;  // [Pa/m]: the interface far stiffer than a block
    FePipeline p(stacked(linear(k), 10.0, k), modes_analysis(6));  // μ = 10: no slip anywhere
    ASSERT_TRUE(p.preload().status().ok()) << p.preload().status().brief();
    const Eigen::VectorXd f = p.modes().frequencies_hz;
    // The first five (a degenerate pair at the sixth: Lanczos may find either member first).
    errors.push_back(((f - f_ref).head(5).array() / f_ref.head(5).array()).abs().maxCoeff());
  }
  EXPECT_LT(errors[1], 3e-4) << errors[0] << " " << errors[1];
  EXPECT_NEAR(errors[0] / errors[1], 10.0, 2.0) << errors[0] << " " << errors[1];  // ~ 1/k
}

TEST(InterfaceLawsFe, FrictionlessInterfaceLeavesThreeMechanisms) {
  for (const contact::NormalLaw& normal : {linear(1e2 * kE / kH), contact::NormalLaw{1e6, 2e5, 0.0}}) {
    FeModel model = stacked(normal, 0.0, 1.0);
    if (normal.kind == contact::NormalLawKind::exponential) model.loads.pressures[0].pressure = 2e6;  // p > p_N0: closes
    FePipeline p(model, modes_analysis(6));
    ASSERT_TRUE(p.preload().status().ok()) << p.preload().status().brief();
    const Eigen::VectorXd f = p.modes().frequencies_hz;
    EXPECT_LT(f.head(3).cwiseAbs().maxCoeff(), 1e-3 * f[3]) << f.transpose();
    EXPECT_GT(f[3], 100.0) << f.transpose();
  }
}

}  // namespace
}  // namespace jointhb::pipeline
