// Tetrahedra (C3D4, C3D10) and wedges (C3D6, C3D15): shape functions, rules, element matrices,
// faces, patch tests, box meshes and convergence of the axial frequency of a bar.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/fe/hexahedron.hpp"
#include "jointhb/fe/mesh_checks.hpp"
#include "jointhb/fe/simplex_elements.hpp"
#include "jointhb/fe/solid_element.hpp"
#include "unit/fe/simplex_test_support.hpp"

namespace jointhb::fe {
namespace {

using testing::axial_frequency;
using testing::box_of;
using testing::distort_mesh;
using testing::element_coordinates;
using testing::patch_test;
using testing::steel;

const ElementType kElementTypes[] = {ElementType::tet4, ElementType::tet10, ElementType::wedge6,
                              ElementType::wedge15};

// A point strictly inside the reference element.
Eigen::Vector3d inside(ElementType type, std::mt19937& gen) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (;;) {
    const Eigen::Vector3d p(u(gen), u(gen), u(gen));
    if (family(type) == ElementFamily::tetrahedron && p.sum() < 1.0) return p;
    if (family(type) == ElementFamily::wedge && p(0) + p(1) < 1.0)
      return {p(0), p(1), 2.0 * p(2) - 1.0};
  }
}

class Simplex : public ::testing::TestWithParam<ElementType> {};

TEST_P(Simplex, PartitionOfUnityAndKroneckerProperty) {
  const ElementType type = GetParam();
  const int n = node_count(type);
  for (int a = 0; a < n; ++a) {
    const Eigen::VectorXd values =
        shape_functions(type, simplex_node_natural_coordinates(type, a));
    for (int b = 0; b < n; ++b) EXPECT_NEAR(values(b), a == b ? 1.0 : 0.0, 1e-14) << a << " " << b;
  }
  std::mt19937 gen(3);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d xi = inside(type, gen);
    EXPECT_NEAR(shape_functions(type, xi).sum(), 1.0, 1e-14);
    EXPECT_LT(shape_derivatives(type, xi).rowwise().sum().cwiseAbs().maxCoeff(), 1e-13);
    // Linear completeness: Σ N_a ξ_a = ξ (isoparametric map of the reference element).
    Eigen::Matrix3Xd nodes(3, n);
    for (int a = 0; a < n; ++a) nodes.col(a) = simplex_node_natural_coordinates(type, a);
    EXPECT_LT((nodes * shape_functions(type, xi) - xi).norm(), 1e-14);
  }
}

TEST_P(Simplex, DerivativesMatchCentralDifferences) {
  const ElementType type = GetParam();
  std::mt19937 gen(5);
  const double h = 1e-6;
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector3d xi = inside(type, gen);
    const Eigen::Matrix3Xd d = shape_derivatives(type, xi);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(k);
      const Eigen::VectorXd fd =
          (shape_functions(type, xi + e) - shape_functions(type, xi - e)) / (2.0 * h);
      EXPECT_LT((fd.transpose() - d.row(k)).cwiseAbs().maxCoeff(), 1e-8) << k;
    }
  }
}

// An element of `type` with straight edges: the reference element mapped by an affine map, then
// its corners moved (≤ 15 % of the size) and mid-edge nodes put back on the edge middles.
Eigen::Matrix3Xd distorted_element(ElementType type, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  Eigen::Matrix3d a;
  a << 1.2, 0.2, -0.1, 0.1, 0.9, 0.3, -0.2, 0.1, 1.1;
  const int n = node_count(type), corners = corner_count(type);
  Eigen::Matrix3Xd x(3, n);
  for (int k = 0; k < corners; ++k)
    x.col(k) = a * simplex_node_natural_coordinates(type, k) + Eigen::Vector3d(u(gen), u(gen), u(gen));
  const auto edges = edge_corners(type);
  for (int k = corners; k < n; ++k) {
    const auto& e = edges[static_cast<std::size_t>(k - corners)];
    x.col(k) = 0.5 * (x.col(e[0]) + x.col(e[1]));
  }
  return x;
}

