// Global assembly and DOF map (fe/assembly.hpp): total mass, rigid-body null space of a free
// mesh, symmetry, thread-count independence (bit for bit), free-DOF restriction, errors.
#include "jointhb/fe/assembly.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstring>

#include "unit/fe/test_box.hpp"

namespace jointhb::fe {
namespace {

const Material kAluminium{"aluminium", 70e9, 0.33, 2700.0};

class Assembly : public ::testing::TestWithParam<ElementType> {};

TEST_P(Assembly, FreeMeshHasMassOfTheBoxAndSixRigidBodyModes) {
  const ElementType type = GetParam();
  testing::TestBox box = testing::make_test_box(type, 0.3, 0.2, 0.1, 3, 2, 2);
  testing::distort_interior(box, 0.2, 5);  // planar boundary: the volume stays 0.3·0.2·0.1
  const Mesh& mesh = box.mesh;
  const StructuralMatrices m = assemble(mesh, {kAluminium});
  const double volume = 0.3 * 0.2 * 0.1;
  EXPECT_NEAR(m.total_volume, volume, 1e-14);
  EXPECT_NEAR(m.total_mass, kAluminium.density * volume, 1e-12 * kAluminium.density * volume);
  EXPECT_NEAR(m.mass.sum(), 3.0 * m.total_mass, 1e-12 * m.total_mass);
  EXPECT_EQ(m.stiffness.rows(), mesh.num_dofs());
  EXPECT_EQ(Eigen::SparseMatrix<double>(m.stiffness -
                                        Eigen::SparseMatrix<double>(m.stiffness.transpose()))
                .cwiseAbs()
                .sum(),
            0.0);
  EXPECT_EQ(Eigen::SparseMatrix<double>(m.mass - Eigen::SparseMatrix<double>(m.mass.transpose()))
                .cwiseAbs()
                .sum(),
            0.0);

  // K r = 0 for the 6 rigid-body fields; M r has the resultant ρ V of a translation.
  const double k_scale = Eigen::MatrixXd(m.stiffness).cwiseAbs().maxCoeff();
  for (int mode = 0; mode < 6; ++mode) {
    Eigen::VectorXd r(mesh.num_dofs());
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      const Eigen::Vector3d x = mesh.coordinates.col(i);
      r.segment<3>(3 * i) = mode < 3 ? Eigen::Vector3d(Eigen::Vector3d::Unit(mode))
                                     : Eigen::Vector3d(Eigen::Vector3d::Unit(mode - 3).cross(x));
    }
    const Eigen::VectorXd kr = m.stiffness * r;
    EXPECT_LT(kr.cwiseAbs().maxCoeff(), 1e-12 * k_scale * r.cwiseAbs().maxCoeff()) << mode;
    if (mode < 3) {
      EXPECT_NEAR(r.dot(m.mass * r), m.total_mass, 1e-12 * m.total_mass);
    }
  }
  // Exactly 6 zero eigenvalues: the mesh has no spurious mechanism (hex20_reduced included).
  const Eigen::VectorXd eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(m.stiffness)).eigenvalues();
  EXPECT_LT(eigenvalues(5), 1e-10 * eigenvalues.maxCoeff());
  EXPECT_GT(eigenvalues(6), 1e-8 * eigenvalues.maxCoeff());
}

TEST_P(Assembly, OneAndTwoThreadsAreBitIdentical) {
  testing::TestBox box = testing::make_test_box(GetParam(), 1.0, 0.5, 0.25, 12, 6, 3);
  testing::distort_interior(box, 0.2, 9);
  AssemblyOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const StructuralMatrices a = assemble(box.mesh, {kAluminium}, one);
  const StructuralMatrices b = assemble(box.mesh, {kAluminium}, two);
  ASSERT_EQ(a.stiffness.nonZeros(), b.stiffness.nonZeros());
  const auto bytes = static_cast<std::size_t>(a.stiffness.nonZeros()) * sizeof(double);
  EXPECT_EQ(std::memcmp(a.stiffness.valuePtr(), b.stiffness.valuePtr(), bytes), 0);
  EXPECT_EQ(std::memcmp(a.mass.valuePtr(), b.mass.valuePtr(), bytes), 0);
  EXPECT_EQ(std::memcmp(a.stiffness.innerIndexPtr(), b.stiffness.innerIndexPtr(),
                        static_cast<std::size_t>(a.stiffness.nonZeros()) * sizeof(int)),
            0);
  EXPECT_EQ(a.total_mass, b.total_mass);
}

