// Bolts of an FE case (docs/case-files.md §"Bolts"): a footprint's optional inner_radius selects a
// washer's annulus (eq. B-4 of preload/bolt.hpp); a value outside [0, radius) is one line naming
// the key.
#include <gtest/gtest.h>

#include <string>

#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/input_error.hpp"

namespace jointhb::io {
namespace {

// Two 20 × 20 mm blocks (2 mm faces) clamped by one bolt at their centre.
std::string bolted_case(const std::string& head) {
  return R"(model:
  type: fe
  materials: {steel: {youngs_modulus: 200.0e9, poissons_ratio: 0.29, density: 7800.0}}
  parts:
    - {name: lower, material: steel, box: {size: [0.02, 0.02, 0.005], divisions: [10, 10, 1]}}
    - {name: upper, material: steel, box: {origin: [0.0, 0.0, 0.005], size: [0.02, 0.02, 0.005], divisions: [10, 10, 1]}}
  interfaces:
    - {name: lap, bottom: lower.zmax, top: upper.zmin, contact: {pressure: 1.0e6, decay: 1.0e6, mu: 0.3, law: jenkins}}
  bolts:
    - {name: b1, point: [0.01, 0.01, 0.0], head: )" +
         head + R"(, nut: {surface: lower.zmin, radius: 0.008},
       stiffness: 3.5e8, preload: 1000.0}
)";
}

std::string bolt_error_of(const std::string& head) {
  try {
    (void)parse_fe_case(bolted_case(head), "bolts.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(FeCaseBolts, InnerRadiusSelectsAnAnnulus) {
  const FeCase disc =
      parse_fe_case(bolted_case("{surface: upper.zmax, radius: 0.008}"), "bolts.yaml");
  const FeCase ring = parse_fe_case(
      bolted_case("{surface: upper.zmax, radius: 0.008, inner_radius: 0.004}"), "bolts.yaml");
  ASSERT_EQ(disc.bolts.size(), 1u);
  ASSERT_EQ(ring.bolts.size(), 1u);
  EXPECT_DOUBLE_EQ(disc.bolts[0].head_inner_radius, 0.0);
  EXPECT_DOUBLE_EQ(ring.bolts[0].head_inner_radius, 0.004);
  EXPECT_DOUBLE_EQ(ring.bolts[0].nut_inner_radius, 0.0);
  // The 2 mm faces whose centres lie within 4 mm of the axis (4 at √2 mm, 8 at √10 mm) leave the
  // head footprint; the nut keeps its disc.
  EXPECT_NEAR(disc.bolts[0].head_area - ring.bolts[0].head_area, 12 * 4e-6, 1e-15);
  EXPECT_DOUBLE_EQ(ring.bolts[0].nut_area, disc.bolts[0].nut_area);
}

TEST(FeCaseBolts, InnerRadiusOutsideItsRangeIsOneLineNamingTheKey) {
  const std::string at_radius =
      bolt_error_of("{surface: upper.zmax, radius: 0.008, inner_radius: 0.008}");
  EXPECT_NE(
      at_radius.find("key 'model.bolts[0].head.inner_radius': must be < radius = 0.008, got 0.008"),
      std::string::npos)
      << at_radius;
  EXPECT_EQ(at_radius.find('\n'), std::string::npos) << at_radius;
  EXPECT_NE(bolt_error_of("{surface: upper.zmax, radius: 0.008, inner_radius: -0.001}")
                .find("key 'model.bolts[0].head.inner_radius': must be >= 0"),
            std::string::npos);
  EXPECT_NE(bolt_error_of("{surface: upper.zmax, radius: 0.008, inner_radius: 0.01}")
                .find("must be < radius = 0.008, got 0.01"),
            std::string::npos);
  EXPECT_NE(bolt_error_of("{surface: upper.zmax, radius: 0.008, inner_radius: 0.0079}")
                .find("no face has its centre between head_inner_radius = 0.0079 m and head_radius "
                      "= 0.008 m"),
            std::string::npos);
  EXPECT_NE(bolt_error_of("{surface: upper.zmax, radius: 0.008, inner: 0.004}")
                .find("key 'model.bolts[0].head.inner': unknown key"),
            std::string::npos);
}

}  // namespace
}  // namespace jointhb::io
