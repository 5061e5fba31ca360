#include "jointhb/fe/gmsh_reader.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <Eigen/Dense>
#include <string>

#include "jointhb/fe/mesh_checks.hpp"
#include "jointhb/fe/mesh_file_error.hpp"
#include "unit/io/temp_file.hpp"

namespace jointhb::fe {
namespace {

using io::testing::TempFile;

// The unit cube as one 8-node hexahedron (node tags 11-18, element tag 7) in physical volume
// "block", with its top face as quadrangle 3 in physical surface "top" (MSH 4.1, hand-written).
const char* const kCubeHex8 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 5 "top"
3 1 "block"
$EndPhysicalNames
$Entities
0 0 1 1
6 0 0 1 1 1 1 1 5 0
1 0 0 0 1 1 1 1 1 0
$EndEntities
$Nodes
2 8 11 18
3 1 0 4
11
12
13
14
0 0 0
1 0 0
1 1 0
0 1 0
2 6 0 4
15
16
17
18
0 0 1
1 0 1
1 1 1
0 1 1
$EndNodes
$Elements
2 2 3 7
2 6 3 1
3 16 17 18 15
3 1 5 1
7 11 12 13 14 15 16 17 18
$EndElements
)";

// The cube [0, 2]³ as one 20-node hexahedron in Gmsh's node order: corners as Abaqus', mid-edge
// nodes 8-19 on the edges 0-1, 0-3, 0-4, 1-2, 1-5, 2-3, 2-6, 3-7, 4-5, 4-7, 5-6, 6-7 (Gmsh
// manual, "Node ordering"). Node tag = Gmsh local index + 1. The bottom face is an 8-node
// quadrangle of the unnamed physical surface 9; the volume is in no physical group.
const char* const kCubeHex20 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 1 1
1 0 0 0 2 2 0 1 9 0
1 0 0 0 2 2 2 0 0
$EndEntities
$Nodes
1 20 1 20
3 1 0 20
1
2
3
4
5
6
7
8
9
10
11
12
13
14
15
16
17
18
19
20
0 0 0
2 0 0
2 2 0
0 2 0
0 0 2
2 0 2
2 2 2
0 2 2
1 0 0
0 1 0
0 0 1
2 1 0
2 0 1
1 2 0
2 2 1
0 2 1
1 0 2
0 1 2
2 1 2
1 2 2
$EndNodes
$Elements
2 2 1 2
2 1 16 1
2 1 4 3 2 10 14 12 9
3 1 17 1
1 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20
$EndElements
)";

::testing::AssertionResult msh_reports(const std::string& contents, int line, const std::string& text) {
  const TempFile file(".msh", contents);
  std::string message;
  try {
    (void)read_gmsh(file.path());
    return ::testing::AssertionFailure() << "no exception";
  } catch (const MeshFileError& e) {
    message = e.what();
  }
  const std::string position =
      line > 0 ? fmt::format("{}:{}: ", file.path().string(), line) : file.path().string() + ": ";
  if (message.rfind(position, 0) != 0 || message.find(text) == std::string::npos) {
    return ::testing::AssertionFailure() << "got: " << message;
  }
  return ::testing::AssertionSuccess();
}

// `text` with the first occurrence of `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(GmshReader, ReadsAHex8CubeWithPhysicalVolumeAndSurface) {
  const TempFile file(".msh", kCubeHex8);
  const Mesh mesh = read_gmsh(file.path());
  ASSERT_EQ(mesh.num_nodes(), 8);
  ASSERT_EQ(mesh.num_elements(), 1);
  EXPECT_EQ(mesh.node_ids, (std::vector<long>{11, 12, 13, 14, 15, 16, 17, 18}));
  EXPECT_EQ(mesh.element_ids, std::vector<long>{7});
  EXPECT_EQ(mesh.parts, std::vector<std::string>{"block"});
  EXPECT_EQ(mesh.element_sets.at("block"), std::vector<int>{0});
  EXPECT_EQ(mesh.elements[0].type, ElementType::hex8_incompatible);
  EXPECT_EQ(mesh.surfaces.at("top"), (std::vector<Face>{{0, 1}}));  // S2, the face ζ = +1
  EXPECT_EQ(mesh.node_sets.at("top"), (std::vector<int>{4, 5, 6, 7}));
  EXPECT_NEAR(element_volume(mesh, 0), 1.0, 1e-15);
  EXPECT_TRUE(check_mesh(mesh).empty());

  GmshOptions options;
  options.hex8_type = ElementType::hex8;
  EXPECT_EQ(read_gmsh(file.path(), options).elements[0].type, ElementType::hex8);
  options.hex8_type = ElementType::hex20;
  EXPECT_THROW((void)read_gmsh(file.path(), options), std::invalid_argument);
}

