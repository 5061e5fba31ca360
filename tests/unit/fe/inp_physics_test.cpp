// The physics cards of an Abaqus/CalculiX deck (fe/inp_reader.hpp, inp_physics.cpp): materials by
// section, *BOUNDARY in its forms, *CLOAD, *DSLOAD and *DLOAD as static loads, and the cards that
// stop a run (with FILE:LINE) unless the case lists them under ignore_cards.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <string>

#include "jointhb/fe/inp_reader.hpp"
#include "jointhb/fe/mesh_file_error.hpp"
#include "unit/fe/inp_reports.hpp"
#include "unit/io/temp_file.hpp"

namespace jointhb::fe {
namespace {

using io::testing::TempFile;
using testing::inp_reports;

// Two unit cubes along x (C3D8, nodes 1-12) in two parts A and B, with sets and surfaces; lines
// 1-24.
const std::string kDeck = R"(*NODE
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
11, 2., 0., 1.
12, 2., 1., 1.
*ELEMENT, TYPE=C3D8, ELSET=A
1, 1, 2, 3, 4, 5, 6, 7, 8
*ELEMENT, TYPE=C3D8, ELSET=B
2, 2, 9, 10, 3, 6, 11, 12, 7
*NSET, NSET=LEFT
1, 4, 5, 8
*NSET, NSET=RIGHT
9, 10, 11, 12
*SURFACE, NAME=TOP
A, S2
B, S2
)";

const std::string kMaterials = R"(*MATERIAL, NAME=Steel
*ELASTIC
210e9, 0.3
*EXPANSION
1.2e-5
*DENSITY
7850.
*Material, name=alu
*Elastic, type=ISOTROPIC
70e9, 0.33
*Density
2700.,
*SOLID SECTION, ELSET=A, MATERIAL=steel
,
*SOLID SECTION, ELSET=B, MATERIAL=ALU
)";

InpResult read(const std::string& text, const InpOptions& options = {}) {
  const TempFile file(".inp", text);
  return read_inp(file.path(), options);
}

TEST(InpPhysics, MaterialsComeFromTheSections) {
  const InpResult r = read(kDeck + kMaterials);
  ASSERT_EQ(r.mesh.parts, (std::vector<std::string>{"A", "B"}));
  ASSERT_EQ(r.part_materials.size(), 2u);
  ASSERT_TRUE(r.part_materials[0] && r.part_materials[1]);
  EXPECT_EQ(r.part_materials[0]->name, "Steel");
  EXPECT_EQ(r.part_materials[0]->youngs_modulus, 210e9);
  EXPECT_EQ(r.part_materials[0]->poissons_ratio, 0.3);
  EXPECT_EQ(r.part_materials[0]->density, 7850.0);
  EXPECT_EQ(r.part_materials[1]->name, "alu");
  EXPECT_EQ(r.part_materials[1]->density, 2700.0);
  ASSERT_EQ(r.ignored_cards.size(), 1u);  // *EXPANSION: no temperature field, no effect
  EXPECT_EQ(r.ignored_cards[0].keyword, "*EXPANSION");

  // A part without a section has no material (the case must give one).
  const InpResult partial = read(kDeck + "*MATERIAL, NAME=S\n*ELASTIC\n1e9, 0.2\n*DENSITY\n1000\n*SOLID SECTION, ELSET=A, MATERIAL=S\n");
  EXPECT_TRUE(partial.part_materials[0].has_value());
  EXPECT_FALSE(partial.part_materials[1].has_value());
}

