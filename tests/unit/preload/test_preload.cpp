// The bolts and the preloaded static state (preload/bolt.hpp, preload/preload_solver.hpp) on two
// stacked blocks joined by a zero-thickness interface.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "jointhb/contact/harmonic_loop.hpp"
#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/preload/preload_solver.hpp"

namespace fe = jointhb::fe;
namespace pl = jointhb::preload;
namespace ct = jointhb::contact;

namespace {

// Two 20 × 20 × h mm aluminium blocks, the upper one on the lower one.
fe::Mesh two_blocks(int n = 4, double h = 0.01) {
  fe::BoxOptions lower;
  lower.part = "lower";
  lower.size = {0.02, 0.02, h};
  lower.divisions = {n, n, 2};
  fe::BoxOptions upper = lower;
  upper.part = "upper";
  upper.origin = {0.0, 0.0, h};
  fe::Mesh mesh = fe::box_mesh(lower);
  fe::append(mesh, fe::box_mesh(upper));
  return mesh;
}

ct::ContactPointOptions contact_options() {
  ct::ContactPointOptions o;
  o.normal.reference_pressure = 1e6;
  o.normal.decay = 1e6;
  o.friction_coefficient = 0.3;
  return o;
}

pl::PreloadModel model_of(const fe::Mesh& mesh, double radius, double preload = 4000.0) {
  pl::PreloadModel m;
  m.mesh = &mesh;
  fe::Material al{"aluminium", 70e9, 0.33, 2700.0};
  m.structure = fe::assemble(mesh, {al, al});
  fe::InterfaceOptions io;
  io.name = "joint";
  io.bottom_surface = "lower.zmax";
  io.top_surface = "upper.zmin";
  m.interfaces.push_back({fe::build_interface(mesh, io),
                          ct::ContactPoint(contact_options(), ct::make_tangential_law("gaul-mayer", 1.0 / 3.0))});
  pl::BoltOptions b;
  b.name = "bolt";
  b.axis_point = {0.01, 0.01, 0.0};
  b.head_surface = "upper.zmax";
  b.nut_surface = "lower.zmin";
  b.head_radius = b.nut_radius = radius;
  b.axial_stiffness = 5e8;
  b.preload = preload;
  m.bolts.push_back(pl::build_bolt(mesh, b));
  return m;
}

}  // namespace

TEST(PreloadBolt, CouplingIsSelfEquilibratedAndMeasuresElongation) {
  const fe::Mesh mesh = two_blocks();
  const pl::PreloadModel m = model_of(mesh, 0.006);
  const pl::Bolt& bolt = m.bolts.front();
  EXPECT_FALSE(bolt.head_nodes.empty());
  EXPECT_FALSE(bolt.nut_nodes.empty());
  // A rigid translation does not stretch the bolt: bᵀu = 0.
  Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh.num_dofs());
  for (int i = 0; i < mesh.num_nodes(); ++i) u.segment<3>(3 * i) << 1e-3, -2e-3, 3e-3;
  EXPECT_NEAR(bolt.coupling.dot(u), 0.0, 1e-15);
  // Head up by δ, nut fixed: elongation δ.
  u.setZero();
  for (int i : bolt.head_nodes) u[3 * i + 2] = 1e-4;
  EXPECT_NEAR(bolt.coupling.dot(u), 1e-4, 1e-16);
  // The preload is self-equilibrated: Σ f = 0, Σ f_z over the head = −P.
  const Eigen::VectorXd f = pl::bolt_load(m.bolts, mesh.num_dofs());
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  double head_z = 0.0;
  for (int i = 0; i < mesh.num_nodes(); ++i) total += f.segment<3>(3 * i);
  for (int i : bolt.head_nodes) head_z += f[3 * i + 2];
  EXPECT_LT(total.norm(), 1e-9);
  EXPECT_NEAR(head_z, -4000.0, 1e-9);
}