TEST_P(Simplex, SingleElementHasExactlySixRigidBodyModes) {
  const ElementType type = GetParam();
  const Eigen::Matrix3Xd x = distorted_element(type, 11);
  const Eigen::MatrixXd k = element_stiffness(type, x, steel());
  EXPECT_LT((k - k.transpose()).cwiseAbs().maxCoeff(), 1e-12 * k.cwiseAbs().maxCoeff());
  const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k).eigenvalues();
  const double tol = 1e-10 * lambda.cwiseAbs().maxCoeff();
  int zeros = 0;
  for (Eigen::Index i = 0; i < lambda.size(); ++i) zeros += std::abs(lambda(i)) < tol ? 1 : 0;
  EXPECT_EQ(zeros, 6) << abaqus_name(type);
  EXPECT_GT(lambda(0), -tol);
  EXPECT_GT(lambda(6), 1e-6 * lambda(lambda.size() - 1)) << "spurious near-zero-energy mode";
}

// Exact volume of the distorted element: a tetrahedron |det| / 6; a wedge with its three corner
// columns split into 3 tetrahedra (exact for a wedge whose side faces are planar).
double tet_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  const Eigen::Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

TEST_P(Simplex, VolumeAndTotalMassAreExact) {
  const ElementType type = GetParam();
  Eigen::Matrix3Xd x = distorted_element(type, 17);
  double exact = 0.0;
  if (family(type) == ElementFamily::tetrahedron) {
    exact = tet_volume(x.col(0), x.col(1), x.col(2), x.col(3));
  } else {
    // A frustum of a triangular pyramid (planar side faces): top = apex + ½ (bottom − apex).
    const Eigen::Vector3d apex(0.4, 0.3, 2.2);
    for (int k = 0; k < 3; ++k) x.col(k + 3) = apex + 0.5 * (x.col(k) - apex);
    const auto edges = edge_corners(type);
    for (int k = 6; k < node_count(type); ++k)
      x.col(k) = 0.5 * (x.col(edges[static_cast<std::size_t>(k - 6)][0]) +
                        x.col(edges[static_cast<std::size_t>(k - 6)][1]));
    exact = (1.0 - 0.125) * tet_volume(x.col(0), x.col(1), x.col(2), apex);
  }
  const Material material = steel();
  const ElementMatrices e = element_matrices(type, x, material);
  EXPECT_NEAR(e.volume, exact, 1e-14 * exact) << abaqus_name(type);
  // Σ_ab M_(3a,3b) = ρ V for each direction (partition of unity).
  for (int d = 0; d < 3; ++d) {
    double total = 0.0;
    for (int a = 0; a < node_count(type); ++a)
      for (int b = 0; b < node_count(type); ++b) total += e.mass(3 * a + d, 3 * b + d);
    EXPECT_NEAR(total, material.density * exact, 1e-12 * material.density * exact);
  }
  // Mesh checks' volume agrees.
  Mesh mesh;
  mesh.coordinates = x;
  mesh.parts = {"p"};
  Element element;
  element.type = type;
  for (int a = 0; a < node_count(type); ++a) element.nodes[static_cast<std::size_t>(a)] = a;
  mesh.elements = {element};
  mesh.element_ids = {1};
  for (int a = 0; a < node_count(type); ++a) mesh.node_ids.push_back(a + 1);
  EXPECT_NEAR(element_volume(mesh, 0), exact, 1e-14 * exact);
  EXPECT_TRUE(check_mesh(mesh).empty());
}

