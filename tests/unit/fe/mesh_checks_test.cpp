#include "jointhb/fe/mesh_checks.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <stdexcept>
#include <utility>

#include "jointhb/fe/box_mesh.hpp"

namespace jointhb::fe {
namespace {

Mesh unit_cube(ElementType type) {
  BoxOptions options;
  options.type = type;
  return box_mesh(options);
}

bool has(const std::vector<MeshProblem>& problems, MeshProblem::Kind kind,
         const std::string& text) {
  for (const MeshProblem& p : problems)
    if (p.kind == kind && p.message.find(text) != std::string::npos) return true;
  return false;
}

std::string all(const std::vector<MeshProblem>& problems) {
  std::string text;
  for (const MeshProblem& p : problems) text += p.message + "\n";
  return text;
}

TEST(MeshChecks, RegularElementsPass) {
  for (ElementType type : {ElementType::hex8, ElementType::hex20}) {
    const Mesh mesh = unit_cube(type);
    EXPECT_TRUE(check_mesh(mesh).empty()) << all(check_mesh(mesh));
    EXPECT_NEAR(jacobian_ratio(mesh, 0), 1.0, 1e-14);
  }
}

TEST(MeshChecks, MirroredNodeOrderIsInverted) {
  for (ElementType type : {ElementType::hex8, ElementType::hex20}) {
    Mesh mesh = unit_cube(type);
    mesh.element_ids = {41};
    auto& n = mesh.elements[0].nodes;
    // Swap the bottom and top faces (corners 0-3 with 4-7, and for hex20 mid-edges 8-11 with
    // 12-15): the same cube, numbered with the wrong handedness.
    for (std::size_t a = 0; a < 4; ++a) std::swap(n[a], n[a + 4]);
    if (type == ElementType::hex20)
      for (std::size_t a = 8; a < 12; ++a) std::swap(n[a], n[a + 4]);
    const auto problems = check_mesh(mesh);
    ASSERT_EQ(problems.size(), 1u) << all(problems);
    EXPECT_EQ(problems[0].kind, MeshProblem::Kind::inverted_element);
    EXPECT_EQ(problems[0].element, 0);
    EXPECT_NE(problems[0].message.find("element 41"), std::string::npos) << problems[0].message;
    EXPECT_NE(problems[0].message.find("ratio -1"), std::string::npos) << problems[0].message;
    EXPECT_NEAR(jacobian_ratio(mesh, 0), -1.0, 1e-14);
  }
}

TEST(MeshChecks, CornerPushedThroughIsInverted) {
  Mesh mesh = unit_cube(ElementType::hex8);
  // Corner 6, at (1, 1, 1), pulled inside past the centre: det J < 0 at that corner.
  mesh.coordinates.col(mesh.elements[0].nodes[6]) = Eigen::Vector3d(0.2, 0.2, 0.2);
  const auto problems = check_mesh(mesh);
  EXPECT_TRUE(has(problems, MeshProblem::Kind::inverted_element, "element 1")) << all(problems);
}

TEST(MeshChecks, CollapsedAndFlatElementsAreDegenerate) {
  Mesh collapsed = unit_cube(ElementType::hex8);
  // Corner 6 moved onto corner 2: the edge 2-6 has zero length, det J = 0 at both corners.
  collapsed.coordinates.col(collapsed.elements[0].nodes[6]) =
      collapsed.coordinates.col(collapsed.elements[0].nodes[2]);
  auto problems = check_mesh(collapsed);
  EXPECT_TRUE(has(problems, MeshProblem::Kind::degenerate_element, "element 1")) << all(problems);

  Mesh flat = unit_cube(ElementType::hex20);
  flat.coordinates.row(2).setZero();  // every node in the plane z = 0
  problems = check_mesh(flat);
  EXPECT_TRUE(has(problems, MeshProblem::Kind::degenerate_element, "degenerate")) << all(problems);
}

TEST(MeshChecks, RepeatedAndOutOfRangeNodesAreNamed) {
  Mesh mesh = unit_cube(ElementType::hex8);
  mesh.node_ids = {101, 102, 103, 104, 105, 106, 107, 108};
  mesh.elements[0].nodes[5] = mesh.elements[0].nodes[1];
  auto problems = check_mesh(mesh);
  EXPECT_TRUE(has(problems, MeshProblem::Kind::repeated_node, "node 102 appears twice"))
      << all(problems);

  mesh = unit_cube(ElementType::hex8);
  mesh.elements[0].nodes[7] = 8;
  problems = check_mesh(mesh);
  EXPECT_TRUE(has(problems, MeshProblem::Kind::node_out_of_range, "index 8 outside [0, 8)"))
      << all(problems);
  EXPECT_THROW((void)connected_components(mesh), std::invalid_argument);
}

TEST(MeshChecks, BadPartsSetsAndIdsAreReported) {
  Mesh mesh = unit_cube(ElementType::hex8);
  mesh.elements[0].part = 3;
  mesh.node_sets["ghost"] = {42};
  mesh.surfaces["box.zmax"].push_back({0, 6});
  mesh.element_ids.clear();
  const auto problems = check_mesh(mesh);
  EXPECT_TRUE(has(problems, MeshProblem::Kind::bad_part, "part index 3")) << all(problems);
  EXPECT_TRUE(has(problems, MeshProblem::Kind::bad_set, "node set 'ghost'")) << all(problems);
  EXPECT_TRUE(has(problems, MeshProblem::Kind::bad_set, "surface 'box.zmax'")) << all(problems);
  EXPECT_TRUE(has(problems, MeshProblem::Kind::inconsistent_sizes, "0 element ids"))
      << all(problems);
}

TEST(MeshChecks, VolumeOfAParallelepipedIsExact) {
  // x ↦ A x maps the unit cube to a parallelepiped of volume det A, for hex8 and hex20 alike.
  Eigen::Matrix3d a;
  a << 2.0, 0.3, 0.1, -0.2, 1.5, 0.4, 0.0, 0.25, 0.8;
  for (ElementType type : {ElementType::hex8_incompatible, ElementType::hex20_reduced}) {
    Mesh mesh = unit_cube(type);
    mesh.coordinates = a * mesh.coordinates;
    EXPECT_NEAR(element_volume(mesh, 0), a.determinant(), 1e-14) << abaqus_name(type);
    EXPECT_NEAR(jacobian_ratio(mesh, 0), 1.0, 1e-14);
  }
}

TEST(MeshChecks, CurvedHex20VolumeIsIntegratedExactly) {
  // Mid-edge node 9 (edge 1-2, on the face x = 1) pushed out by h along x. With J₀ = ½ I,
  // det J = det(J₀ + h e_x ∇N₉ᵀ) = ⅛ (1 + 2h ∂N₉/∂ξ) exactly (rank-one update), so the volume
  // grows by (h/4) ∫∫ N₉(ξ = 1) dη dζ with N₉(1, η, ζ) = ½ (1 - η²)(1 - ζ): (h/4) · 4/3 = h/3.
  Mesh mesh = unit_cube(ElementType::hex20);
  const double h = 0.1;
  mesh.coordinates(0, mesh.elements[0].nodes[9]) += h;
  EXPECT_NEAR(element_volume(mesh, 0), 1.0 + h / 3.0, 1e-14);
  EXPECT_TRUE(check_mesh(mesh).empty());
}

TEST(MeshChecks, ConnectedComponentsFollowSharedNodes) {
  BoxOptions options;
  options.divisions = {3, 1, 1};
  Mesh mesh = box_mesh(options);
  EXPECT_EQ(connected_components(mesh).size(), 1u);
  // Give the middle element its own copies of the nodes it shares: three components.
  Element& middle = mesh.elements[1];
  for (std::size_t a = 0; a < 8; ++a) {
    int& n = middle.nodes[a];
    const Eigen::Vector3d x = mesh.coordinates.col(n);
    mesh.coordinates.conservativeResize(Eigen::NoChange, mesh.num_nodes() + 1);
    mesh.coordinates.col(mesh.num_nodes() - 1) = x;
    n = mesh.num_nodes() - 1;
  }
  const auto components = connected_components(mesh);
  ASSERT_EQ(components.size(), 3u);
  EXPECT_EQ(components[1], std::vector<int>{1});
}

TEST(MeshChecks, InvalidOptionsThrow) {
  MeshCheckOptions options;
  options.min_jacobian_ratio = 0.0;
  EXPECT_THROW((void)check_mesh(unit_cube(ElementType::hex8), options), std::invalid_argument);
}

}  // namespace
}  // namespace jointhb::fe