TEST(PreloadBolt, ErrorsNameTheBoltAndTheField) {
  const fe::Mesh mesh = two_blocks();
  pl::BoltOptions b;
  b.name = "b7";
  b.axis_point = {0.01, 0.01, 0.0};
  b.head_surface = "upper.zmax";
  b.nut_surface = "nope";
  b.head_radius = b.nut_radius = 0.004;
  b.axial_stiffness = 1e8;
  b.preload = 1e3;
  try {
    (void)pl::build_bolt(mesh, b);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bolt 'b7': nut_surface: unknown surface 'nope'"), std::string::npos) << e.what();
  }
  b.nut_surface = "lower.zmin";
  b.axis_point = {1.0, 1.0, 0.0};  // far outside
  EXPECT_THROW((void)pl::build_bolt(mesh, b), std::invalid_argument);
  b.axis_point = {0.01, 0.01, 0.0};
  b.head_surface = "lower.zmin";  // head below the nut
  b.nut_surface = "upper.zmax";
  EXPECT_THROW((void)pl::build_bolt(mesh, b), std::invalid_argument);
}

// A washer's annulus (eq. B-4): on a plate of square faces of side h, the footprint is the faces
// whose centroid lies in [r_i, r_o]; it differs from the exact annulus only by faces straddling one
// of the two circles, which lie within h/√2 of it, so |A − π(r_o² − r_i²)| ≤ 2√2 π (r_o + r_i) h.
// The washer of a 5/16-in bolt (cases/14-brake-reuss-beam): r_o = 8.73 mm, r_i = 4.37 mm.
TEST(PreloadBolt, AnnularFootprintHasTheWasherArea) {
  const double r_o = 8.73e-3, r_i = 4.37e-3, exact = std::numbers::pi * (r_o * r_o - r_i * r_i);
  for (const int n : {80, 160}) {
    fe::BoxOptions plate;
    plate.part = "plate";
    plate.size = {0.02, 0.02, 0.002};
    plate.divisions = {n, n, 1};
    plate.type = fe::ElementType::hex8;
    const fe::Mesh mesh = fe::box_mesh(plate);
    const double h = 0.02 / n;
    pl::BoltOptions b;
    b.name = "washer";
    b.axis_point = {0.01, 0.01, 0.0};
    b.head_surface = "plate.zmax";
    b.nut_surface = "plate.zmin";
    b.head_radius = b.nut_radius = r_o;
    b.head_inner_radius = b.nut_inner_radius = r_i;
    b.axial_stiffness = 3.5e8;
    b.preload = 12e3;
    const pl::Bolt bolt = pl::build_bolt(mesh, b);
    const double bound = 2.0 * std::sqrt(2.0) * std::numbers::pi * (r_o + r_i) * h;
    std::printf("h = %.4g mm: footprint %.6g mm^2, pi (r_o^2 - r_i^2) = %.6g mm^2, error %.2e (bound %.2e)\n",
                h * 1e3, bolt.head_area * 1e6, exact * 1e6, bolt.head_area / exact - 1.0, bound / exact);
    EXPECT_LE(std::abs(bolt.head_area - exact), bound) << "n = " << n;
    EXPECT_NEAR(bolt.nut_area, bolt.head_area, 1e-12 * exact);
    EXPECT_DOUBLE_EQ(bolt.head_inner_radius, r_i);
    // No node of the hole: every footprint node lies within a face diagonal of the annulus.
    for (const int i : bolt.head_nodes) {
      const double r = std::hypot(mesh.coordinates(0, i) - 0.01, mesh.coordinates(1, i) - 0.01);
      EXPECT_GE(r, r_i - h / std::sqrt(2.0) - 1e-12) << "node " << i;
      EXPECT_LE(r, r_o + h / std::sqrt(2.0) + 1e-12) << "node " << i;
    }
    // The annulus still measures the elongation: head up by δ, nut fixed gives bᵀu = δ.
    Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh.num_dofs());
    for (const int i : bolt.head_nodes) u[3 * i + 2] = 1e-4;
    EXPECT_NEAR(bolt.coupling.dot(u), 1e-4, 1e-16);
  }
}

