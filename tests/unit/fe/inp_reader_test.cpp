#include "jointhb/fe/inp_reader.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <string>

#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/fe/mesh_checks.hpp"
#include "jointhb/fe/mesh_file_error.hpp"
#include "unit/fe/inp_reports.hpp"
#include "unit/io/temp_file.hpp"

namespace jointhb::fe {
namespace {

using io::testing::TempFile;
using testing::inp_reports;

// Two C3D8 elements side by side along x (nodes 1-12), with sets, a surface and cards to skip.
const char* const kTwoBricks = R"(*HEADING
two bricks
** a comment line
*NODE, NSET=ALLNODES
1, 0., 0., 0.
2, 1., 0., 0.
3, 1., 1., 0.
4, 0., 1., 0.
5, 0., 0., 1.
6, 1., 0., 1.
7, 1., 1., 1.
8, 0., 1., 1.
9, 2., 0., 0.
10, 2., 1., 0.
11, 2., 0., 1.D0
12, 2., 1., 1.0e0

*ELEMENT, TYPE=C3D8I, ELSET=Block
1, 1, 2, 3, 4, 5, 6, 7, 8
2, 2, 9, 10, 3, 6, 11, 12, 7
*Nset, nset=Left, generate
1, 5, 4
*NSET, NSET=left
8, 4
*Elset, elset=Right
2
*Surface, type=ELEMENT, name=Top
block, S2
*Surface, name=Right_End
Right, s4
*Material, name=Steel
*Elastic
210e9, 0.3
*Density
7800.
*Solid Section, elset=Block, material=Steel
*STEP
*STATIC
*BOUNDARY
Left, 1, 3
*END STEP
)";

std::string message_of(const std::string& contents) {
  const TempFile file(".inp", contents);
  try {
    (void)read_inp(file.path());
  } catch (const MeshFileError& e) {
    return e.what();
  }
  return "no exception";
}

TEST(InpReader, ReadsNodesElementsSetsAndSurfaces) {
  const TempFile file(".inp", kTwoBricks);
  const InpResult result = read_inp(file.path());
  const Mesh& mesh = result.mesh;
  ASSERT_EQ(mesh.num_nodes(), 12);
  ASSERT_EQ(mesh.num_elements(), 2);
  EXPECT_EQ(mesh.node_ids[8], 9);
  EXPECT_EQ(mesh.coordinates.col(10), Eigen::Vector3d(2.0, 0.0, 1.0));
  EXPECT_EQ(mesh.coordinates.col(11), Eigen::Vector3d(2.0, 1.0, 1.0));
  EXPECT_EQ(mesh.parts, std::vector<std::string>{"Block"});
  EXPECT_EQ(mesh.elements[1].type, ElementType::hex8_incompatible);
  EXPECT_EQ(mesh.elements[1].nodes[1], 8);  // node 9
  EXPECT_EQ(mesh.element_sets.at("Block"), (std::vector<int>{0, 1}));
  EXPECT_EQ(mesh.element_sets.at("Right"), std::vector<int>{1});
  // "Left" by GENERATE (1, 5), extended by "left" (8, 4): one set, first spelling kept.
  EXPECT_EQ(mesh.node_sets.at("Left"), (std::vector<int>{0, 3, 4, 7}));
  EXPECT_EQ(mesh.node_sets.at("ALLNODES").size(), 12u);
  EXPECT_EQ(mesh.surfaces.at("Top"), (std::vector<Face>{{0, 1}, {1, 1}}));
  EXPECT_EQ(mesh.surfaces.at("Right_End"), (std::vector<Face>{{1, 3}}));
  EXPECT_TRUE(check_mesh(mesh).empty());

  std::vector<std::string> ignored;
  for (const IgnoredCard& card : result.ignored_cards) {
    ignored.push_back(fmt::format("{}@{}", card.keyword, card.line));
  }
  EXPECT_EQ(ignored, (std::vector<std::string>{"*HEADING@1", "*STEP@37", "*STATIC@38",
                                               "*END STEP@41"}));
  // The physics cards: the section's material for the part, the *BOUNDARY on set Left.
  ASSERT_EQ(result.part_materials.size(), 1u);
  ASSERT_TRUE(result.part_materials[0].has_value());
  EXPECT_EQ(result.part_materials[0]->name, "Steel");
  EXPECT_EQ(result.part_materials[0]->youngs_modulus, 210e9);
  EXPECT_EQ(result.part_materials[0]->density, 7800.0);
  ASSERT_EQ(result.constraints.size(), 1u);
  EXPECT_EQ(result.constraints[0].nodes, (std::vector<int>{0, 3, 4, 7}));
  EXPECT_EQ(result.constraint_labels[0], file.path().string() + ":40");
}

// A hex20 box written as C3D20R with each element's 20 nodes over `per_line`-entry lines.
std::string hex20_inp(const Mesh& mesh, int per_line) {
  std::string text = "*NODE\n";
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    text +=
        fmt::format("{}, {:.17g}, {:.17g}, {:.17g}\n", mesh.node_ids[static_cast<std::size_t>(n)],
                    mesh.coordinates(0, n), mesh.coordinates(1, n), mesh.coordinates(2, n));
  }
  text += "*ELEMENT, TYPE=C3D20R, ELSET=EALL\n";
  for (int e = 0; e < mesh.num_elements(); ++e) {
    std::vector<long> entries = {mesh.element_ids[static_cast<std::size_t>(e)]};
    for (int n : mesh.elements[static_cast<std::size_t>(e)].node_span()) {
      entries.push_back(mesh.node_ids[static_cast<std::size_t>(n)]);
    }
    for (std::size_t i = 0; i < entries.size(); ++i) {
      text += std::to_string(entries[i]);
      text += i + 1 == entries.size() ? "\n" : ((i + 1) % per_line == 0 ? ",\n" : ", ");
    }
  }
  return text;
}

