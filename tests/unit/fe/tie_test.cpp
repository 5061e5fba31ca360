// Bonded surfaces (fe/tie.hpp, docs/ties.md): K_tie = k Gᵀ A G (TIE-1) with k = α E_max / h
// (TIE-2). The independent reference is the uncut bar: a bar cut in two boxes and tied must have
// the frequencies of one box with the same mesh (nodes merged), with an error that falls like 1/α;
// K_tie must annihilate the six rigid-body motions of the whole, be symmetric positive
// semi-definite and frame-independent (a relative translation d costs k A |d|² in any direction).
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/fe/tie.hpp"
#include "jointhb/pipeline/fe_model.hpp"

namespace jointhb::fe {
namespace {

const Material kSteel{"steel", 210e9, 0.3, 7850.0};

// A steel bar [0, 0.1] × [0, 0.02] × [0, 0.01] of `type`, 10 × 2 × 1 cells: cut at x = 0.05 into
// two boxes "a" and "b" (coincident nodes on the cut), or whole.
Mesh bar(bool cut, ElementType type) {
  BoxOptions o;
  o.type = type;
  if (!cut) {
    o.size = {0.1, 0.02, 0.01};
    o.divisions = {10, 2, 1};
    return box_mesh(o);
  }
  o.part = "a";
  o.size = {0.05, 0.02, 0.01};
  o.divisions = {5, 2, 1};
  Mesh mesh = box_mesh(o);
  o.part = "b";
  o.origin = {0.05, 0.0, 0.0};
  append(mesh, box_mesh(o));
  return mesh;
}

TieOptions cut_tie(double alpha) {
  TieOptions o;
  o.name = "cut";
  o.slave_surface = "b.xmin";
  o.master_surface = "a.xmax";
  o.penalty_factor = alpha;
  return o;
}

// The lowest `count` frequencies [Hz] of (K, M) with the nodes of `clamped` fixed (dense: the
// bars are small, and a dense solver is independent of the ARPACK path of the pipeline).
Eigen::VectorXd frequencies(const Eigen::SparseMatrix<double>& k, const Eigen::SparseMatrix<double>& m,
                            const std::vector<int>& clamped, int num_nodes, int count) {
  const DofMap dofs = DofMap::from_fixed_nodes(num_nodes, {FixedNodes{clamped}});
  const Eigen::MatrixXd kd = Eigen::MatrixXd(dofs.restrict(k));
  const Eigen::MatrixXd md = Eigen::MatrixXd(dofs.restrict(m));
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(kd, md, Eigen::EigenvaluesOnly);
  return eig.eigenvalues().head(count).cwiseSqrt() / (2.0 * M_PI);
}

// The cantilever frequencies of the uncut bar (the reference) and of the cut bar tied with factor α
// (through pipeline::preload_model, the path every stage takes).
Eigen::VectorXd whole_bar(ElementType type, int count) {
  const Mesh whole = bar(false, type);
  const StructuralMatrices s = assemble(whole, {kSteel});
  return frequencies(s.stiffness, s.mass, whole.node_sets.at("box.xmin"), whole.num_nodes(), count);
}

struct TiedBar {
  Eigen::VectorXd frequencies;
  double penalty = 0.0;
};

TiedBar tied_bar(double alpha, ElementType type, int count) {
  pipeline::FeModel model;
  model.mesh = bar(true, type);
  model.material_per_part = {kSteel, kSteel};
  model.ties.push_back(build_tie(model.mesh, model.material_per_part, cut_tie(alpha)));
  const preload::PreloadModel p = pipeline::preload_model(model);
  return {frequencies(p.structure.stiffness, p.structure.mass, model.mesh.node_sets.at("a.xmin"),
                      model.mesh.num_nodes(), count),
          model.ties[0].penalty};
}

TEST(Tie, PenaltyFollowsTheMaterialAndTheSmallestEdge) {
  const Mesh mesh = bar(true, ElementType::hex8_incompatible);
  Material soft = kSteel;
  soft.youngs_modulus = 70e9;
  const Tie tie = build_tie(mesh, {soft, kSteel}, cut_tie(1e3));
  EXPECT_EQ(tie.youngs_modulus, 210e9);  // the stiffer side
  EXPECT_NEAR(tie.element_size, 0.01, 1e-15);  // cells 0.01 × 0.01 × 0.01
  EXPECT_NEAR(tie.penalty, 1e3 * 210e9 / 0.01, 1e-6 * tie.penalty);
  EXPECT_NEAR(tie.area, 0.02 * 0.01, 1e-18);
  EXPECT_EQ(tie.num_tied_points(), 2 * 4);  // nodal integration: 4 points per face, 2 faces
  EXPECT_EQ(tie.geometry.integration, InterfaceIntegration::nodal);
}

// (TIE-1): symmetric, positive semi-definite, zero on the six rigid-body motions of the whole, and
// a relative translation d of one box costs uᵀ K_tie u = k A |d|² whatever its direction.
TEST(Tie, StiffnessIsSymmetricSemiDefiniteAndAnnihilatesRigidBodyMotions) {
  const Mesh mesh = bar(true, ElementType::hex8_incompatible);
  const Tie tie = build_tie(mesh, {kSteel, kSteel}, cut_tie(1e3));
  const Eigen::SparseMatrix<double> k = tie_stiffness(std::span<const Tie>(&tie, 1), mesh.num_dofs());
  const Eigen::MatrixXd kd = Eigen::MatrixXd(k);
  EXPECT_EQ((kd - kd.transpose()).cwiseAbs().maxCoeff(), 0.0);  // exactly symmetric
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(kd, Eigen::EigenvaluesOnly);
  EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12 * eig.eigenvalues().maxCoeff());