TEST(InpPhysics, MaterialErrorsNameTheLine) {
  EXPECT_TRUE(inp_reports(kDeck + "*SOLID SECTION, ELSET=A, MATERIAL=NONE\n", 25, "unknown material 'NONE'"));
  EXPECT_TRUE(inp_reports(kDeck + "*MATERIAL, NAME=S\n*ELASTIC\n1e9, 0.2\n*SOLID SECTION, ELSET=A, MATERIAL=S\n", 25, "material 'S' has no *DENSITY"));
  EXPECT_TRUE(inp_reports(kDeck + "*MATERIAL, NAME=S\n*ELASTIC\n1e9, 0.7\n*DENSITY\n1\n*SOLID SECTION, ELSET=A, MATERIAL=S\n", 25, "poissons_ratio"));
  EXPECT_TRUE(inp_reports(kDeck + "*MATERIAL, NAME=S\n*ELASTIC\n1e9, 0.2, 20.\n1e9, 0.2, 100.\n", 28, "temperature-dependent"));
  EXPECT_TRUE(inp_reports(kDeck + "*MATERIAL, NAME=S\n*ELASTIC, TYPE=ORTHOTROPIC\n1,2,3,4,5,6,7,8,9\n", 26, "only isotropic"));
  EXPECT_TRUE(inp_reports(kDeck + "*ELASTIC\n1e9, 0.2\n", 25, "*ELASTIC outside a *MATERIAL"));
  EXPECT_TRUE(inp_reports(kDeck + "*MATERIAL, NAME=S\n*MATERIAL, NAME=s\n", 26, "defined twice (first at line 25)"));
  // One material per part: a section over one element of a two-element part.
  EXPECT_TRUE(inp_reports(kDeck + "*ELSET, ELSET=ONE\n1\n*ELEMENT, TYPE=C3D8, ELSET=A\n3, 2, 9, 10, 3, 6, 11, 12, 7\n"
                              "*MATERIAL, NAME=S\n*ELASTIC\n1e9, 0.2\n*DENSITY\n1\n*SOLID SECTION, ELSET=ONE, MATERIAL=S\n",
                      34, "part 'A' has elements with and without a *SOLID SECTION"));
  EXPECT_TRUE(inp_reports(kDeck + kMaterials + "*SOLID SECTION, ELSET=A, MATERIAL=ALU\n", 40, "element 1 already has a section (line 37)"));
}

TEST(InpPhysics, BoundaryConditionsInAllTheirForms) {
  const InpResult r = read(kDeck + kMaterials + R"(*BOUNDARY
LEFT, ENCASTRE
RIGHT, 1, 2
9, 3, 3, 0.0
10, ZSYMM
11, YASYMM
12, 4, 6
*STEP
*STATIC
*BOUNDARY, OP=NEW
LEFT, 2
*END STEP
)");
  using Dirs = std::array<bool, 3>;
  ASSERT_EQ(r.constraints.size(), 6u);  // "12, 4, 6" fixes rotations only: solids have none
  EXPECT_EQ(r.constraints[0].nodes, (std::vector<int>{0, 3, 4, 7}));
  EXPECT_EQ(r.constraints[0].directions, (Dirs{true, true, true}));
  EXPECT_EQ(r.constraints[1].nodes, (std::vector<int>{8, 9, 10, 11}));
  EXPECT_EQ(r.constraints[1].directions, (Dirs{true, true, false}));
  EXPECT_EQ(r.constraints[2].nodes, std::vector<int>{8});
  EXPECT_EQ(r.constraints[2].directions, (Dirs{false, false, true}));
  EXPECT_EQ(r.constraints[3].directions, (Dirs{false, false, true}));
  EXPECT_EQ(r.constraints[4].directions, (Dirs{true, false, true}));
  EXPECT_EQ(r.constraints[5].directions, (Dirs{false, true, false}));
  EXPECT_NE(r.constraint_labels[5].find(":50"), std::string::npos) << r.constraint_labels[5];

  const std::string base = kDeck + kMaterials;  // 39 lines
  EXPECT_TRUE(inp_reports(base + "*BOUNDARY\nLEFT, 1, 3, 0.001\n", 41, "prescribed displacement of 0.001 is not supported"));
  EXPECT_TRUE(inp_reports(base + "*BOUNDARY\nNOPE, 1, 3\n", 41, "unknown node set 'NOPE'"));
  EXPECT_TRUE(inp_reports(base + "*BOUNDARY\n99, 1, 3\n", 41, "unknown node 99"));
  EXPECT_TRUE(inp_reports(base + "*BOUNDARY\nLEFT, 7\n", 41, "DOF '7' must be an integer 1..6"));
  EXPECT_TRUE(inp_reports(base + "*BOUNDARY\nLEFT, 3, 1\n", 41, "last DOF 1 < first DOF 3"));
  EXPECT_TRUE(inp_reports(base + "*BOUNDARY, AMPLITUDE=RAMP\nLEFT, 1, 3\n", 40, "AMPLITUDE=RAMP"));
  EXPECT_TRUE(inp_reports(base + "*BOUNDARY, TYPE=VELOCITY\nLEFT, 1, 3\n", 40, "TYPE=VELOCITY is not supported"));
}