TEST(InpReader, ReadsHex20ElementsContinuedOverSeveralLines) {
  BoxOptions options;
  options.size = Eigen::Vector3d(0.1, 0.2, 0.3);
  options.divisions = {2, 1, 2};
  options.type = ElementType::hex20_reduced;
  const Mesh box = box_mesh(options);
  for (int per_line : {16, 10, 7}) {  // CalculiX writes 16 + 5; other tools 10 + 11 and others
    const TempFile file(".inp", hex20_inp(box, per_line));
    const Mesh mesh = read_inp(file.path()).mesh;
    ASSERT_EQ(mesh.num_elements(), box.num_elements());
    EXPECT_EQ(mesh.coordinates, box.coordinates);
    for (int e = 0; e < mesh.num_elements(); ++e) {
      const auto& a = mesh.elements[static_cast<std::size_t>(e)];
      const auto& b = box.elements[static_cast<std::size_t>(e)];
      EXPECT_EQ(a.type, ElementType::hex20_reduced);
      EXPECT_EQ(a.nodes, b.nodes) << "element " << e + 1 << ", " << per_line << " per line";
    }
    EXPECT_TRUE(check_mesh(mesh).empty());
  }
}

TEST(InpReader, ReadsASinglePartInstanceAndElementsWithoutElset) {
  const std::string text = R"(*Part, name=Bracket
*Node
      1,           0.,           0.,           0.
      2,           1.,           0.,           0.
      3,           1.,           1.,           0.
      4,           0.,           1.,           0.
      5,           0.,           0.,           1.
      6,           1.,           0.,           1.
      7,           1.,           1.,           1.
      8,           0.,           1.,           1.
*Element, type=C3D8
1, 1, 2, 3, 4, 5, 6, 7, 8
*End Part
*Assembly, name=Assembly
*Instance, name=Bracket-1, part=Bracket
*End Instance
*Nset, nset=Fixed, instance=Bracket-1
 1, 2, 3, 4
*Elset, elset=_Load_S2, internal, instance=Bracket-1
 1,
*Surface, type=ELEMENT, name=Load
_Load_S2, S2
*End Assembly
)";
  const TempFile file(".inp", text);
  const Mesh mesh = read_inp(file.path()).mesh;
  EXPECT_EQ(mesh.parts, std::vector<std::string>{"Bracket"});
  EXPECT_EQ(mesh.elements[0].type, ElementType::hex8);
  EXPECT_EQ(mesh.node_sets.at("Fixed"), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(mesh.surfaces.at("Load"), (std::vector<Face>{{0, 1}}));

  const TempFile flat("-flat.inp",
                      "*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n5,0,0,1\n6,1,0,1\n"
                      "7,1,1,1\n8,0,1,1\n*ELEMENT,TYPE=C3D8I\n1,1,2,3,4,5,6,7,8\n");
  EXPECT_EQ(read_inp(flat.path()).mesh.parts, std::vector<std::string>{"default"});
}

const std::string kNodes =
    "*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n5,0,0,1\n6,1,0,1\n7,1,1,1\n8,0,1,1\n";

