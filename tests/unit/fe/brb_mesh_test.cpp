// The Brake-Reuss beam's mesh deck (cases/14-brake-reuss-beam/brb.inp, written by make_mesh.py
// there; tests/cli/run_fe_brb.sh checks that the shipped file is what the script writes) read by
// jointhb's .inp reader and checked against closed forms: the volume of each half-beam, the
// interface area, the lap faces' coincident nodes and the washers' annular footprints. The holes
// are 40-gons inscribed in their circle (r = 4.25 mm), so each closed form with circular holes is
// met within the polygon's area deficit, and the polygonal one to round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <set>

#include "jointhb/fe/inp_reader.hpp"
#include "jointhb/fe/interface.hpp"
#include "jointhb/fe/mesh_checks.hpp"
#include "jointhb/preload/bolt.hpp"

namespace jointhb::fe {
namespace {

constexpr double kMm = 1e-3;
constexpr double kLength = 420 * kMm, kLap = 120 * kMm, kSide = 25.4 * kMm, kHalf = 12.7 * kMm;
constexpr double kHole = 4.25 * kMm, kWasher = 8.73 * kMm;
constexpr int kSegments = 40;  // make_mesh.py's --hole-segments

// Area of the n-gon inscribed in a circle of radius r.
double polygon_area(double r, int n) {
  return 0.5 * n * r * r * std::sin(2.0 * std::numbers::pi / n);
}

const InpResult& brb() {
  static const InpResult deck = [] {
    // tests/unit/fe/this_file.cpp -> repository root
    const auto root =
        std::filesystem::path(__FILE__).parent_path().parent_path().parent_path().parent_path();
    return read_inp(root / "cases/14-brake-reuss-beam/brb.inp");
  }();
  return deck;
}

TEST(BrakeReussBeamMesh, TwoSteelHalvesWithTheVolumeOfTheDrawing) {
  const InpResult& deck = brb();
  const Mesh& mesh = deck.mesh;
  ASSERT_EQ(mesh.parts, (std::vector<std::string>{"LOWER", "UPPER"}));
  ASSERT_EQ(deck.part_materials.size(), 2u);
  for (const auto& m : deck.part_materials) {
    ASSERT_TRUE(m.has_value());
    EXPECT_EQ(m->youngs_modulus, 200e9);
    EXPECT_EQ(m->poissons_ratio, 0.29);
    EXPECT_EQ(m->density, 7800.0);
  }
  EXPECT_TRUE(check_mesh(mesh).empty());
  std::vector<double> volume(2, 0.0);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    EXPECT_EQ(mesh.elements[static_cast<std::size_t>(e)].type, ElementType::hex8_incompatible);
    volume[static_cast<std::size_t>(mesh.elements[static_cast<std::size_t>(e)].part)] +=
        element_volume(mesh, e);
  }
  // 420 mm of 25.4 x 25.4 mm, less the lap's cut (120 x 25.4 x 12.7 mm), less three holes
  // through the lap's 12.7 mm.
  const double solid = kLength * kSide * kSide - kLap * kSide * kHalf;
  const double polygonal = solid - 3 * kHalf * polygon_area(kHole, kSegments);
  const double circular = solid - 3 * kHalf * std::numbers::pi * kHole * kHole;
  const double deficit =
      3 * kHalf * (std::numbers::pi * kHole * kHole - polygon_area(kHole, kSegments));
  for (const double v : volume) {
    std::printf(
        "half-beam volume %.9g mm^3: with 40-gon holes %.9g, with round holes %.9g (deficit bound "
        "%.3g)\n",
        v / 1e-9, polygonal / 1e-9, circular / 1e-9, deficit / 1e-9);
    EXPECT_NEAR(v / polygonal - 1.0, 0.0, 1e-9);  // the deck's 12 digits
    EXPECT_LE(std::abs(v - circular), deficit * (1.0 + 1e-6));
  }
}

TEST(BrakeReussBeamMesh, LapFacesHaveCoincidentSeparateNodesAndTheInterfaceArea) {
  const Mesh& mesh = brb().mesh;
  // The two lap faces: the same positions, separate nodes.
  std::vector<std::set<int>> nodes(2);
  const char* names[] = {"LOWER.LAP_FACE", "UPPER.LAP_FACE"};
  for (int s = 0; s < 2; ++s)
    for (const Face& f : mesh.surfaces.at(names[s]))
      for (int n : face_nodes(mesh, f)) nodes[static_cast<std::size_t>(s)].insert(n);
  EXPECT_EQ(nodes[0].size(), nodes[1].size());
  EXPECT_EQ(nodes[0].size(), 1016u);  // the in-plane layout of make_mesh.py's defaults
  // Every lower node has exactly one upper node within 1 nm (the deck's 12 digits and the 180°
  // turn of the upper instance leave ~1e-16 m).
  for (int n : nodes[1]) EXPECT_NEAR(mesh.coordinates(2, n), 0.0, 1e-12);
  std::set<int> partners;
  for (int n : nodes[0]) {
    EXPECT_NEAR(mesh.coordinates(2, n), 0.0, 1e-12);
    int found = 0;
    for (int m : nodes[1]) {
      if ((mesh.coordinates.col(n) - mesh.coordinates.col(m)).norm() > 1e-9) continue;
      ++found;
      partners.insert(m);
      EXPECT_NE(m, n);
    }
    EXPECT_EQ(found, 1) << "lower lap node " << n;
  }
  EXPECT_EQ(partners.size(), nodes[1].size());
  // The zero-thickness interface pairs every face; its area is the lap's less the holes.
  InterfaceOptions o;
  o.name = "lap";
  o.bottom_surface = "LOWER.LAP_FACE";
  o.top_surface = "UPPER.LAP_FACE";
  const Interface lap = build_interface(mesh, o);
  EXPECT_EQ(lap.node_pairs.size(), 1016u);
  const double polygonal = kLap * kSide - 3 * polygon_area(kHole, kSegments);
  const double circular = kLap * kSide - 3 * std::numbers::pi * kHole * kHole;
  const double deficit = 3 * (std::numbers::pi * kHole * kHole - polygon_area(kHole, kSegments));
  std::printf(
      "interface area %.9g mm^2: with 40-gon holes %.9g, 120 x 25.4 - 3 pi 4.25^2 = %.9g (deficit "
      "bound %.3g)\n",
      lap.total_area / 1e-6, polygonal / 1e-6, circular / 1e-6, deficit / 1e-6);
  EXPECT_NEAR(lap.total_area / polygonal - 1.0, 0.0, 1e-9);
  EXPECT_LE(std::abs(lap.total_area - circular), deficit * (1.0 + 1e-6));
  for (const InterfacePoint& p : lap.points) EXPECT_NEAR(p.frame(2, 2), 1.0, 1e-12);  // normal +z
}

// The washers press on the lap's outer faces (z = ±12.7 mm): the bolt footprint r_i = 4.37 mm,
// r_o = 8.73 mm takes exactly the faces between the hole (a 40-gon at 4.25 mm) and the ring of
// nodes at 8.73 mm, whose area is 20 sin(9°)(8.73² − 4.25²) mm².
TEST(BrakeReussBeamMesh, WasherFootprintsAreTheMeshedAnnuli) {
  const Mesh& mesh = brb().mesh;
  for (const double x : {-0.03, 0.0, 0.03}) {
    preload::BoltOptions b;
    b.name = "bolt";
    b.axis_point = {x, 0.0, 0.0};
    b.head_surface = "UPPER.WASHER_FACE";
    b.nut_surface = "LOWER.WASHER_FACE";
    b.head_radius = b.nut_radius = kWasher;
    b.head_inner_radius = b.nut_inner_radius = 4.37 * kMm;
    b.axial_stiffness = 3.46e8;
    b.preload = 12e3;
    const preload::Bolt bolt = preload::build_bolt(mesh, b);
    const double annulus = polygon_area(kWasher, kSegments) - polygon_area(kHole, kSegments);
    EXPECT_NEAR(bolt.head_area / annulus - 1.0, 0.0, 1e-9) << x;
    EXPECT_NEAR(bolt.nut_area / annulus - 1.0, 0.0, 1e-9) << x;
    EXPECT_EQ(bolt.head_nodes.size(), 4u * kSegments);  // the hole, two rings between, the washer's
    for (int n : bolt.head_nodes) EXPECT_NEAR(mesh.coordinates(2, n), kHalf, 1e-12);
    for (int n : bolt.nut_nodes) EXPECT_NEAR(mesh.coordinates(2, n), -kHalf, 1e-12);
  }
}

}  // namespace
}  // namespace jointhb::fe