TEST(PreloadBolt, InnerRadiusMustLieBelowTheRadius) {
  const fe::Mesh mesh = two_blocks();
  pl::BoltOptions b;
  b.name = "b7";
  b.axis_point = {0.01, 0.01, 0.0};
  b.head_surface = "upper.zmax";
  b.nut_surface = "lower.zmin";
  b.head_radius = b.nut_radius = 0.004;
  b.axial_stiffness = 1e8;
  b.preload = 1e3;
  b.head_inner_radius = 0.004;
  EXPECT_EQ(b.validate(), "head_inner_radius: must be >= 0 and < head_radius = 0.004, got 0.004");
  try {
    (void)pl::build_bolt(mesh, b);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_EQ(what, "bolt 'b7': head_inner_radius: must be >= 0 and < head_radius = 0.004, got 0.004");
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  b.head_inner_radius = 0.0;
  b.nut_inner_radius = -1e-3;
  EXPECT_EQ(b.validate(), "nut_inner_radius: must be >= 0 and < nut_radius = 0.004, got -0.001");
  // An annulus with no face centre inside it (the 5 mm faces of two_blocks have centres at
  // 2.5√2 mm and farther from the axis) is named.
  b.nut_inner_radius = 0.0;
  b.head_inner_radius = 0.001;
  b.head_radius = 0.002;
  try {
    (void)pl::build_bolt(mesh, b);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no face has its centre between head_inner_radius = 0.001 m and head_radius = 0.002 m"),
              std::string::npos)
        << e.what();
  }
}

// A footprint covering the whole top and bottom faces loads the blocks by a uniform pressure
// P/A, so the interface pressure is uniform and equal to it; the gap follows from eq. (6):
// g = −ln(P/(A p_N0))/λ, independent of the blocks' elasticity.
TEST(PreloadSolver, UniformClampingMatchesTheExponentialLawInClosedForm) {
  const fe::Mesh mesh = two_blocks();
  const pl::PreloadModel m = model_of(mesh, 1.0);  // radius 1 m: every face
  pl::PreloadOptions o;
  o.residual_tolerance = 1e-11;
  const pl::PreloadResult r = pl::solve_preload(m, o);
  ASSERT_TRUE(r.status().ok()) << r.message;
  const double area = 0.02 * 0.02, p = 4000.0 / area;
  const auto& iface = r.interfaces.front();
  EXPECT_NEAR(iface.clamping_force / 4000.0 - 1.0, 0.0, 1e-9);
  const double gap = -std::log(p / 1e6) / 1e6;
  for (Eigen::Index k = 0; k < iface.state.pressure.size(); ++k) {
    EXPECT_NEAR(iface.state.pressure[k] / p - 1.0, 0.0, 1e-6) << "point " << k;
    EXPECT_NEAR(iface.state.gap[3 * k + 2], gap, 1e-6 * std::abs(gap));
  }
  EXPECT_NEAR(iface.closed_area_fraction, 1.0, 1e-12);
  EXPECT_LT(r.support_reaction, 1e-8);  // the 3-2-1 support carries (almost) nothing
  EXPECT_EQ(r.support_dofs.size(), 6u);
}

