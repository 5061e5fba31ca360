// An Abaqus deck's physics in an FE case (io/fe_case.hpp): the deck's *BOUNDARY, *SOLID SECTION
// materials and loads reach the model with the indices of the combined mesh, the case overrides
// the deck's materials, and a clamped deck gives the clamped frequencies (the same as the
// constraints written in the case), never free-free ones.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/input_error.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"
#include "unit/io/temp_file.hpp"

namespace jointhb::io {
namespace {

namespace fs = std::filesystem;

// A directory of its own for the case and its deck, removed afterwards.
using testing::CaseDir;

// A steel cantilever 100 × 10 × 10 mm of 10 × 1 × 1 C3D8I elements as a deck, clamped at x = 0 by
// *BOUNDARY (when `clamp`) and loaded by a *CLOAD at its tip.
std::string beam_deck(bool clamp) {
  fe::BoxOptions o;
  o.size = {0.1, 0.01, 0.01};
  o.divisions = {10, 1, 1};
  const fe::Mesh box = fe::box_mesh(o);
  std::string text = "*HEADING\ncantilever\n*NODE\n";
  for (int n = 0; n < box.num_nodes(); ++n)
    text += fmt::format("{}, {:.17g}, {:.17g}, {:.17g}\n", n + 1, box.coordinates(0, n), box.coordinates(1, n), box.coordinates(2, n));
  text += "*ELEMENT, TYPE=C3D8I, ELSET=BEAM\n";
  for (int e = 0; e < box.num_elements(); ++e) {
    text += std::to_string(e + 1);
    for (int n : box.elements[static_cast<std::size_t>(e)].node_span()) text += ", " + std::to_string(n + 1);
    text += "\n";
  }
  text += "*NSET, NSET=ROOT\n";
  for (int n : box.node_sets.at("box.xmin")) text += std::to_string(n + 1) + ",\n";
  text += "*NSET, NSET=TIP\n";
  for (int n : box.node_sets.at("box.xmax")) text += std::to_string(n + 1) + ",\n";
  text += "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n*SOLID SECTION, ELSET=BEAM, MATERIAL=STEEL\n";
  text += "*STEP\n*STATIC\n";
  if (clamp) text += "*BOUNDARY\nROOT, ENCASTRE\n";
  text += "*CLOAD\nTIP, 3, -25.\n*END STEP\n";
  return text;
}

const char* const kCase = R"(model:
  type: fe
  parts:
    - {{name: block, material: alu, box: {{origin: [0.0, 0.0, -0.01], size: [0.01, 0.01, 0.01], divisions: [1, 1, 1]}}}}
    - {{mesh: beam.inp{extra}}}
  materials: {{alu: {{youngs_modulus: 70.0e9, poissons_ratio: 0.33, density: 2700.0}}}}
  constraints: [{{node_set: block.zmin}}]
analysis:
  preload: {{}}
  modes: {{count: 4, shift_hz: -1.0}}
)";

TEST(FeCaseDeck, BoundaryLoadsAndMaterialsOfTheDeckReachTheModel) {
  const CaseDir d;
  d.write("beam.inp", beam_deck(true));
  const FeCase c = d.read(fmt::format(fmt::runtime(kCase), fmt::arg("extra", "")));
  const int block_nodes = 8, block_elements = 1;
  ASSERT_EQ(c.material_per_part.size(), 2u);
  EXPECT_EQ(c.material_per_part[1].name, "STEEL");
  EXPECT_EQ(c.material_per_part[1].youngs_modulus, 210e9);
  ASSERT_EQ(c.constraints.size(), 2u);  // the deck's (read with its part), then the case's
  EXPECT_EQ(c.constraint_sets[1], "block.zmin");
  EXPECT_EQ(c.constraint_sets[0], (d.dir / "beam.inp").string() + ":78");
  for (int n : c.constraints[0].nodes) {
    EXPECT_GE(n, block_nodes);
    EXPECT_EQ(c.mesh.coordinates(0, n), 0.0);  // the deck's root nodes, shifted past the block's
  }
  ASSERT_EQ(c.loads.forces.size(), 1u);
  for (int n : c.loads.forces[0].nodes) EXPECT_NEAR(c.mesh.coordinates(0, n), 0.1, 1e-15);
  EXPECT_EQ(c.loads.forces[0].force, Eigen::Vector3d(0.0, 0.0, -25.0));
  EXPECT_EQ(block_elements + 10, c.mesh.num_elements());
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find("*HEADING (1), *STEP (75), *STATIC (76), *END STEP (81)"), std::string::npos) << c.warnings[0];