TEST_P(Simplex, InvertedElementIsRejectedAndReported) {
  const ElementType type = GetParam();
  Eigen::Matrix3Xd x = distorted_element(type, 23);
  x.row(2) *= -1.0;  // mirror: negative det J everywhere
  EXPECT_THROW((void)element_matrices(type, x, steel()), std::invalid_argument);
  Mesh mesh;
  mesh.coordinates = x;
  mesh.parts = {"p"};
  Element element;
  element.type = type;
  for (int a = 0; a < node_count(type); ++a) element.nodes[static_cast<std::size_t>(a)] = a;
  mesh.elements = {element};
  mesh.element_ids = {7};
  for (int a = 0; a < node_count(type); ++a) mesh.node_ids.push_back(a + 1);
  const auto problems = check_mesh(mesh);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].kind, MeshProblem::Kind::inverted_element);
  EXPECT_NE(problems[0].message.find(abaqus_name(type)), std::string::npos);
}

TEST_P(Simplex, FacesHaveOutwardNormalsAndMidEdgeNodesBetweenTheirCorners) {
  const ElementType type = GetParam();
  const Eigen::Matrix3Xd x = distorted_element(type, 29);
  const Eigen::Vector3d centroid = x.leftCols(corner_count(type)).rowwise().mean();
  for (int f = 0; f < face_count(type); ++f) {
    const auto local = face_local_nodes(type, f);
    const int corners = face_corner_count(type, f);
    ASSERT_EQ(static_cast<int>(local.size()), is_quadratic(type) ? 2 * corners : corners);
    Eigen::Vector3d normal = Eigen::Vector3d::Zero(), centre = Eigen::Vector3d::Zero();
    for (int k = 0; k < corners; ++k) {
      const Eigen::Vector3d p = x.col(local[static_cast<std::size_t>(k)]);
      const Eigen::Vector3d q = x.col(local[static_cast<std::size_t>((k + 1) % corners)]);
      normal += p.cross(q);  // twice the vector area
      centre += p / corners;
    }
    EXPECT_GT(normal.dot(centre - centroid), 0.0) << abaqus_name(type) << " S" << f + 1;
    for (int k = 0; is_quadratic(type) && k < corners; ++k) {
      const Eigen::Vector3d mid = 0.5 * (x.col(local[static_cast<std::size_t>(k)]) +
                                         x.col(local[static_cast<std::size_t>((k + 1) % corners)]));
      EXPECT_LT((x.col(local[static_cast<std::size_t>(corners + k)]) - mid).norm(), 1e-14);
    }
  }
}

TEST_P(Simplex, PatchTestOnADistortedBoxMesh) {
  const ElementType type = GetParam();
  const std::array<int, 3> divisions = {3, 3, 3};
  Mesh mesh = box_of(type, {1.0, 0.8, 1.2}, divisions);
  distort_mesh(mesh, divisions, 0.15, 41);
  ASSERT_TRUE(check_mesh(mesh).empty());
  const testing::PatchResult r = patch_test(mesh, steel());
  EXPECT_LT(r.displacement_error, 1e-10) << abaqus_name(type);
  EXPECT_LT(r.stress_error, 1e-9) << abaqus_name(type);
}