// A bolt with a small footprint: equilibrium makes the clamping force equal to the preload, the
// pressure concentrates under the bolt and decays away from it.
TEST(PreloadSolver, LocalBoltConcentratesThePressureAndBalancesTheBoltForce) {
  const fe::Mesh mesh = two_blocks(8, 0.004);
  const pl::PreloadModel m = model_of(mesh, 0.004);
  pl::PreloadOptions o;
  o.residual_tolerance = 1e-10;
  const pl::PreloadResult r = pl::solve_preload(m, o);
  ASSERT_TRUE(r.status().ok()) << r.message;
  const auto& iface = r.interfaces.front();
  EXPECT_NEAR(iface.clamping_force / 4000.0 - 1.0, 0.0, 1e-8);
  // Pressure at the point nearest the axis vs at a corner.
  double centre = 0.0, corner = 0.0, best_c = 1.0, best_k = 0.0;
  for (std::size_t p = 0; p < m.interfaces.front().geometry.points.size(); ++p) {
    const Eigen::Vector3d x = m.interfaces.front().geometry.points[p].position;
    const double d = std::hypot(x.x() - 0.01, x.y() - 0.01);
    if (d < best_c) best_c = d, centre = iface.state.pressure[static_cast<Eigen::Index>(p)];
    if (d > best_k) best_k = d, corner = iface.state.pressure[static_cast<Eigen::Index>(p)];
  }
  EXPECT_GT(centre, 2.0 * iface.mean_pressure);
  EXPECT_LT(corner, centre);
  EXPECT_GT(iface.max_gap, iface.min_gap);
  // The dynamic tangent is symmetric.
  const Eigen::SparseMatrix<double> K = r.dynamic_stiffness;
  EXPECT_LT(Eigen::MatrixXd(K - Eigen::SparseMatrix<double>(K.transpose())).cwiseAbs().maxCoeff(),
            1e-9 * Eigen::MatrixXd(K).cwiseAbs().maxCoeff());
}

// Modified Newton (reuse_factor_ratio): chord steps with an earlier factor save factorisations
// and reach the same state to the residual tolerance; 0 is plain Newton, one factorisation per
// iteration.
TEST(PreloadSolver, FactorReuseSavesFactorisationsAndReachesTheSameState) {
  const fe::Mesh mesh = two_blocks(8, 0.004);
  const pl::PreloadModel m = model_of(mesh, 0.004);
  pl::PreloadOptions plain;
  plain.residual_tolerance = 1e-10;
  plain.reuse_factor_ratio = 0.0;
  pl::PreloadOptions reuse = plain;
  reuse.reuse_factor_ratio = 0.1;
  const pl::PreloadResult a = pl::solve_preload(m, plain), b = pl::solve_preload(m, reuse);
  ASSERT_TRUE(a.status().ok()) << a.message;
  ASSERT_TRUE(b.status().ok()) << b.message;
  EXPECT_EQ(a.factor.factorizations, a.total_iterations);
  int chords = 0, factorizations = 0;
  for (const pl::PreloadStep& s : b.steps) {
    chords += s.chord_iterations;
    factorizations += s.factorizations;
    EXPECT_LE(s.residual, reuse.residual_tolerance);
  }
  EXPECT_GT(chords, 0);
  EXPECT_EQ(factorizations, b.factor.factorizations);
  EXPECT_LT(b.factor.factorizations, a.factor.factorizations);
  // Both states satisfy the residual tolerance: they agree far below the displacement scale.
  EXPECT_LT((a.displacement - b.displacement).norm(), 1e-6 * a.displacement.norm());
  pl::PreloadOptions bad = plain;
  bad.reuse_factor_ratio = 1.0;
  EXPECT_NE(bad.validate().find("reuse_factor_ratio"), std::string::npos);
}

TEST(PreloadSolver, UnconnectedPartIsNamed) {
  const fe::Mesh mesh = two_blocks();
  pl::PreloadModel m = model_of(mesh, 0.006);
  m.interfaces.clear();
  m.bolts.clear();
  try {
    (void)pl::solve_preload(m, {});
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("part 'upper'"), std::string::npos) << e.what();
  }
}

