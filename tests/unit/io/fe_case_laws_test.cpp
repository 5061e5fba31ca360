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

// Issue 20, item 3 for FE cases: positive physical numbers outside [1e-100, 1e100] are refused at
// their key (their products leave the range of doubles), the edges of the range are accepted.
TEST(FeCaseLaws, PhysicalNumbersOutsideTheRangeOfDoublesAreRefusedAtTheirKey) {
  const std::string huge = law_error_of("{pressure: 1.0e300, decay: 2.0e5, mu: 0.3, law: gaul-mayer}");
  EXPECT_NE(huge.find("key 'model.interfaces[0].contact.pressure': magnitude must lie in [1e-100, 1e+100]"),
            std::string::npos) << huge;
  const std::string tiny = law_error_of("{pressure: 1.0e6, decay: 2.0e5, mu: 1.0e-120, law: gaul-mayer}");
  EXPECT_NE(tiny.find("contact.mu': magnitude must lie in"), std::string::npos) << tiny;
  EXPECT_EQ(law_error_of("{pressure: 1.0e100, decay: 1.0e-100, mu: 0.3, law: gaul-mayer}"), "no error");
  std::string modulus = lap_case("{pressure: 1.0e6, decay: 2.0e5, mu: 0.3, law: gaul-mayer}");
  modulus.replace(modulus.find("70.0e9"), 6, "7.0e200");
  try {
    (void)parse_fe_case(modulus, "laws.yaml");
    ADD_FAILURE() << "youngs_modulus 7e200 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("youngs_modulus': magnitude must lie in"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace jointhb::io
