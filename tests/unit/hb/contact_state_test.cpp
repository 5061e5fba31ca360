// Contact states from the law's own variables (hb/contact_state.hpp): the rules on a truth table,
// the limit measures on hand-made samples, and the states and force ratios of one contact point's
// AFT (hb/contact_point_aft.hpp) against the closed-form symmetric loop of the Gaul–Mayer law
// (contact/closed_forms.hpp) and the Jenkins element at constant pressure, and under normal motion
// that opens the point for part of the period or throughout.
#include "jointhb/hb/contact_state.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "jointhb/contact/closed_forms.hpp"
#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/jenkins_law.hpp"
#include "jointhb/hb/contact_point_aft.hpp"

namespace jointhb::hb {
namespace {

namespace jc = jointhb::contact;

TEST(ContactState, RulesInOrderOfPrecedence) {
  struct Row {
    ContactStateInputs in;
    ContactState expected;
  };
  const std::vector<Row> rows = {
      {{1.0, 0.0, 0.0, false}, ContactState::open},
      {{0.25, 0.5, 1.0, false}, ContactState::gapping},  // opening wins over the limit
      {{0.0, 0.1, 1.0, true}, ContactState::gross_slip},
      {{0.0, 1.0 / 128, 1.0, false}, ContactState::gross_slip},
      {{0.0, 0.0, 0.999, true}, ContactState::stuck},  // Jenkins below its limit sticks
      {{0.0, 0.0, 0.999, false}, ContactState::microslip},
      {{0.0, 0.0, 0.0099, false}, ContactState::stuck},  // stuck-like
      {{0.0, 0.0, 0.01, false}, ContactState::microslip},
      {{0.0, 0.0, 0.0, false}, ContactState::stuck},
  };
  for (const Row& r : rows) {
    EXPECT_EQ(classify_contact_state(r.in), r.expected) << contact_state_name(r.expected);
  }
  EXPECT_EQ(classify_contact_state({0.0, 0.0, 0.2, false}, {.stuck_ratio = 0.5}), ContactState::stuck);
  EXPECT_EQ(contact_state_name(ContactState::gross_slip), "gross_slip");
  EXPECT_TRUE(ContactStateOptions{}.validate().empty());
  EXPECT_NE(ContactStateOptions{.stuck_ratio = 1.0}.validate().find("stuck_ratio"), std::string::npos);
  EXPECT_NE(ContactStateOptions{.limit_tolerance = -1.0}.validate().find("limit_tolerance"), std::string::npos);
  ContactStateCounts c;
  for (const Row& r : rows) c.add(r.expected);
  EXPECT_EQ(c.total(), static_cast<int>(rows.size()));
  EXPECT_EQ(c.slipping(), 4);  // 2 gross slip + 2 microslip
}

TEST(ContactState, LimitMeasuresSkipOpenSamples) {
  const std::vector<double> t = {0.0, 0.5, 2.0 - 1e-12, 1.0, 3.0};
  const std::vector<double> l = {1.0, 1.0, 2.0, 0.0, 4.0};  // the fourth open (no limit)
  const LimitMeasures m = limit_measures(t, l, 1e-9);
  EXPECT_DOUBLE_EQ(m.share, 1.0 / 5.0);
  EXPECT_DOUBLE_EQ(m.ratio, (2.0 - 1e-12) / 2.0);
  EXPECT_EQ(limit_measures({}, {}, 1e-9).share, 0.0);
  EXPECT_THROW((void)limit_measures(t, std::vector<double>(2, 1.0), 1e-9), std::invalid_argument);
}

// One point at constant pressure p = 1 MPa (μ = 0.4, k_T0 = 1.6e11 Pa/m, n = 0.3 for
// Gaul–Mayer) under g_T = a cos Ωt: sample 0 is the tip of the loop, so the force ratio is
// F̂/F_s of the closed-form symmetric loop (to the periodic solve's tolerance).
constexpr double kStatePressure = 1.0e6;
constexpr double kStateMu = 0.4;
constexpr double kStateStiffness = 1.6e11;
constexpr double kStateExponent = 0.3;

jc::ContactPoint state_test_point(bool gaul_mayer) {
  jc::ContactPointOptions o;
  o.normal = {2.0e6, 2.0e5, 0.0};
  o.friction_coefficient = kStateMu;
  o.stiffness_model = jc::TangentialStiffnessModel::constant;
  o.tangential_stiffness = kStateStiffness;
  o.gap_pressure_ratio = 1e-3;
  std::shared_ptr<const jc::TangentialLaw> law;
  if (gaul_mayer) {
    law = std::make_shared<jc::GaulMayerLaw>(kStateExponent);
  } else {
    law = std::make_shared<jc::JenkinsLaw>();
  }
  return jc::ContactPoint(o, law);
}

ContactPointReference state_test_reference(const jc::ContactPoint& point) {
  ContactPointReference r;
  r.gap << 0.0, 0.0, point.options().normal.gap_at_pressure(kStatePressure);
  r.traction << 0.0, 0.0, -kStatePressure;
  return r;
}

TEST(ContactState, ForceRatioIsTheClosedFormLoopsAndTheStateFollowsTheAmplitude) {
  const FourierBasis basis(5, 256);
  const double fs = kStateMu * kStatePressure;
  const jc::closed_form::MicroslipParameters params{kStateExponent, fs, kStateStiffness};
  const double g_max = jc::closed_form::full_slip_span(params);
  struct Case {
    bool gaul_mayer;
    double amplitude;  // of g_max
    ContactState expected;
  };
  // Gaul–Mayer: F̂/F_s ≈ (1 − n) a/g_max at small a: 7e-6 stuck-like, 0.035 microslip; a = 3 g_max
  // reaches the limit. Jenkins: elastic up to a = F_s/k = 0.7 g_max, then at the limit.
  for (const Case& c : {Case{true, 1e-5, ContactState::stuck}, Case{true, 0.05, ContactState::microslip},
                        Case{true, 0.5, ContactState::microslip}, Case{true, 3.0, ContactState::gross_slip},
                        Case{false, 0.2, ContactState::stuck}, Case{false, 0.69, ContactState::stuck},
                        Case{false, 3.0, ContactState::gross_slip}}) {
    SCOPED_TRACE(std::string(c.gaul_mayer ? "gaul-mayer" : "jenkins") + " a/g_max " + std::to_string(c.amplitude));
    const jc::ContactPoint point = state_test_point(c.gaul_mayer);
    const double a = c.amplitude * g_max;
    Eigen::MatrixXd dg = Eigen::MatrixXd::Zero(basis.size(), 3);
    dg(basis.cosine_index(1), 0) = 0.6 * a;
    dg(basis.cosine_index(1), 1) = 0.8 * a;
    const ContactPointAftResult r = evaluate_contact_point(point, state_test_reference(point), basis, dg);
    ASSERT_TRUE(r.converged) << r.message;
    const double expected_ratio = c.gaul_mayer ? jc::closed_form::symmetric_loop(a, params).force_amplitude / fs
                                               : std::min(1.0, kStateStiffness * a / fs);
    EXPECT_NEAR(r.limit_ratio, expected_ratio, 1e-9 * expected_ratio);  // the periodic solve's tolerance
    EXPECT_EQ(r.state, c.expected) << contact_state_name(r.state);
    EXPECT_EQ(r.limit_share > 0.0, c.expected == ContactState::gross_slip);
    EXPECT_EQ(r.open_fraction, 0.0);
  }
}

TEST(ContactState, NormalMotionThatOpensThePointGapsOrOpensIt) {
  const FourierBasis basis(3, 128);
  const jc::ContactPoint point = state_test_point(true);
  const ContactPointReference ref = state_test_reference(point);
  // p = p_ref exp(−λ δg_N) falls below the gapping floor 1e-3 p_N0 = 2e3 Pa at δg_N = 3.1e-5 m.
  Eigen::MatrixXd dg = Eigen::MatrixXd::Zero(basis.size(), 3);
  dg(basis.cosine_index(1), 2) = 5e-5;
  dg(basis.cosine_index(1), 0) = 1e-8;
  const ContactPointAftResult gapping = evaluate_contact_point(point, ref, basis, dg);
  ASSERT_TRUE(gapping.converged) << gapping.message;
  EXPECT_GT(gapping.open_fraction, 0.0);
  EXPECT_LT(gapping.open_fraction, 1.0);
  EXPECT_EQ(gapping.state, ContactState::gapping);
  dg.setZero();
  dg(0, 2) = 1e-3;  // a mean opening far beyond the floor
  const ContactPointAftResult open = evaluate_contact_point(point, ref, basis, dg);
  EXPECT_EQ(open.open_fraction, 1.0);
  EXPECT_EQ(open.state, ContactState::open);
  EXPECT_EQ(open.limit_ratio, 0.0);
}

}  // namespace
}  // namespace jointhb::hb