TEST(InpReader, ErrorsNameFileLineAndEntity) {
  EXPECT_TRUE(inp_reports(kNodes + "*ELEMENT, TYPE=C3D8\n1, 1, 2, 3, 4, 5, 6, 7, 17\n", 11,
                      "element 1: unknown node 17"));
  EXPECT_TRUE(inp_reports(kNodes + "3, 5, 5, 5\n", 10, "node 3 defined twice (first at line 4)"));
  EXPECT_TRUE(inp_reports(kNodes + "9, 1.0, abc, 0\n", 10, "node 9: coordinate 'abc'"));
  EXPECT_TRUE(inp_reports(kNodes + "*ELEMENT, TYPE=C3D8\n1,1,2,3,4,5,6,7,8\n1,1,2,3,4,5,6,7,8\n", 12,
                      "element 1 defined twice (first at line 11)"));
  EXPECT_TRUE(inp_reports(kNodes + "*ELEMENT, TYPE=C3D20\n1,1,2,3,4,5,6,7,8,\n", 11,
                      "element 1: 8 node numbers, C3D20 needs 20"));
  EXPECT_TRUE(inp_reports(kNodes + "*ELEMENT, TYPE=C3D8\n1,1,2,3,4,5,6,7,8,9\n", 11,
                      "more than 8 node numbers"));
  EXPECT_TRUE(inp_reports(kNodes + "*ELEMENT, TYPE=C3D8\n1,1,2,3,4,5,6,7,x\n", 11,
                      "element 1: 'x' is not an integer"));
}

TEST(InpReader, UnsupportedCardsAndParametersStop) {
  const std::string element = "*ELEMENT, TYPE=C3D8, ELSET=B\n1,1,2,3,4,5,6,7,8\n";
  EXPECT_TRUE(inp_reports(kNodes + "*Element, type=C3D10M\n1, 1, 2, 3, 5\n", 10,
                      "element type C3D10M is not supported"));
  EXPECT_TRUE(inp_reports(kNodes + "*ELEMENT, TYPE=S4\n1, 1, 2, 3, 4\n", 10, "element type S4"));
  EXPECT_TRUE(
      inp_reports("*NODE\n1, 0, 0, 0\n*NGEN, NSET=LINE\n1, 10, 1\n", 3, "card *NGEN is not supported"));
  EXPECT_TRUE(inp_reports("*INCLUDE, INPUT=mesh.inp\n", 1, "card *INCLUDE is not supported"));
  EXPECT_TRUE(inp_reports(kNodes + element + "*SURFACE, NAME=S, TYPE=NODE\n1\n", 12,
                      "TYPE=NODE is not supported"));
  EXPECT_TRUE(
      inp_reports(kNodes + element + "*SURFACE, NAME=S\nNOPE, S1\n", 13, "unknown element set 'NOPE'"));
  EXPECT_TRUE(inp_reports(kNodes + element + "*SURFACE, NAME=S\nB, S7\n", 13,
                      "face label 'S7' is not one of S1..S6"));
  EXPECT_TRUE(inp_reports(kNodes + element + "*SURFACE, NAME=S\nB\n", 13, "got 'B'"));
  EXPECT_TRUE(inp_reports(kNodes + element + "*NSET, NSET=N\n1, 99\n", 13, "unknown node 99"));
  EXPECT_TRUE(
      inp_reports(kNodes + element + "*ELSET, ELSET=E, GENERATE\n1, 3\n", 13, "unknown element 2"));
  EXPECT_TRUE(inp_reports(kNodes + "*NODE, SYSTEM=C\n9, 1, 0, 0\n", 10, "SYSTEM=C is not supported"));
  EXPECT_TRUE(inp_reports(kNodes + "*ELEMENT, TYPE=C3D8, INPUT=e.inp\n", 10,
                      "parameter INPUT of *ELEMENT is not supported"));
  EXPECT_TRUE(inp_reports("1, 0, 0, 0\n", 1, "data line before the first keyword"));
  const std::string no_elements = message_of(kNodes);
  EXPECT_NE(no_elements.find("no elements"), std::string::npos) << no_elements;
}

// An Abaqus/CAE-style deck: one part (a unit cube with a part-level set, surface and section),
// instanced twice, the second translated by (0, 0, 1) and then turned 90° about the z axis;
// boundary conditions and loads at assembly level name "instance.set" and "instance.node".
const std::string kAssembly = R"(*Part, name=Cube
*Node
1, 0., 0., 0.
2, 1., 0., 0.
3, 1., 1., 0.
4, 0., 1., 0.
5, 0., 0., 1.
6, 1., 0., 1.
7, 1., 1., 1.
8, 0., 1., 1.
*Element, type=C3D8
1, 1, 2, 3, 4, 5, 6, 7, 8
*Nset, nset=Bottom
1, 2, 3, 4
*Elset, elset=All
1
*Surface, type=ELEMENT, name=Top
All, S2
*Solid Section, elset=All, material=Steel
,
*End Part
*Assembly, name=Assembly
*Instance, name=Cube-1, part=Cube
*End Instance
*Instance, name=Cube-2, part=Cube
0., 0., 1.
0., 0., 0., 0., 0., 1., 90.
*End Instance
*Nset, nset=Corner, instance=Cube-2
7
*End Assembly
*Material, name=Steel
*Elastic
210e9, 0.3
*Density
7850.
*Step
*Static
*Boundary
Cube-1.Bottom, ENCASTRE
*Cload
Cube-2.5, 1, 10.
Corner, 2, -3.
*Dsload
Cube-2.Top, P, 1e5
*End Step
)";