  const Eigen::Vector3d centre(0.05, 0.01, 0.005);
  Eigen::MatrixXd rigid(mesh.num_dofs(), 6);
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const Eigen::Vector3d x = mesh.coordinates.col(n) - centre;
    for (int r = 0; r < 3; ++r) {
      rigid.block<3, 1>(3 * n, r) = Eigen::Vector3d::Unit(r);
      rigid.block<3, 1>(3 * n, 3 + r) = Eigen::Vector3d::Unit(r).cross(x) / 0.05;  // unit-size rotations
    }
  }
  const double scale = kd.norm() * rigid.norm();
  EXPECT_LE((k * rigid).norm(), 1e-14 * scale) << "‖K_tie R‖ / (‖K_tie‖ ‖R‖) = " << (k * rigid).norm() / scale;

  for (const Eigen::Vector3d& d : {Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, 1.0),
                                   Eigen::Vector3d(0.3, -0.5, 0.8).normalized()}) {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(mesh.num_dofs());
    for (int n = mesh.num_nodes() / 2; n < mesh.num_nodes(); ++n) u.segment<3>(3 * n) = d;  // box b's nodes
    EXPECT_NEAR(u.dot(k * u), tie.penalty * tie.area, 1e-12 * tie.penalty * tie.area) << d.transpose();
  }
}

