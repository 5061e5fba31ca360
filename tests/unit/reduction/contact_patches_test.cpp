// Interface reduction by contact patches (reduction/contact_patches.hpp) on the preloaded coarse
// lap (192 contact points): coincident points (node pairs) merge exactly; larger patches keep the
// static force of every patch, conserve the virtual work of the contact forces
// (A N_fine = Wᵀ A_c N_c with load weights), and give the fine model's linear limit; patches that
// mix local frames are refused.
#include "jointhb/reduction/contact_patches.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <memory>
#include <numbers>

#include "../../../validation/fe/lap_case.hpp"
#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/reduction/modal_interface.hpp"
#include "unit/test_constants.hpp"

namespace {

using namespace jointhb;
namespace rd = jointhb::reduction;
using test_constants::kTwoPi;

struct PatchLap {
  io::FeCase c;
  preload::PreloadModel model;
  preload::PreloadResult preload;
  hb::InterfaceModel interface;
};

const PatchLap& patch_lap() {
  static const std::unique_ptr<PatchLap> instance = [] {
    auto l = std::make_unique<PatchLap>();
    validation::LapCaseOptions o;
    o.nx = 20, o.ny = 6, o.nz = 1;
    l->c = io::parse_fe_case(validation::lap_case_yaml(o), "lap.yaml");
    l->model.mesh = &l->c.mesh;
    l->model.structure = fe::assemble(l->c.mesh, l->c.material_per_part);
    l->model.interfaces = l->c.interfaces;
    l->model.bolts = l->c.bolts;
    l->model.constraints = l->c.constraints;
    l->preload = preload::solve_preload(l->model, l->c.preload);
    const int n = l->c.mesh.num_dofs();
    rd::ModalInterfaceOptions mo;
    mo.cutoff_hz = 20000.0;
    mo.modal.shift = -std::pow(kTwoPi * 10.0, 2);
    mo.rayleigh_stiffness = 1.6e-6;
    const rd::ModalLoad load{"z", Eigen::VectorXd::Unit(n, n - 1)};
    l->interface = rd::build_modal_interface(l->model, l->preload, load, {{"z", Eigen::VectorXd::Unit(n, n - 1)}}, mo).model;
    return l;
  }();
  return *instance;
}

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

// Nodal integration puts a point of every element at each of its nodes: the 192 points of the lap
// stand on 63 node pairs, and coincident points have the same gap operator row, so the same gap
// and traction. Merging them (patches smaller than the node spacing) is exact: the same damping
// curve with a third of the gap unknowns.
TEST(ContactPatches, CoincidentNodalPointsMergeExactly) {
  const hb::InterfaceModel& fine = patch_lap().interface;
  const rd::ContactPatchResult r = rd::merge_contact_patches(fine, patch_lap().model, {.size = 0.0});
  EXPECT_EQ(rd::merge_contact_patches(fine, patch_lap().model, {.size = 1e-6}).patches, 63);
  EXPECT_EQ(fine.num_points(), 192);
  EXPECT_EQ(r.patches, 63);  // (8 + 1) × (6 + 1) node pairs of the 40 × 30 mm overlap
  for (int p = 0; p < fine.num_points(); ++p) {
    const int c = r.patch_of_point[static_cast<std::size_t>(p)];
    const auto& a = r.model.references[static_cast<std::size_t>(c)];
    const auto& b = fine.references[static_cast<std::size_t>(p)];
    EXPECT_NEAR(a.traction.z(), b.traction.z(), 1e-12 * std::abs(b.traction.z()));
    EXPECT_NEAR(a.gap.z(), b.gap.z(), 1e-15);
    EXPECT_LT(relative(r.model.gap_shapes.middleRows(3 * c, 3), fine.gap_shapes.middleRows(3 * p, 3)), 1e-12);
  }
  continuation::InterfaceBackboneOptions o;
  o.mode.balance.harmonics = 1;
  o.mode.balance.time_samples = 32;
  o.log10_amplitude_start = -7.0;
  o.log10_amplitude_end = -5.0;  // microslip: f falls by ~0.1 %
  const auto a = continuation::trace_interface_backbone(fine, o);
  const auto b = continuation::trace_interface_backbone(r.model, o);
  ASSERT_TRUE(a.completed() && b.completed()) << a.message << " / " << b.message;
  const auto& sa = a.points.back().state;
  const auto& sb = b.points.back().state;
  ASSERT_NEAR(sa.amplitude, sb.amplitude, 1e-12 * sa.amplitude);
  std::printf("q = 1e-5: merged vs fine: frequency %.1e, damping %.1e (f drop %.1e; %d vs %d unknowns; %.1f vs %.1f s)\n",
              std::abs(sb.omega / sa.omega - 1.0), std::abs(sb.damping_ratio / sa.damping_ratio - 1.0),
              1.0 - sa.omega / std::sqrt(fine.omega2[fine.rigid_modes]), static_cast<int>(b.unknowns),
              static_cast<int>(a.unknowns), b.timings.total, a.timings.total);
  EXPECT_LT(std::abs(sb.omega / sa.omega - 1.0), 1e-10);
  EXPECT_LT(std::abs(sb.damping_ratio / sa.damping_ratio - 1.0), 1e-7);
  EXPECT_GT(sa.damping_ratio, 1.02 * a.points.front().state.damping_ratio);  // really nonlinear there
}

TEST(ContactPatches, PatchesKeepTheStaticForceAndTheVirtualWork) {
  const hb::InterfaceModel& fine = patch_lap().interface;
  const rd::ContactPatchResult r = rd::merge_contact_patches(fine, patch_lap().model, {.size = 0.01});
  ASSERT_LT(r.patches, fine.num_points() / 8);  // 40 × 30 mm overlap, 10 mm patches: 4 × 3
  EXPECT_EQ(r.patches, 12);
  EXPECT_NEAR(r.model.areas.sum(), fine.areas.sum(), 1e-15);
  // Static force of the interface: Σ A_c t_c = Σ A_p t_p (normal and tangential).
  Eigen::Vector3d fine_force = Eigen::Vector3d::Zero(), patch_force = Eigen::Vector3d::Zero();
  for (int p = 0; p < fine.num_points(); ++p) fine_force += fine.areas[p] * fine.references[static_cast<std::size_t>(p)].traction;
  for (int c = 0; c < r.patches; ++c) patch_force += r.model.areas[c] * r.model.references[static_cast<std::size_t>(c)].traction;
  EXPECT_NEAR((patch_force - fine_force).norm(), 0.0, 1e-10 * fine_force.norm());
  // Load weights ω_p = A_p p_p / Σ_patch A p (T-31): the patch gap is Σ ω_p g_p and its force
  // A_c N_c is shared as ω_p A_c N_c.
  Eigen::VectorXd load = Eigen::VectorXd::Zero(r.patches), weight(fine.num_points());
  for (int p = 0; p < fine.num_points(); ++p)
    load[r.patch_of_point[static_cast<std::size_t>(p)]] += fine.areas[p] * -fine.references[static_cast<std::size_t>(p)].traction.z();
  for (int p = 0; p < fine.num_points(); ++p)
    weight[p] = fine.areas[p] * -fine.references[static_cast<std::size_t>(p)].traction.z() /
                load[r.patch_of_point[static_cast<std::size_t>(p)]];
  // gap_shapes_c = W Gφ: the modal force of the patch forces equals that of the shared fine forces.
  Eigen::VectorXd tc = Eigen::VectorXd::LinSpaced(3 * r.patches, -1.0, 2.0);  // any patch tractions
  Eigen::VectorXd fine_traction(3 * fine.num_points());
  for (int p = 0; p < fine.num_points(); ++p) {
    const int c = r.patch_of_point[static_cast<std::size_t>(p)];
    fine_traction.segment<3>(3 * p) = weight[p] * r.model.areas[c] * tc.segment<3>(3 * c);
  }
  Eigen::VectorXd patch_traction(3 * r.patches);
  for (int c = 0; c < r.patches; ++c) patch_traction.segment<3>(3 * c) = r.model.areas[c] * tc.segment<3>(3 * c);
  EXPECT_LT(relative(r.model.gap_shapes.transpose() * patch_traction, fine.gap_shapes.transpose() * fine_traction), 1e-12);
  // R0_c (A_c N_c) = W R0 (Wᵀ A_c N_c): the patches' mean of the fine residual gaps.
  const Eigen::VectorXd fine_gap = fine.residual_flexibility * fine_traction;
  Eigen::VectorXd mean_gap = Eigen::VectorXd::Zero(3 * r.patches);
  for (int p = 0; p < fine.num_points(); ++p) {
    const int c = r.patch_of_point[static_cast<std::size_t>(p)];
    mean_gap.segment<3>(3 * c) += weight[p] * fine_gap.segment<3>(3 * p);
  }
  EXPECT_LT(relative(r.model.residual_flexibility * patch_traction, mean_gap), 1e-12);
}

TEST(ContactPatches, LinearLimitOfTheDampingCurveIsTheFineOne) {
  // At small amplitude N_c → 0: the patch model is the fine linear model (same modes, residual
  // terms and damping), whatever the patch size. Reference: the exactly merged node pairs.
  const rd::ContactPatchResult exact = rd::merge_contact_patches(patch_lap().interface, patch_lap().model, {.size = 0.0});
  const rd::ContactPatchResult r = rd::merge_contact_patches(patch_lap().interface, patch_lap().model, {.size = 0.01});
  continuation::InterfaceBackboneOptions o;
  o.mode.balance.harmonics = 1;
  o.mode.balance.time_samples = 32;
  o.log10_amplitude_start = -10.0;
  o.log10_amplitude_end = -9.5;
  const auto a = continuation::trace_interface_backbone(exact.model, o);
  const auto b = continuation::trace_interface_backbone(r.model, o);
  ASSERT_FALSE(a.points.empty());
  ASSERT_FALSE(b.points.empty());
  const double linear = std::sqrt(patch_lap().interface.omega2[patch_lap().interface.rigid_modes]);
  const double df = std::abs(b.points.front().state.omega / a.points.front().state.omega - 1.0);
  const double dz = std::abs(b.points.front().state.damping_ratio / a.points.front().state.damping_ratio - 1.0);
  std::printf("q = 1e-10: 10 mm patches vs node pairs: frequency %.1e, damping %.1e (both within %.1e of the "
              "linear mode; %d vs %d unknowns)\n", df, dz,
              std::max(std::abs(a.points.front().state.omega / linear - 1.0), std::abs(b.points.front().state.omega / linear - 1.0)),
              static_cast<int>(b.unknowns), static_cast<int>(a.unknowns));
  EXPECT_LT(df, 1e-7);
  EXPECT_LT(dz, 1e-4);
}

TEST(ContactPatches, RejectsBadSizeAndMixedFrames) {
  EXPECT_THROW((void)rd::merge_contact_patches(patch_lap().interface, patch_lap().model, {.size = -1.0}), std::invalid_argument);
  EXPECT_THROW((void)rd::merge_contact_patches(patch_lap().interface, patch_lap().model, {.size = NAN}), std::invalid_argument);
  preload::PreloadModel tilted = patch_lap().model;
  tilted.interfaces[0].geometry.points[5].frame = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()).toRotationMatrix();
  try {
    (void)rd::merge_contact_patches(patch_lap().interface, tilted, {.size = 0.01});
    ADD_FAILURE() << "no error for a patch with mixed frames";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("different local frames"), std::string::npos) << e.what();
  }
  // Coincident points with different frames are not merged (their gaps differ): one more point.
  EXPECT_EQ(rd::merge_contact_patches(patch_lap().interface, tilted, {.size = 0.0}).patches, 64);
}

}  // namespace