INSTANTIATE_TEST_SUITE_P(Types, Assembly,
                         ::testing::Values(ElementType::hex8, ElementType::hex8_incompatible,
                                           ElementType::hex20, ElementType::hex20_reduced),
                         [](const auto& p) { return std::string(abaqus_name(p.param)); });

TEST(AssemblyParts, EachPartUsesItsMaterial) {
  Mesh mesh = testing::make_test_box(ElementType::hex8, 1.0, 1.0, 1.0, 1, 1, 1).mesh;
  Mesh other = testing::make_test_box(ElementType::hex8, 1.0, 1.0, 1.0, 1, 1, 1).mesh;
  other.parts = {"second"};
  append(mesh, other);
  const Material steel{"steel", 210e9, 0.3, 7800.0};
  const StructuralMatrices m = assemble(mesh, {kAluminium, steel});
  EXPECT_NEAR(m.total_mass, 2700.0 + 7800.0, 1e-9);
  const StructuralMatrices single = assemble(other, {steel});
  // The second part's block is the steel cube's matrix.
  EXPECT_NEAR(m.stiffness.coeff(24, 24), single.stiffness.coeff(0, 0), 1e-6);
  EXPECT_THROW((void)assemble(mesh, {kAluminium}), std::invalid_argument);
  Material bad = steel;
  bad.density = 0.0;
  EXPECT_THROW((void)assemble(mesh, {kAluminium, bad}), std::invalid_argument);
}

TEST(AssemblyErrors, InvertedElementIsNamed) {
  Mesh mesh = testing::make_test_box(ElementType::hex8, 1.0, 1.0, 1.0, 2, 1, 1).mesh;
  std::swap(mesh.elements[1].nodes[1], mesh.elements[1].nodes[3]);  // left-handed
  try {
    (void)assemble(mesh, {kAluminium});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("element 2"), std::string::npos) << e.what();
  }
  AssemblyOptions options;
  options.threads = -1;
  EXPECT_NE(options.validate().find("threads"), std::string::npos);
}

TEST(DofMap, FixedDirectionsExpandAndRestrict) {
  const DofMap map =
      DofMap::from_fixed_nodes(3, {{{0}, {true, true, true}}, {{2}, {false, true, false}}});
  EXPECT_EQ(map.num_full(), 9);
  EXPECT_EQ(map.num_free(), 5);
  EXPECT_EQ(map.full_of_free, (std::vector<int>{3, 4, 5, 6, 8}));
  EXPECT_EQ(map.free_of_full[7], -1);
  const Eigen::VectorXd free = Eigen::VectorXd::LinSpaced(5, 1.0, 5.0);
  const Eigen::VectorXd full = map.expand(free);
  EXPECT_EQ(full(0), 0.0);
  EXPECT_EQ(full(8), 5.0);
  EXPECT_EQ(map.restrict(full), free);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(9, 9);
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j)
      if ((i + j) % 2 == 0) dense(i, j) = 10.0 * i + j;
  const Eigen::MatrixXd restricted =
      Eigen::MatrixXd(map.restrict(Eigen::SparseMatrix<double>(dense.sparseView())));
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      EXPECT_EQ(restricted(i, j), dense(map.full_of_free[static_cast<std::size_t>(i)],
                                        map.full_of_free[static_cast<std::size_t>(j)]));
  EXPECT_THROW((void)DofMap::from_fixed_nodes(3, {{{3}}}), std::invalid_argument);
  EXPECT_THROW((void)map.expand(Eigen::VectorXd::Zero(4)), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::fe