// The independent reference: the uncut bar with the same mesh. The tie's compliance adds an
// error O(1/α) to every frequency; printed as the table of docs/ties.md §4 (Markdown rows).
TEST(Tie, CutBarConvergesToTheUncutBarLikeOneOverAlpha) {
  const double alphas[] = {1e2, 1e3, 1e4, 1e5, 1e6};
  const Eigen::VectorXd whole = whole_bar(ElementType::hex8_incompatible, 6);
  std::printf("  (f_whole [Hz]: %s)\n", fmt::format("{:.2f}", fmt::join(whole, ", ")).c_str());
  double previous = 0.0;
  std::printf("| alpha | k [Pa/m] | f/f_whole - 1, modes 1 to 6 | max error | order |\n| --- | --- | --- | --- | --- |\n");
  for (const double alpha : alphas) {
    const TiedBar r = tied_bar(alpha, ElementType::hex8_incompatible, 6);
    const Eigen::ArrayXd relative = r.frequencies.array() / whole.array() - 1.0;
    const double error = relative.abs().maxCoeff();
    // α = 1e6 is printed, not checked: there the round-off of the eigensolver (κ(K) grows like α)
    // reaches the tie's own error (docs/ties.md §4).
    const bool checked = alpha <= 1e5;
    if (checked) {
      EXPECT_TRUE((relative < 0.0).all()) << "a penalty tie is softer than the bond";
    }
    const double order = previous > 0.0 ? std::log10(previous / error) : 0.0;
    std::string modes;
    for (const double e : relative) modes += fmt::format("{}{:.2e}", modes.empty() ? "" : ", ", e);
    std::printf("| %.0e | %.2e | %s | %.3e | %s |\n", alpha, r.penalty, modes.c_str(), error,
                previous > 0.0 ? fmt::format("{:.3f}", order).c_str() : "");
    if (alpha == 1e3) {
      EXPECT_LT(error, 1e-3);
    }
    if (previous > 0.0 && checked) {
      EXPECT_GT(order, 0.9);
      EXPECT_LT(order, 1.1);
    }
    previous = error;
  }
}

// Quadratic faces take Gauss integration (3×3) and converge alike.
TEST(Tie, QuadraticFacesAreTiedWithGaussPoints) {
  const Eigen::ArrayXd whole = whole_bar(ElementType::hex20, 4).array();
  const double e3 = (tied_bar(1e3, ElementType::hex20, 4).frequencies.array() / whole - 1.0).abs().maxCoeff();
  const double e4 = (tied_bar(1e4, ElementType::hex20, 4).frequencies.array() / whole - 1.0).abs().maxCoeff();
  EXPECT_LT(e3, 2e-3);
  EXPECT_NEAR(std::log10(e3 / e4), 1.0, 0.1) << e3 << " " << e4;
  const Tie tie = build_tie(bar(true, ElementType::hex20), {kSteel, kSteel}, cut_tie(1e3));
  EXPECT_EQ(tie.geometry.integration, InterfaceIntegration::gauss);
  EXPECT_NEAR(tie.area, 0.02 * 0.01, 1e-17);
}

TEST(Tie, TiedNodesRestrictTheSlaveNodes) {
  const Mesh mesh = bar(true, ElementType::hex8_incompatible);
  TieOptions o = cut_tie(1e3);
  // The slave nodes at y = 0 only: 2 of the 6 nodes of b.xmin, each in one face → 2 points, a
  // quarter of a face's area each (0.01 × 0.01 / 4).
  for (int n : mesh.node_sets.at("b.xmin"))
    if (mesh.coordinates(1, n) == 0.0) o.tied_nodes.push_back(n);
  const Tie tie = build_tie(mesh, {kSteel, kSteel}, o);
  EXPECT_EQ(tie.num_tied_points(), 2);
  EXPECT_NEAR(tie.area, 2 * 0.25e-4, 1e-18);
  o.tied_nodes = mesh.node_sets.at("a.xmin");  // none on the slave surface
  EXPECT_THROW((void)build_tie(mesh, {kSteel, kSteel}, o), std::invalid_argument);
}