// The status convention (contact/termination.hpp): a converged preload, and one whose first load
// step runs out of Newton iterations (one iteration cannot reach 1e-14 from the unloaded state).
TEST(PreloadSolver, StatusSaysConvergedOrTheIterationLimit) {
  const fe::Mesh mesh = two_blocks();
  const pl::PreloadModel m = model_of(mesh, 1.0);
  const pl::PreloadResult good = pl::solve_preload(m, {});
  ASSERT_TRUE(good.status().ok()) << good.message;
  const jointhb::Status ok = good.status();
  EXPECT_EQ(ok.termination, jointhb::Termination::converged);
  EXPECT_TRUE(ok.ok());
  EXPECT_EQ(ok.brief(), "converged: " + good.message);  // "converged: 4 load steps, …"
  EXPECT_EQ(good.message.find("converged"), std::string::npos) << good.message;  // said once
  for (const pl::PreloadStep& step : good.steps) EXPECT_EQ(step.termination, jointhb::Termination::converged);

  pl::PreloadOptions o;
  o.max_iterations = 1;
  o.load_steps = 1;
  o.residual_tolerance = 1e-14;
  o.reuse_factor_ratio = 0.0;
  const pl::PreloadResult bad = pl::solve_preload(m, o);
  ASSERT_FALSE(bad.status().ok());
  const jointhb::Status s = bad.status();
  EXPECT_EQ(s.termination, jointhb::Termination::no_convergence) << bad.message;
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(s.message, bad.message);
  // The load step that stopped says the same, with its own reason inside the result's message.
  ASSERT_EQ(bad.steps.size(), 1u);
  EXPECT_EQ(bad.steps[0].status().termination, jointhb::Termination::no_convergence);
  EXPECT_NE(bad.message.find(bad.steps[0].message), std::string::npos) << bad.message;

  // A line search without decrease is a breakdown (more iterations would not cure it); a
  // default (never solved) result is failed too.
  o.max_iterations = 200;  // far more than Newton needs to reach round-off
  o.max_line_search = 0;
  o.residual_tolerance = 1e-300;  // below round-off: some Newton step must fail to decrease ‖r‖
  const pl::PreloadResult broken = pl::solve_preload(m, o);
  EXPECT_EQ(broken.status().termination, jointhb::Termination::failed) << broken.message;
  EXPECT_NE(broken.message.find("line search"), std::string::npos) << broken.message;
  EXPECT_EQ(pl::PreloadResult{}.status().termination, jointhb::Termination::failed);
}

// Footprints on triangular faces (tetrahedra; the z sides of wedges): the weights are the
// consistent loads of a uniform pressure, so the coupling averages u_z over the footprint exactly
// for a field the faces interpolate exactly (linear on tri3, quadratic on tri6).
TEST(PreloadBolt, TriangularFootprintsAverageExactly) {
  for (fe::ElementType type : {fe::ElementType::tet4, fe::ElementType::tet10,
                               fe::ElementType::wedge6, fe::ElementType::wedge15}) {
    fe::BoxOptions o;
    o.type = type;
    o.divisions = {3, 3, 2};
    const fe::Mesh mesh = fe::box_mesh(o);  // the unit cube
    pl::BoltOptions b;
    b.name = "b";
    b.axis_point = {0.5, 0.5, 0.0};
    b.head_surface = "box.zmax";
    b.nut_surface = "box.zmin";
    b.head_radius = b.nut_radius = 2.0;  // every face
    b.axial_stiffness = 1e8;
    const pl::Bolt bolt = pl::build_bolt(mesh, b);
    EXPECT_NEAR(bolt.head_area, 1.0, 1e-14) << fe::abaqus_name(type);
    EXPECT_NEAR(bolt.nut_area, 1.0, 1e-14);
    // u_z = z (x + y) / 2 (linear on each face), or z x² (quadratic) for the quadratic types:
    // head mean 1/2 resp. 1/3, nut mean 0.
    const bool quadratic = fe::is_quadratic(type);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh.num_dofs());
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      const Eigen::Vector3d x = mesh.coordinates.col(i);
      u[3 * i + 2] = quadratic ? x.z() * x.x() * x.x() : 0.5 * x.z() * (x.x() + x.y());
    }
    EXPECT_NEAR(bolt.coupling.dot(u), quadratic ? 1.0 / 3.0 : 0.5, 1e-14) << fe::abaqus_name(type);
  }
}