TEST_P(Simplex, BoxMeshIsConformingWithOutwardSideSurfaces) {
  const ElementType type = GetParam();
  const Mesh mesh = box_of(type, {2.0, 1.0, 0.5}, {2, 3, 2});
  EXPECT_TRUE(check_mesh(mesh).empty());
  EXPECT_EQ(connected_components(mesh).size(), 1u);
  double volume = 0.0;
  for (int e = 0; e < mesh.num_elements(); ++e) volume += element_volume(mesh, e);
  EXPECT_NEAR(volume, 1.0, 1e-13);
  EXPECT_EQ(mesh.num_elements(), 12 * (family(type) == ElementFamily::tetrahedron ? 6 : 2));
  // Each side: the faces' vector areas add up to area × outward unit normal.
  const std::map<std::string, Eigen::Vector3d> sides = {
      {"box.xmin", {-0.5, 0, 0}}, {"box.xmax", {0.5, 0, 0}}, {"box.ymin", {0, -1, 0}},
      {"box.ymax", {0, 1, 0}},    {"box.zmin", {0, 0, -2}},  {"box.zmax", {0, 0, 2}}};
  for (const auto& [name, expected] : sides) {
    Eigen::Vector3d area = Eigen::Vector3d::Zero();
    for (const Face& face : mesh.surfaces.at(name)) {
      const std::vector<int> nodes = face_nodes(mesh, face);
      const int corners = face_corner_count(type, face.face);
      for (int k = 0; k < corners; ++k)
        area += 0.5 * mesh.coordinates.col(nodes[static_cast<std::size_t>(k)])
                          .cross(mesh.coordinates.col(nodes[static_cast<std::size_t>((k + 1) % corners)]));
    }
    EXPECT_LT((area - expected).norm(), 1e-13) << name;
  }
  // Conforming: every face is shared by two elements or lies on one of the sides.
  std::map<std::vector<int>, int> uses;
  for (int e = 0; e < mesh.num_elements(); ++e)
    for (int f = 0; f < face_count(type); ++f) {
      std::vector<int> key = face_nodes(mesh, {e, f});
      std::sort(key.begin(), key.end());
      ++uses[key];
    }
  std::size_t boundary = 0;
  for (const auto& [key, count] : uses) {
    EXPECT_LE(count, 2);
    boundary += count == 1 ? 1 : 0;
  }
  std::size_t on_sides = 0;
  for (const auto& [name, expected] : sides) on_sides += mesh.surfaces.at(name).size();
  EXPECT_EQ(boundary, on_sides);
  // The corner lattice 3 × 4 × 3; quadratic types add one node per edge.
  if (!is_quadratic(type)) {
    EXPECT_EQ(mesh.num_nodes(), 3 * 4 * 3);
  }
}

TEST_P(Simplex, CentreStrainOfALinearFieldIsExact) {
  const ElementType type = GetParam();
  const Eigen::Matrix3Xd x = distorted_element(type, 31);
  Eigen::Matrix3d h;
  h << 1, 2, 3, 4, 5, 6, 7, 8, 10;
  h *= 1e-4;
  const Eigen::Matrix3Xd u = h * x;
  const Eigen::VectorXd ue = Eigen::Map<const Eigen::VectorXd>(u.data(), u.size());
  const Vector6d e = element_centre_strain(type, x, ue);
  Vector6d expected;
  expected << h(0, 0), h(1, 1), h(2, 2), h(0, 1) + h(1, 0), h(1, 2) + h(2, 1), h(2, 0) + h(0, 2);
  EXPECT_LT((e - expected).cwiseAbs().maxCoeff(), 1e-15);
}

INSTANTIATE_TEST_SUITE_P(Types, Simplex, ::testing::ValuesIn(kElementTypes),
                         [](const auto& p) { return std::string(abaqus_name(p.param)); });

// ∫ ξ^i η^j ζ^k over the reference tetrahedron = i! j! k! / (i + j + k + 3)!.
double tet_monomial(int i, int j, int k) {
  return std::tgamma(i + 1) * std::tgamma(j + 1) * std::tgamma(k + 1) / std::tgamma(i + j + k + 4);
}

TEST(SimplexRules, TetrahedronRulesAreExactToTheirDegree) {
  for (const auto& [points, degree] : {std::pair{1, 1}, std::pair{4, 2}, std::pair{14, 5}}) {
    const auto& rule = tet_rule(points);
    ASSERT_EQ(static_cast<int>(rule.size()), points);
    for (int i = 0; i <= degree; ++i)
      for (int j = 0; i + j <= degree; ++j)
        for (int k = 0; i + j + k <= degree; ++k) {
          double q = 0.0;
          for (const GaussPoint& p : rule)
            q += p.weight * std::pow(p.xi(0), i) * std::pow(p.xi(1), j) * std::pow(p.xi(2), k);
          EXPECT_NEAR(q, tet_monomial(i, j, k), 1e-15) << points << ": " << i << j << k;
        }
    if (points == 4) {  // and not exact one degree higher (the claim above is tight)
      double q = 0.0;
      for (const GaussPoint& p : rule) q += p.weight * std::pow(p.xi(0), 3);
      EXPECT_GT(std::abs(q - tet_monomial(3, 0, 0)), 1e-6);
    }
  }
}