TEST(GmshReader, ReordersHex20MidEdgeNodesToAbaqus) {
  const TempFile file(".msh", kCubeHex20);
  const Mesh mesh = read_gmsh(file.path());
  ASSERT_EQ(mesh.num_elements(), 1);
  EXPECT_EQ(mesh.parts, std::vector<std::string>{"default"});
  EXPECT_EQ(mesh.elements[0].type, ElementType::hex20);
  // Abaqus mid-edge node 8 + k lies halfway between these corners (mesh.hpp).
  const auto& edges = hex_edge_corners();
  const auto& nodes = mesh.elements[0].nodes;
  for (std::size_t k = 0; k < 12; ++k) {
    const Eigen::Vector3d a = mesh.coordinates.col(nodes[static_cast<std::size_t>(edges[k][0])]);
    const Eigen::Vector3d b = mesh.coordinates.col(nodes[static_cast<std::size_t>(edges[k][1])]);
    EXPECT_EQ(mesh.coordinates.col(nodes[8 + k]), 0.5 * (a + b)) << "Abaqus node " << 8 + k;
  }
  EXPECT_NEAR(jacobian_ratio(mesh, 0), 1.0, 1e-14);
  EXPECT_NEAR(element_volume(mesh, 0), 8.0, 1e-13);
  EXPECT_TRUE(check_mesh(mesh).empty());
  EXPECT_EQ(mesh.surfaces.at("surface_9"), (std::vector<Face>{{0, 0}}));  // S1, the face ζ = -1
  EXPECT_EQ(mesh.node_sets.at("surface_9").size(), 8u);

  GmshOptions options;
  options.hex20_type = ElementType::hex20_reduced;
  EXPECT_EQ(read_gmsh(file.path(), options).elements[0].type, ElementType::hex20_reduced);
}

TEST(GmshReader, RefusesOtherFormatsByName) {
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "4.1 0 8", "2.2 0 8"), 2, "MSH version 2.2"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "4.1 0 8", "4.1 1 8"), 2, "binary MSH files"));
  EXPECT_TRUE(msh_reports("$Nodes\n$EndNodes\n", 1, "first section must be $MeshFormat"));
  EXPECT_TRUE(msh_reports("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PartitionedEntities\n", 4,
                      "partitioned meshes"));
}

TEST(GmshReader, RefusesPyramidsAndCompleteQuadraticElementsAndStrayQuadrangles) {
  // kCubeHex8: node tags 15-18 on lines 26-29; surface block header 37, its quadrangle 38;
  // volume block header 39, its hexahedron 40.
  EXPECT_TRUE(msh_reports(replaced(replaced(kCubeHex8, "3 1 5 1\n", "3 1 7 1\n"),
                               "7 11 12 13 14 15 16 17 18", "7 11 12 13 14 15"),
                      39, "type 7 (5-node pyramid) in volume 1 is not supported"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "3 1 5 1\n", "3 1 13 1\n"), 39, "18-node prism"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "3 16 17 18 15", "3 11 12 17 18"), 38,
                      "quadrangle 3 of physical surface 'top' is not a face of any volume "
                      "element"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "2 6 3 1\n", "2 6 1 1\n"), 37,
                      "type 1 (2-node line) in physical surface 'top'"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "2 6 3 1\n", "2 6 2 1\n"), 38,
                      "element 3 (type 2 (3-node triangle)) has 4 nodes"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "7 11 12 13 14 15 16 17 18", "7 11 12 13 14 15 16 17 99"),
                      40, "element 7: unknown node 99"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "7 11 12 13 14 15 16 17 18", "7 11 12 13 14 15 16 17"),
                      40, "element 7 (type 5 (8-node hexahedron)) has 7 nodes"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "15\n16\n", "12\n16\n"), 26,
                      "node 12 defined twice (first at line 18)"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "1 1 1 1 1 0\n$End", "1 1 1 2 1 2 0\n$End"), 39,
                      "volume 1 is in the physical volumes 'block' and 'volume_2'"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "0 1 0\n2 6", "0 x 0\n2 6"), 24, "'x' is not a finite"));
  EXPECT_TRUE(
      msh_reports(replaced(kCubeHex8, "$EndElements\n", ""), 40, "file ends where $EndElements"));
}

TEST(GmshReader, RefusesHeadersThatDisagreeWithTheirBlocks) {
  // Issue 20, item 7: a $Nodes header claiming more nodes than its blocks hold was accepted.
  // kCubeHex8: the $Nodes header on line 15, the $Elements header on line 36.
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "$Nodes\n2 8 11 18", "$Nodes\n2 100 11 18"), 15,
                      "the $Nodes header declares 100 nodes, its 2 blocks hold 8"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "$Nodes\n2 8 11 18", "$Nodes\n2 7 11 18"), 15,
                      "declares 7 nodes, its 2 blocks hold 8"));
  EXPECT_TRUE(msh_reports(replaced(kCubeHex8, "$Elements\n2 2 3 7", "$Elements\n2 5 3 7"), 36,
                      "the $Elements header declares 5 elements, its 2 blocks hold 2"));
}

TEST(GmshReader, SkipsUnknownSectionsAndLowerDimensionalElements) {
  const std::string extra = replaced(
      replaced(kCubeHex8, "$Nodes\n", "$Comments\nanything at all\n$EndComments\n$Nodes\n"),
      "2 2 3 7\n", "3 3 1 7\n1 1 1 1\n1 11 12\n");
  const TempFile file(".msh", extra);
  const Mesh mesh = read_gmsh(file.path());
  EXPECT_EQ(mesh.num_elements(), 1);
  EXPECT_EQ(mesh.surfaces.at("top").size(), 1u);
}

}  // namespace
}  // namespace jointhb::fe
