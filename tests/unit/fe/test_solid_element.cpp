// Solid hexahedra (fe/solid_element.hpp): symmetry, rigid-body and spurious zero-energy modes,
// agreement of eq. (1) with ∫ Bᵀ D B dV, the patch test on distorted meshes (including Taylor's
// modification of the incompatible modes), consistent mass, pure bending with one element through
// the thickness (hex8 locks, hex8_incompatible and hex20 are exact).
#include "jointhb/fe/solid_element.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <random>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/hexahedron.hpp"
#include "unit/fe/test_box.hpp"

namespace jointhb::fe {
namespace {

const Material kMaterial{"test", 200e9, 0.3, 7800.0};

std::string name_of(const ::testing::TestParamInfo<ElementType>& info) {
  return abaqus_name(info.param);
}

// A distorted element: the corners of [0, 2] × [0, 1.5] × [0, 1] moved randomly by up to 0.2,
// mid-edge nodes at the middle of their edges, moved by up to 0.05 when `curved`.
Eigen::Matrix3Xd distorted_element(ElementType type, bool curved, unsigned seed = 3) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = node_count(type);
  Eigen::Matrix3Xd x(3, n);
  const Eigen::Vector3d half(1.0, 0.75, 0.5);
  for (int a = 0; a < 8; ++a)
    x.col(a) = half.cwiseProduct(hex_node_natural_coordinates(a) + Eigen::Vector3d::Ones()) +
               0.2 * Eigen::Vector3d(u(gen), u(gen), u(gen));
  if (n == 20) {
    // Mid-edge node between corners (edges of mesh.hpp).
    const auto& ends = hex_edge_corners();
    for (int m = 0; m < 12; ++m) {
      x.col(8 + m) = 0.5 * (x.col(ends[m][0]) + x.col(ends[m][1]));
      if (curved) x.col(8 + m) += 0.05 * Eigen::Vector3d(u(gen), u(gen), u(gen));
    }
  }
  return x;
}

// The 6 rigid-body displacement fields (3 translations, 3 infinitesimal rotations) at nodes x.
Eigen::MatrixXd rigid_body_modes(const Eigen::Matrix3Xd& x) {
  const Eigen::Index n = x.cols();
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(3 * n, 6);
  for (Eigen::Index a = 0; a < n; ++a) {
    for (int d = 0; d < 3; ++d) r(3 * a + d, d) = 1.0;
    for (int d = 0; d < 3; ++d)
      r.block<3, 1>(3 * a, 3 + d) = Eigen::Vector3d::Unit(d).cross(Eigen::Vector3d(x.col(a)));
  }
  return r;
}

// Strain-displacement matrix B (6 × 3n, Voigt xx yy zz xy yz zx) from gradients g (3 × n).
Eigen::MatrixXd b_matrix(const Eigen::Matrix3Xd& g) {
  const Eigen::Index n = g.cols();
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(6, 3 * n);
  for (Eigen::Index a = 0; a < n; ++a) {
    b(0, 3 * a) = g(0, a);
    b(1, 3 * a + 1) = g(1, a);
    b(2, 3 * a + 2) = g(2, a);
    b(3, 3 * a) = g(1, a);
    b(3, 3 * a + 1) = g(0, a);
    b(4, 3 * a + 1) = g(2, a);
    b(4, 3 * a + 2) = g(1, a);
    b(5, 3 * a) = g(2, a);
    b(5, 3 * a + 2) = g(0, a);
  }
  return b;
}

class SolidElement : public ::testing::TestWithParam<ElementType> {};

TEST_P(SolidElement, StiffnessIsSymmetricWithSixRigidBodyModes) {
  const ElementType type = GetParam();
  const Eigen::Matrix3Xd x = distorted_element(type, /*curved=*/true);
  const Eigen::MatrixXd k = element_stiffness(type, x, kMaterial);
  ASSERT_EQ(k.rows(), 3 * node_count(type));
  EXPECT_EQ((k - k.transpose()).cwiseAbs().maxCoeff(), 0.0);
  const double scale = k.cwiseAbs().maxCoeff();
  EXPECT_LT((k * rigid_body_modes(x)).cwiseAbs().maxCoeff(), 1e-12 * scale);

  const Eigen::VectorXd eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k).eigenvalues();
  int zeros = 0;
  for (Eigen::Index i = 0; i < eigenvalues.size(); ++i) {
    EXPECT_GT(eigenvalues(i), -1e-10 * eigenvalues.maxCoeff());
    if (eigenvalues(i) < 1e-10 * eigenvalues.maxCoeff()) ++zeros;
  }
  // 2×2×2 integration of the 20-node element leaves 6 spurious (non-communicable) zero-energy
  // modes in a single element (8 points × 6 strains = 48 < 60 − 6 constraints).
  const int expected = type == ElementType::hex20_reduced ? 12 : 6;
  EXPECT_EQ(zeros, expected) << "smallest non-zero eigenvalue / largest: "
                             << eigenvalues(expected) / eigenvalues.maxCoeff();
}