TEST(InpReader, AssembliesOfTranslatedAndRotatedInstances) {
  const TempFile file(".inp", kAssembly);
  const InpResult r = read_inp(file.path());
  const Mesh& mesh = r.mesh;
  ASSERT_EQ(mesh.num_nodes(), 16);
  EXPECT_EQ(mesh.parts, (std::vector<std::string>{"Cube-1", "Cube-2"}));
  EXPECT_EQ(mesh.elements[1].part, 1);
  // Cube-2: x' = R_z(90°) (x + (0, 0, 1)) = (−y, x, z + 1).
  for (int n = 0; n < 8; ++n) {
    const Eigen::Vector3d x = mesh.coordinates.col(n);
    const Eigen::Vector3d expected(-x.y(), x.x(), x.z() + 1.0);
    EXPECT_LT((mesh.coordinates.col(8 + n) - expected).norm(), 1e-15) << "node " << n + 1;
  }
  EXPECT_EQ(mesh.node_sets.at("Cube-1.Bottom"), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(mesh.node_sets.at("Cube-2.Bottom"), (std::vector<int>{8, 9, 10, 11}));
  EXPECT_EQ(mesh.node_sets.at("Corner"), std::vector<int>{14});
  EXPECT_EQ(mesh.surfaces.at("Cube-2.Top"), (std::vector<Face>{{1, 1}}));
  EXPECT_TRUE(check_mesh(mesh).empty());
  ASSERT_EQ(r.part_materials.size(), 2u);  // the part's section, once per instance
  EXPECT_TRUE(r.part_materials[0] && r.part_materials[1]);
  ASSERT_EQ(r.constraints.size(), 1u);
  EXPECT_EQ(r.constraints[0].nodes, (std::vector<int>{0, 1, 2, 3}));
  ASSERT_EQ(r.loads.forces.size(), 2u);
  EXPECT_EQ(r.loads.forces[0].nodes, std::vector<int>{12});  // Cube-2.5
  EXPECT_EQ(r.loads.forces[1].nodes, std::vector<int>{14});
  ASSERT_EQ(r.loads.pressures.size(), 1u);
  EXPECT_EQ(r.loads.pressures[0].faces, (std::vector<Face>{{1, 1}}));
}

TEST(InpReader, AssemblyErrorsAreNamed) {
  const std::string part = "*PART, NAME=A\n" + kNodes + "*ELEMENT, TYPE=C3D8\n1,1,2,3,4,5,6,7,8\n*END PART\n";
  EXPECT_TRUE(inp_reports(part + "*PART, NAME=a\n*END PART\n", 14, "*PART 'a' defined twice (first at line 1)"));
  EXPECT_TRUE(inp_reports(part + "*ASSEMBLY, NAME=X\n*INSTANCE, NAME=A-1, PART=B\n", 15, "part 'B', which is not defined"));
  EXPECT_TRUE(inp_reports(part + "*INSTANCE, NAME=A-1, PART=A\n0., 0.\n", 15, "the translation line must have 3 numbers"));
  EXPECT_TRUE(inp_reports(part + "*INSTANCE, NAME=A-1, PART=A\n0, 0, 0\n1, 1, 1, 1, 1, 1, 90.\n", 16, "the rotation axis points a and b coincide"));
  EXPECT_TRUE(inp_reports(part + "*INSTANCE, NAME=A-1, PART=A\n*END INSTANCE\n*INSTANCE, NAME=a-1, PART=A\n", 16,
                      "*INSTANCE 'a-1' defined twice"));
  EXPECT_TRUE(inp_reports(part + "*INSTANCE, NAME=A-1, PART=A\n*NODE\n99, 0, 0, 0\n", 15, "*NODE inside *INSTANCE 'A-1'"));
  EXPECT_TRUE(inp_reports(part + "*NSET, NSET=N, INSTANCE=Z-1\n1\n", 14,
                      "refers to instance 'Z-1', which is not defined"));
  EXPECT_TRUE(inp_reports("*PART, NAME=A\n" + kNodes, 1, "*PART 'A' has no *END PART"));
}

TEST(InpReader, EmptyAndMissingFilesAreNamed) {
  const std::string message = message_of("");
  EXPECT_NE(message.find("no elements"), std::string::npos) << message;
  try {
    (void)read_inp("/nonexistent/dir/model.inp");
    FAIL() << "no exception";
  } catch (const MeshFileError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/dir/model.inp: cannot be opened for reading");
  }
}

}  // namespace
}  // namespace jointhb::fe