TEST(SimplexRules, TriangleRulesAreExactToTheirDegree) {
  // ∫ ξ^i η^j over the reference triangle = i! j! / (i + j + 2)!.
  for (const auto& [points, degree] : {std::pair{1, 1}, std::pair{3, 2}, std::pair{7, 5}}) {
    for (int i = 0; i <= degree; ++i)
      for (int j = 0; i + j <= degree; ++j) {
        double q = 0.0;
        for (const GaussPoint& p : triangle_rule(points))
          q += p.weight * std::pow(p.xi(0), i) * std::pow(p.xi(1), j);
        EXPECT_NEAR(q, std::tgamma(i + 1) * std::tgamma(j + 1) / std::tgamma(i + j + 3), 1e-15)
            << points << ": " << i << j;
      }
  }
  double weights = 0.0;
  for (const GaussPoint& p : wedge_rule(7, 3)) weights += p.weight;
  EXPECT_NEAR(weights, 1.0, 1e-15);
  EXPECT_EQ(wedge_rule(3, 2).size(), 6u);
}

TEST(SimplexRules, HexahedronRulesOfOtherFamiliesAreRefused) {
  EXPECT_THROW((void)stiffness_rule(ElementType::tet10), std::invalid_argument);
  EXPECT_THROW((void)mass_rule(ElementType::wedge6), std::invalid_argument);
  EXPECT_THROW((void)face_node_count(ElementType::wedge15), std::invalid_argument);
  EXPECT_EQ(stiffness_rule(ElementType::hex20), 3);
  EXPECT_EQ(face_node_count(ElementType::wedge15, 0), 6);
  EXPECT_EQ(face_node_count(ElementType::wedge15, 2), 8);
  EXPECT_EQ(face_node_count(ElementType::tet10, 3), 6);
  EXPECT_THROW((void)face_local_nodes(ElementType::tet4, 4), std::out_of_range);
  EXPECT_THROW((void)face_local_nodes(ElementType::wedge6, 5), std::out_of_range);
}

// Mesh convergence of the first axial frequency of a free-free bar (ν = 0, closed form):
// linear elements converge as h², quadratic ones as h⁴ (Strang & Fix, §6.3: eigenvalue error
// O(h^{2p})).
struct RateCase {
  ElementType type;
  int coarse;
  double rate;
};

class AxialConvergence : public ::testing::TestWithParam<RateCase> {};

TEST_P(AxialConvergence, ObservedRateMatchesTheOrder) {
  const RateCase c = GetParam();
  const double e1 = axial_frequency(c.type, c.coarse).relative_error();
  const double e2 = axial_frequency(c.type, 2 * c.coarse).relative_error();
  const double rate = std::log2(e1 / e2);
  EXPECT_NEAR(rate, c.rate, 0.15) << abaqus_name(c.type) << " errors " << e1 << " " << e2;
  EXPECT_LT(e2, c.rate == 2.0 ? 0.02 : 1e-4) << abaqus_name(c.type);
}

INSTANTIATE_TEST_SUITE_P(Types, AxialConvergence,
                         ::testing::Values(RateCase{ElementType::tet4, 4, 2.0},
                                           RateCase{ElementType::tet10, 8, 4.0},
                                           RateCase{ElementType::wedge6, 4, 2.0},
                                           RateCase{ElementType::wedge15, 8, 4.0}),
                         [](const auto& p) { return std::string(abaqus_name(p.param.type)); });

}  // namespace
}  // namespace jointhb::fe