TEST_P(SolidElement, ConsistentMassCarriesTheElementMass) {
  const ElementType type = GetParam();
  // A parallelepiped x = A ξ + c (affine): V = 8 det A exactly.
  Eigen::Matrix3d a;
  a << 1.0, 0.2, 0.1, -0.1, 0.7, 0.15, 0.05, -0.2, 0.4;
  const int n = node_count(type);
  Eigen::Matrix3Xd x(3, n);
  for (int i = 0; i < n; ++i)
    x.col(i) = a * hex_node_natural_coordinates(i) + Eigen::Vector3d(1, 2, 3);
  const ElementMatrices e = element_matrices(type, x, kMaterial);
  const double volume = 8.0 * a.determinant();
  EXPECT_NEAR(e.volume, volume, 1e-14 * volume);
  EXPECT_EQ((e.mass - e.mass.transpose()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR(e.mass.sum(), 3.0 * kMaterial.density * volume, 1e-12 * kMaterial.density * volume);
  // Translational kinetic energy: ṫᵀ M ṫ = ρ V |v|² for a uniform velocity v, without coupling.
  const Eigen::MatrixXd r = rigid_body_modes(x).leftCols(3);
  const Eigen::Matrix3d translational = r.transpose() * e.mass * r;
  EXPECT_LT((translational - kMaterial.density * volume * Eigen::Matrix3d::Identity())
                .cwiseAbs()
                .maxCoeff(),
            1e-12 * kMaterial.density * volume);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(e.mass).eigenvalues().minCoeff(), 0.0);
}

TEST_P(SolidElement, IsotropicFormulaEqualsBtDB) {
  const ElementType type = GetParam();
  const Eigen::Matrix3Xd x = distorted_element(type, true);
  if (type == ElementType::hex8_incompatible) {
    // Condensation, eq. (3), only releases: K(hex8) − K(hex8_incompatible) = K_uα K_αα⁻¹ K_αu is
    // positive semi-definite, of rank ≤ 9, and non-zero.
    const Eigen::MatrixXd released =
        element_stiffness(ElementType::hex8, x, kMaterial) - element_stiffness(type, x, kMaterial);
    const Eigen::VectorXd ev =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(released).eigenvalues();
    EXPECT_GT(ev.minCoeff(), -1e-12 * ev.maxCoeff());
    EXPECT_GT(ev.maxCoeff(), 1e-3 * element_stiffness(ElementType::hex8, x, kMaterial).norm());
    EXPECT_LT(ev(ev.size() - 10), 1e-10 * ev.maxCoeff());
    return;
  }
  const Matrix6d d = elasticity_matrix(kMaterial);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(3 * x.cols(), 3 * x.cols());
  for (const GaussPoint& p : hex_gauss_rule(stiffness_rule(type))) {
    const Eigen::Matrix3Xd dn = shape_derivatives(type, p.xi);
    const Eigen::Matrix3d j = dn * x.transpose();
    const Eigen::MatrixXd b = b_matrix(j.inverse() * dn);
    expected += p.weight * j.determinant() * b.transpose() * d * b;
  }
  const Eigen::MatrixXd k = element_stiffness(type, x, kMaterial);
  EXPECT_LT((k - expected).cwiseAbs().maxCoeff(), 1e-13 * expected.cwiseAbs().maxCoeff());
}

// Patch test (Irons; MacNeal & Harder 1985): a 3×3×3 patch with randomly moved interior nodes,
// boundary nodes given the linear field u = A x + c; the interior solution must be the same linear
// field and every element centre must carry σ = D ε(A).
TEST_P(SolidElement, PatchTestOnDistortedMesh) {
  const ElementType type = GetParam();
  testing::TestBox box = testing::make_test_box(type, 1.0, 1.0, 1.0, 3, 3, 3);
  testing::distort_interior(box, 0.25, 17);
  const Mesh& mesh = box.mesh;
  Eigen::Matrix3d a;
  a << 1e-3, 2e-4, -3e-4, 5e-4, -2e-3, 1e-4, -4e-4, 3e-4, 1.5e-3;
  const Eigen::Vector3d c(1e-4, -2e-4, 3e-4);
  Eigen::VectorXd exact(mesh.num_dofs());
  for (int i = 0; i < mesh.num_nodes(); ++i)
    exact.segment<3>(3 * i) = a * mesh.coordinates.col(i) + c;

  FixedNodes boundary;
  for (int axis = 0; axis < 3; ++axis)
    for (double value : {0.0, 1.0})
      for (int node : testing::nodes_where(mesh, axis, value)) boundary.nodes.push_back(node);
  const DofMap dofs = DofMap::from_fixed_nodes(mesh.num_nodes(), {boundary});
  ASSERT_GT(dofs.num_free(), 0);
  const StructuralMatrices m = assemble(mesh, {kMaterial});
  // K_ff u_f = −K_fb u_b, with u_b = the exact field on the boundary.
  Eigen::VectorXd boundary_values = exact;
  for (int f : dofs.full_of_free) boundary_values(f) = 0.0;
  const Eigen::VectorXd rhs = -dofs.restrict(Eigen::VectorXd(m.stiffness * boundary_values));
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(dofs.restrict(m.stiffness));
  ASSERT_EQ(solver.info(), Eigen::Success);
  const Eigen::VectorXd u = dofs.expand(solver.solve(rhs)) + boundary_values;
  EXPECT_LT((u - exact).cwiseAbs().maxCoeff(), 1e-10 * exact.cwiseAbs().maxCoeff());

  Vector6d strain;
  strain << a(0, 0), a(1, 1), a(2, 2), a(0, 1) + a(1, 0), a(1, 2) + a(2, 1), a(2, 0) + a(0, 2);
  const Vector6d stress = elasticity_matrix(kMaterial) * strain;
  for (const Element& element : mesh.elements) {
    const int n = node_count(element.type);
    Eigen::Matrix3Xd x(3, n);
    Eigen::VectorXd ue(3 * n);
    for (int i = 0; i < n; ++i) {
      x.col(i) = mesh.coordinates.col(element.nodes[static_cast<std::size_t>(i)]);
      ue.segment<3>(3 * i) = u.segment<3>(3 * element.nodes[static_cast<std::size_t>(i)]);
    }
    EXPECT_LT((element_centre_stress(type, x, kMaterial, ue) - stress).cwiseAbs().maxCoeff(),
              1e-8 * stress.cwiseAbs().maxCoeff());
  }
}

INSTANTIATE_TEST_SUITE_P(Types, SolidElement,
                         ::testing::Values(ElementType::hex8, ElementType::hex8_incompatible,
                                           ElementType::hex20, ElementType::hex20_reduced),
                         name_of);

// Pure bending of a slender cantilever, one element through the thickness: length L = 10, square
// section h = b = 1, ν = 0 (no anticlastic curvature, so the fully clamped end is exact), end
// moment M applied as the consistent load of σ_xx = −M z/I. Beam theory (exact in 3D here):
// u_z(L) = M L² / (2 E I).
double bending_tip_ratio(ElementType type, int nx) {
  const double length = 10.0, h = 1.0, moment = 1.0;
  const Material material{"nu0", 1000.0, 0.0, 1.0};
  const testing::TestBox box = testing::make_test_box(type, length, h, h, nx, 1, 1);
  const Mesh& mesh = box.mesh;
  const double inertia = h * h * h * h / 12.0;
  const Eigen::VectorXd f = testing::face_load(mesh, length, [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(-moment * (p(2) - 0.5 * h) / inertia, 0.0, 0.0);
  });
  const DofMap dofs =
      DofMap::from_fixed_nodes(mesh.num_nodes(), {{testing::nodes_where(mesh, 0, 0.0)}});
  const StructuralMatrices m = assemble(mesh, {material});
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(dofs.restrict(m.stiffness));
  const Eigen::VectorXd u = dofs.expand(solver.solve(dofs.restrict(f)));
  const std::vector<int> tip = testing::nodes_where(mesh, 0, length);
  double w = 0.0;
  for (int node : tip) w += u(3 * node + 2) / static_cast<double>(tip.size());
  return w / (moment * length * length / (2.0 * material.youngs_modulus * inertia));
}

TEST(SolidElementBending, IncompatibleModesAndHex20AreExactInPureBending) {
  // Element aspect ratio 2 (5 elements) and 1 (10 elements).
  for (int nx : {5, 10}) {
    EXPECT_NEAR(bending_tip_ratio(ElementType::hex8_incompatible, nx), 1.0, 1e-9) << nx;
    EXPECT_NEAR(bending_tip_ratio(ElementType::hex20, nx), 1.0, 1e-9) << nx;
    EXPECT_NEAR(bending_tip_ratio(ElementType::hex20_reduced, nx), 1.0, 1e-9) << nx;
  }
}

TEST(SolidElementBending, FullyIntegratedHex8LocksInBending) {
  // Parasitic shear: for a 2D bilinear element the ratio is 1/(1 + (a/h)²/2) at ν = 0 (Cook et
  // al., Concepts and Applications of FEA, §6.13); here ≈ 1/3 at a/h = 2 and ≈ 2/3 at a/h = 1.
  const double aspect2 = bending_tip_ratio(ElementType::hex8, 5);
  const double aspect1 = bending_tip_ratio(ElementType::hex8, 10);
  EXPECT_LT(aspect2, 0.4);
  EXPECT_GT(aspect2, 0.25);
  EXPECT_LT(aspect1, 0.7);
  EXPECT_LT(aspect2, aspect1);
  std::printf(
      "hex8 pure bending, one element through the thickness: tip / exact = %.4f (a/h = 2), "
      "%.4f (a/h = 1)\n",
      aspect2, aspect1);
}

TEST(SolidElementErrors, InvertedElementAndWrongSizesThrow) {
  Eigen::Matrix3Xd x(3, 8);
  for (int a = 0; a < 8; ++a) x.col(a) = hex_node_natural_coordinates(a);
  EXPECT_NO_THROW((void)element_stiffness(ElementType::hex8, x, kMaterial));
  Eigen::Matrix3Xd mirrored = x;
  mirrored.row(0) *= -1.0;  // left-handed node order: det J < 0
  EXPECT_THROW((void)element_stiffness(ElementType::hex8, mirrored, kMaterial),
               std::invalid_argument);
  EXPECT_THROW((void)element_stiffness(ElementType::hex8_incompatible, mirrored, kMaterial),
               std::invalid_argument);
  EXPECT_THROW((void)element_stiffness(ElementType::hex20, x, kMaterial), std::invalid_argument);
  Material bad = kMaterial;
  bad.poissons_ratio = 0.5;
  EXPECT_THROW((void)element_mass(ElementType::hex8, x, bad), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::fe