TEST(InpPhysics, ConcentratedAndPressureLoads) {
  const InpResult r = read(kDeck + kMaterials + R"(*STEP
*STATIC
*CLOAD
RIGHT, 1, 250.
5, 3, -10.
*DSLOAD
TOP, P, 1.0e5
*DLOAD
B, P1, 2.0e5
*END STEP
)");
  ASSERT_EQ(r.loads.forces.size(), 2u);
  EXPECT_EQ(r.loads.forces[0].nodes, (std::vector<int>{8, 9, 10, 11}));
  EXPECT_EQ(r.loads.forces[0].force, Eigen::Vector3d(250.0, 0.0, 0.0));
  EXPECT_EQ(r.loads.forces[1].nodes, std::vector<int>{4});
  EXPECT_EQ(r.loads.forces[1].force, Eigen::Vector3d(0.0, 0.0, -10.0));
  ASSERT_EQ(r.loads.pressures.size(), 2u);
  EXPECT_EQ(r.loads.pressures[0].faces, (std::vector<Face>{{0, 1}, {1, 1}}));
  EXPECT_EQ(r.loads.pressures[0].pressure, 1.0e5);
  EXPECT_EQ(r.loads.pressures[1].faces, (std::vector<Face>{{1, 0}}));
  EXPECT_EQ(r.loads.pressures[1].pressure, 2.0e5);
  EXPECT_NE(r.loads.pressures[1].label.find(":48"), std::string::npos) << r.loads.pressures[1].label;

  const std::string base = kDeck + kMaterials;
  EXPECT_TRUE(inp_reports(base + "*CLOAD\n9, 1, 1.\n*CLOAD\nRIGHT, 1, 2.\n", 43, "node 9 DOF 1 already loaded at line 41"));
  EXPECT_TRUE(inp_reports(base + "*CLOAD\n9, 5, 1.\n", 41, "a moment (DOF 5)"));
  EXPECT_TRUE(inp_reports(base + "*CLOAD\n9, 1, abc\n", 41, "'abc' is not a finite number"));
  EXPECT_TRUE(inp_reports(base + "*CLOAD, FOLLOWER\n9, 1, 1.\n", 40, "parameter FOLLOWER of *CLOAD is not supported"));
  EXPECT_TRUE(inp_reports(base + "*DSLOAD\nTOP, TRVEC, 1., 1., 0., 0.\n", 41, "*DSLOAD data must be"));
  EXPECT_TRUE(inp_reports(base + "*DSLOAD\nTOP, PNU, 1.\n", 41, "load type 'PNU' is not supported"));
  EXPECT_TRUE(inp_reports(base + "*DSLOAD\nNOSURF, P, 1.\n", 41, "unknown surface 'NOSURF'"));
  EXPECT_TRUE(inp_reports(base + "*DLOAD\nA, GRAV, 9.81, 0., 0., -1.\n", 41, "*DLOAD data must be"));
  EXPECT_TRUE(inp_reports(base + "*DLOAD\nA, BZ, 9.81\n", 41, "load type 'BZ' is not supported"));
  EXPECT_TRUE(inp_reports(base + "*STEP\n*STATIC\n*END STEP\n*STEP\n", 43, "a second *STEP (the first is at line 40)"));
}

TEST(InpPhysics, CardsThatChangeThePhysicsStopUnlessIgnored) {
  const std::string deck = kDeck + kMaterials + "*SURFACE, NAME=BOT\nA, S1\n*EQUATION\n2\n2, 1, 1., 9, 1, -1.\n*DAMPING, ALPHA=2.0\n";
  EXPECT_TRUE(inp_reports(deck, 42, "card *EQUATION changes the physics and is not supported; to run without it, list it in the case under ignore_cards"));
  InpOptions options;
  options.ignore_cards = {"*Equation", "DAMPING"};
  const InpResult r = read(deck, options);
  ASSERT_EQ(r.skipped_cards.size(), 2u);
  EXPECT_EQ(r.skipped_cards[0].keyword, "*EQUATION");
  EXPECT_EQ(r.skipped_cards[0].line, 42);
  EXPECT_EQ(r.skipped_cards[1].keyword, "*DAMPING");
  // A physics card that jointhb reads is skipped too when the case lists it.
  options.ignore_cards = {"*TIE"};
  const InpResult untied = read(kDeck + kMaterials + "*SURFACE, NAME=BOT\nA, S1\n*TIE, NAME=T1\nBOT, TOP\n", options);
  EXPECT_TRUE(untied.ties.empty());
  ASSERT_EQ(untied.skipped_cards.size(), 1u);
  EXPECT_EQ(untied.skipped_cards[0].keyword, "*TIE");
  // A card jointhb does not know at all stops too, and can be ignored the same way.
  EXPECT_TRUE(inp_reports(kDeck + "*FANCY CARD, X=1\n", 25, "card *FANCY CARD is not supported"));
  options.ignore_cards = {"*fancy  card"};
  EXPECT_EQ(read(kDeck + "*FANCY CARD, X=1\n", options).skipped_cards.size(), 1u);
}