TEST(Tie, ErrorsNameTheTie) {
  const Mesh mesh = bar(true, ElementType::hex8_incompatible);
  const auto message = [&](const TieOptions& o) -> std::string {
    try {
      (void)build_tie(mesh, {kSteel, kSteel}, o);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no exception";
  };
  TieOptions o = cut_tie(1e3);
  o.master_surface = "nope";
  EXPECT_EQ(message(o), "tie 'cut' (slave = bottom, master = top): unknown surface 'nope' (top_surface)");
  o = cut_tie(0.5);
  EXPECT_EQ(message(o), "tie 'cut': penalty_factor = 0.5 must lie in [1, 1e6]");
  o = cut_tie(1e3);
  o.master_surface = "a.xmin";  // not coincident with b.xmin
  EXPECT_EQ(message(o).rfind("tie 'cut' (slave = bottom, master = top): ", 0), 0u) << message(o);
  EXPECT_THROW((void)build_tie(mesh, {kSteel}, cut_tie(1e3)), std::invalid_argument);  // 1 material, 2 parts
}

}  // namespace
}  // namespace jointhb::fe

namespace jointhb::fe {
namespace {

// A tie between independently meshed halves (automatic → non-matching, dual mortar): box a with
// 5 × 2 × 1 cells, box b with 7 × 3 × 2. Its frequencies lie between those of the uncut bar meshed
// like a (10 × 2 × 1) and like b (14 × 3 × 2) — the tie adds nothing beyond the discretisation
// error (and the O(1/α) penalty error) — and K_tie still annihilates the rigid-body motions.
TEST(Tie, NonMatchingHalvesLieBetweenTheirTwoMeshes) {
  pipeline::FeModel model;
  BoxOptions o;
  o.part = "a";
  o.size = {0.05, 0.02, 0.01};
  o.divisions = {5, 2, 1};
  model.mesh = box_mesh(o);
  o.part = "b";
  o.origin = {0.05, 0.0, 0.0};
  o.divisions = {7, 3, 2};
  append(model.mesh, box_mesh(o));
  model.material_per_part = {kSteel, kSteel};
  model.ties.push_back(build_tie(model.mesh, model.material_per_part, cut_tie(1e5)));
  EXPECT_EQ(model.ties[0].geometry.meshes, InterfaceMeshes::non_matching);
  const preload::PreloadModel p = pipeline::preload_model(model);
  const Eigen::VectorXd tied = frequencies(p.structure.stiffness, p.structure.mass, model.mesh.node_sets.at("a.xmin"),
                                           model.mesh.num_nodes(), 6);
  const auto whole = [&](std::array<int, 3> divisions) {
    BoxOptions w;
    w.size = {0.1, 0.02, 0.01};
    w.divisions = divisions;
    const Mesh m = box_mesh(w);
    const StructuralMatrices s = assemble(m, {kSteel});
    return frequencies(s.stiffness, s.mass, m.node_sets.at("box.xmin"), m.num_nodes(), 6);
  };
  const Eigen::VectorXd coarse = whole({10, 2, 1}), fine = whole({14, 3, 2});
  for (int j = 0; j < 6; ++j) {
    const double lo = std::min(coarse(j), fine(j)), hi = std::max(coarse(j), fine(j));
    EXPECT_GE(tied(j), lo * (1.0 - 1e-4)) << "mode " << j + 1;
    EXPECT_LE(tied(j), hi * (1.0 + 1e-4)) << "mode " << j + 1;
  }
  const Tie& tie = model.ties[0];
  const Eigen::SparseMatrix<double> k = tie_stiffness(std::span<const Tie>(&tie, 1), model.mesh.num_dofs());
  Eigen::MatrixXd rigid(model.mesh.num_dofs(), 6);
  for (int n = 0; n < model.mesh.num_nodes(); ++n) {
    const Eigen::Vector3d x = model.mesh.coordinates.col(n) - Eigen::Vector3d(0.05, 0.01, 0.005);
    for (int r = 0; r < 3; ++r) {
      rigid.block<3, 1>(3 * n, r) = Eigen::Vector3d::Unit(r);
      rigid.block<3, 1>(3 * n, 3 + r) = Eigen::Vector3d::Unit(r).cross(x) / 0.05;
    }
  }
  EXPECT_LE((k * rigid).norm(), 1e-13 * Eigen::MatrixXd(k).norm() * rigid.norm());
}

}  // namespace
}  // namespace jointhb::fe
