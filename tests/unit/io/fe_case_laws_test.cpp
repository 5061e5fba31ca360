// The interface laws of an FE case (docs/case-files.md §"Interfaces"): exponential with a cutoff
// gap, linear penalty, frictionless, and the errors that name the key.
#include <gtest/gtest.h>

#include <string>

#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/input_error.hpp"

namespace jointhb::io {
namespace {

std::string lap_case(const std::string& contact) {
  return R"(model:
  type: fe
  materials: {al: {youngs_modulus: 70.0e9, poissons_ratio: 0.33, density: 2700.0}}
  parts:
    - {name: lower, material: al, box: {size: [0.02, 0.02, 0.005], divisions: [2, 2, 1]}}
    - {name: upper, material: al, box: {origin: [0.0, 0.0, 0.005], size: [0.02, 0.02, 0.005], divisions: [2, 2, 1]}}
  interfaces:
    - {name: lap, bottom: lower.zmax, top: upper.zmin, contact: )" + contact + R"(}
  constraints: [{node_set: lower.zmin}]
  loads: [{surface: upper.zmax, pressure: 1.0e6}]
)";
}

std::string law_error_of(const std::string& contact) {
  try {
    (void)parse_fe_case(lap_case(contact), "laws.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(FeCaseLaws, EachLawReachesTheContactPoint) {
  {
    const FeCase c = parse_fe_case(lap_case("{pressure: 1.0e6, decay: 2.0e5, cutoff_gap: 2.0e-5, mu: 0.3, law: gaul-mayer}"), "laws.yaml");
    const contact::NormalLaw& n = c.interfaces[0].law.options().normal;
    EXPECT_EQ(n.kind, contact::NormalLawKind::exponential);
    EXPECT_EQ(n.cutoff_gap, 2.0e-5);
    EXPECT_EQ(c.interface_specs[0].cutoff_gap, 2.0e-5);
    EXPECT_EQ(c.loads.pressures.size(), 1u);
  }
  {
    const FeCase c = parse_fe_case(lap_case("{normal_stiffness: 1.0e13, mu: 0.2, law: jenkins, kt: 5.0e12}"), "laws.yaml");
    const contact::ContactPointOptions& o = c.interfaces[0].law.options();
    EXPECT_EQ(o.normal.kind, contact::NormalLawKind::linear);
    EXPECT_EQ(o.normal.penalty_stiffness, 1.0e13);
    EXPECT_EQ(o.tangential_stiffness, 5.0e12);
    EXPECT_EQ(o.friction_coefficient, 0.2);
  }
  {
    const FeCase c = parse_fe_case(lap_case("{normal_stiffness: 1.0e13, law: frictionless}"), "laws.yaml");
    EXPECT_EQ(c.interfaces[0].law.options().friction_coefficient, 0.0);
    EXPECT_TRUE(c.interface_specs[0].frictionless);
  }
}

TEST(FeCaseLaws, InconsistentLawKeysAreNamed) {
  EXPECT_NE(law_error_of("{normal_stiffness: 1.0e13, pressure: 1.0e6, mu: 0.2, law: jenkins}")
                .find("key 'model.interfaces[0].contact.pressure': belongs to the exponential normal law"),
            std::string::npos);
  EXPECT_NE(law_error_of("{mu: 0.2, law: jenkins}").find("needs the normal law"), std::string::npos);
  EXPECT_NE(law_error_of("{normal_stiffness: 1.0e13, law: frictionless, mu: 0.3}")
                .find("contact.mu': a frictionless contact has no tangential law"),
            std::string::npos);
  EXPECT_NE(law_error_of("{normal_stiffness: 1.0e13, law: jenkins}").find("contact.mu': required"), std::string::npos);
  EXPECT_NE(law_error_of("{pressure: 1.0e6, decay: 2.0e5, cutoff_gap: -1.0e-6, mu: 0.3, law: jenkins}").find("contact.cutoff_gap"),
            std::string::npos);
  EXPECT_NE(law_error_of("{normal_stiffness: 1.0e13, law: coulomb, mu: 0.3}").find("contact.law"), std::string::npos);
}

}  // namespace
}  // namespace jointhb::io