// *TIE: one data line "slave, master" (Abaqus' order), the surfaces resolved to the mesh's names;
// ADJUST, POSITION TOLERANCE and TYPE are checked and accepted (no effect on a linear tie), TIED
// NSET restricts the slave nodes.
TEST(InpPhysics, TiesNameTheirSlaveAndMasterSurfaces) {
  const std::string base = kDeck + kMaterials + "*SURFACE, NAME=BOT\nA, S1\n";  // 41 lines
  const InpResult r = read(base + "*TIE, NAME=T1, ADJUST=YES, POSITION TOLERANCE=0.001, TYPE=SURFACE TO SURFACE\n"
                                  "bot, top\n*Tie, name=T2, tied nset=LEFT, adjust=no\nTOP, BOT\n");
  ASSERT_EQ(r.ties.size(), 2u);
  EXPECT_EQ(r.ties[0].name, "T1");
  EXPECT_EQ(r.ties[0].slave_surface, "BOT");
  EXPECT_EQ(r.ties[0].master_surface, "TOP");
  EXPECT_EQ(r.ties[0].line, 42);
  EXPECT_TRUE(r.ties[0].tied_nodes.empty());
  EXPECT_EQ(r.ties[1].slave_surface, "TOP");
  EXPECT_EQ(r.ties[1].tied_nodes, (std::vector<int>{0, 3, 4, 7}));
  EXPECT_TRUE(r.ignored_cards.size() == 1u && r.skipped_cards.empty());  // *EXPANSION only

  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T\nNOPE, TOP\n", 43, "*TIE 'T': unknown slave surface 'NOPE'"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T\nBOT, NOPE\n", 43, "*TIE 'T': unknown master surface 'NOPE'"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T\nBOT\n", 43, "*TIE 'T' data must be 'slave surface, master surface', got 'BOT'"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T\nBOT,\n", 43, "*TIE 'T' data must be 'slave surface, master surface'"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T\n", 42, "one data line 'slave surface, master surface' expected, got 0"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T\nBOT, TOP\nTOP, BOT\n", 44, "one data line 'slave surface, master surface' expected, got 2"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T\nBOT, bot\n", 43, "the slave and master surfaces are the same ('BOT')"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T, CONSTRAINT RATIO=0.1\nBOT, TOP\n", 42,
                      "parameter CONSTRAINT RATIO of *TIE is not supported (supported: NAME, POSITION TOLERANCE, ADJUST, TIED NSET, TYPE)"));
  EXPECT_TRUE(inp_reports(base + "*TIE\nBOT, TOP\n", 42, "*TIE needs the parameter NAME="));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T, ADJUST=MAYBE\nBOT, TOP\n", 42, "*TIE, ADJUST=MAYBE: must be YES or NO"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T, POSITION TOLERANCE=-1\nBOT, TOP\n", 42, "POSITION TOLERANCE=-1: must be a number >= 0"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T, TYPE=CYCLIC\nBOT, TOP\n", 42, "*TIE, TYPE=CYCLIC: must be SURFACE TO SURFACE or NODE TO SURFACE"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T, TIED NSET=NOPE\nBOT, TOP\n", 42, "unknown node set 'NOPE'"));
  EXPECT_TRUE(inp_reports(base + "*TIE, NAME=T\nBOT, TOP\n*TIE, NAME=t\nTOP, BOT\n", 44, "*TIE 't' defined twice (first at line 42)"));
}

}  // namespace
}  // namespace jointhb::fe