  // The case's material overrides the deck's.
  const FeCase o = d.read(fmt::format(fmt::runtime(kCase), fmt::arg("extra", ", material: alu")));
  EXPECT_EQ(o.material_per_part[1].name, "alu");
}

TEST(FeCaseDeck, AClampedDeckGivesTheClampedFrequencies) {
  const CaseDir d;
  // The same beam clamped by the deck, and unclamped in the deck but clamped in the case.
  d.write("beam.inp", beam_deck(true));
  const FeCase by_deck = d.read(fmt::format(fmt::runtime(kCase), fmt::arg("extra", "")));
  d.write("beam.inp", beam_deck(false));
  std::string yaml = fmt::format(fmt::runtime(kCase), fmt::arg("extra", ""));
  const std::string clamp = "constraints: [{node_set: block.zmin}]";
  yaml.replace(yaml.find(clamp), clamp.size(), "constraints: [{node_set: block.zmin}, {node_set: ROOT}]");
  const FeCase by_case = d.read(yaml);
  pipeline::FePipeline a(by_deck, by_deck), b(by_case, by_case);
  const modal::ModalResult& ma = a.modes();
  const modal::ModalResult& mb = b.modes();
  ASSERT_EQ(ma.frequencies_hz.size(), 4);
  EXPECT_LT((ma.frequencies_hz - mb.frequencies_hz).cwiseAbs().maxCoeff(), 1e-9 * mb.frequencies_hz.maxCoeff());
  // Euler–Bernoulli clamped-free first bending frequency f1 = (1.8751²/2π) √(EI/(ρA L⁴)) = 835.5 Hz
  // for this beam; a free-free model would have six zero frequencies instead.
  const double f1 = 1.8751040687 * 1.8751040687 / (2.0 * M_PI) * std::sqrt(210e9 * 1e-8 / 12.0 / (7850.0 * 1e-4 * 1e-4));
  EXPECT_NEAR(ma.frequencies_hz[0] / f1, 1.0, 0.03) << ma.frequencies_hz.transpose();
  // The deck's tip load bends the beam down in the preload: w_tip ≈ −F L³/(3EI), F = 4 × 25 N.
  const double w = -100.0 * 1e-3 / (3.0 * 210e9 * 1e-8 / 12.0);
  const preload::PreloadResult& p = a.preload();
  double tip = 0.0;
  for (int n : by_deck.loads.forces[0].nodes) tip += p.displacement[3 * n + 2] / 4.0;
  EXPECT_NEAR(tip / w, 1.0, 0.03) << tip << " vs " << w;
}

TEST(FeCaseDeck, UnbalancedLoadsOnAFreeModelAndPhysicsCardsAreInputErrors) {
  const CaseDir d;
  d.write("beam.inp", beam_deck(false));
  const std::string free_case = "model:\n  type: fe\n  parts:\n    - {mesh: beam.inp}\n"
                                "  loads: [{node_set: TIP, force: [0.0, 0.0, 1.0]}]\n";
  try {
    (void)d.read(free_case);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model.loads"), std::string::npos) << e.what();
    // The deck's tip load, 4 × 25 N down, less the case's 4 × 1 N up.
    EXPECT_NE(std::string(e.what()).find("resultant force of 96 N"), std::string::npos) << e.what();
  }
  // The deck's load alone on a free model is refused when the case is read, not in the preload.
  try {
    (void)d.read("model:\n  type: fe\n  parts:\n    - {mesh: beam.inp}\n");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("resultant force of 100 N"), std::string::npos) << e.what();
  }
  d.write("coupled.inp", beam_deck(true) + "*EQUATION\n2\n1, 1, 1., 2, 1, -1.\n");
  const std::string coupled = "model:\n  type: fe\n  parts:\n    - {mesh: coupled.inp}\n";
  try {
    (void)d.read(coupled);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("coupled.inp:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("*EQUATION changes the physics"), std::string::npos) << e.what();
  }
  const FeCase ignored = d.read("model:\n  type: fe\n  parts:\n    - {mesh: coupled.inp, ignore_cards: ['*EQUATION']}\n");
  ASSERT_EQ(ignored.warnings.size(), 2u);
  EXPECT_NE(ignored.warnings[1].find("*EQUATION skipped as the case asks"), std::string::npos) << ignored.warnings[1];
}

}  // namespace
}  // namespace jointhb::io
