// The cutoff exponential law (N-1) and the linear penalty law (N-2) of normal_law.hpp, and the
// contact points built on them: continuity at the cutoff, k_N = -dp_N/dg_N and dk_N/dg_N by
// central differences, the inverse, and a frictionless point that carries no tangential traction.
#include <gtest/gtest.h>

#include <cmath>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/jenkins_law.hpp"
#include "jointhb/contact/normal_law.hpp"

namespace jointhb::contact {
namespace {

NormalLaw cutoff_law() {
  NormalLaw law{3.0e6, 2.0e5, 1.0e-6};
  law.cutoff_gap = 2.0e-5;  // 3.8 σ above g_N0: p_c = p_N0 e^{-3.8} ≈ 67 kPa
  return law;
}

NormalLaw linear_law() {
  NormalLaw law;
  law.kind = NormalLawKind::linear;
  law.reference_gap = -2.0e-6;
  law.penalty_stiffness = 5.0e12;
  return law;
}

TEST(NormalLawVariants, CutoffLawVanishesContinuouslyAtTheCutoff) {
  const NormalLaw law = cutoff_law();
  ASSERT_EQ(law.validate(), "");
  const double pc = 3.0e6 * std::exp(-2.0e5 * (2.0e-5 - 1.0e-6));
  for (double gap = -1e-5; gap < 2e-5; gap += 1.3e-6) {  // (N-1)
    const double expected = 3.0e6 * std::exp(-2.0e5 * (gap - 1.0e-6)) - pc;
    EXPECT_NEAR(law.pressure(gap), expected, 1e-12 * 3.0e6) << gap;
  }
  EXPECT_NEAR(law.pressure(2.0e-5 * (1.0 - 1e-12)), 0.0, 1e-9 * 3.0e6);
  EXPECT_EQ(law.pressure(2.0e-5), 0.0);
  EXPECT_EQ(law.pressure(1.0), 0.0);
  EXPECT_EQ(law.stiffness(2.5e-5), 0.0);
  EXPECT_EQ(law.stiffness_slope(2.5e-5), 0.0);
  const double h = 1e-3 / law.decay;
  for (double gap = -1e-5; gap < 1.9e-5; gap += 2.9e-6) {
    const double slope = (law.pressure(gap + h) - law.pressure(gap - h)) / (2.0 * h);
    EXPECT_NEAR(law.stiffness(gap) / -slope, 1.0, 1e-6) << gap;
    const double curvature = (law.stiffness(gap + h) - law.stiffness(gap - h)) / (2.0 * h);
    EXPECT_NEAR(law.stiffness_slope(gap) / curvature, 1.0, 1e-6) << gap;
    EXPECT_NEAR(law.gap_at_pressure(law.pressure(gap)), gap, 1e-15 + 1e-9 * std::abs(gap)) << gap;
  }
  // Without a cutoff the law is eq. (6) exactly.
  NormalLaw plain = law;
  plain.cutoff_gap = std::numeric_limits<double>::infinity();
  EXPECT_EQ(plain.pressure(3e-5), 3.0e6 * std::exp(-2.0e5 * (3e-5 - 1.0e-6)));
}

TEST(NormalLawVariants, LinearLawIsAPenaltyClosedUpToItsReferenceGap) {
  const NormalLaw law = linear_law();
  ASSERT_EQ(law.validate(), "");
  EXPECT_DOUBLE_EQ(law.pressure(-3.0e-6), 5.0e12 * 1.0e-6);
  EXPECT_EQ(law.stiffness(-3.0e-6), 5.0e12);
  EXPECT_EQ(law.pressure(-2.0e-6), 0.0);  // closed at g_N0, without pressure
  EXPECT_EQ(law.stiffness(-2.0e-6), 5.0e12);
  EXPECT_EQ(law.pressure(0.0), 0.0);
  EXPECT_EQ(law.stiffness(0.0), 0.0);
  EXPECT_EQ(law.stiffness_slope(-3.0e-6), 0.0);
  EXPECT_NEAR(law.gap_at_pressure(5.0e6), -3.0e-6, 1e-20);
}

TEST(NormalLawVariants, ValidateNamesTheField) {
  NormalLaw law = cutoff_law();
  law.cutoff_gap = 0.5e-6;  // below g_N0
  EXPECT_NE(law.validate().find("cutoff_gap"), std::string::npos) << law.validate();
  law = linear_law();
  law.penalty_stiffness = 0.0;
  EXPECT_NE(law.validate().find("penalty_stiffness"), std::string::npos) << law.validate();
}

ContactPoint point(const NormalLaw& normal, double mu, TangentialStiffnessModel model) {
  ContactPointOptions o;
  o.normal = normal;
  o.friction_coefficient = mu;
  o.stiffness_model = model;
  o.stiffness_ratio = 0.8;
  o.tangential_stiffness = 2.0e12;
  return ContactPoint(o, std::make_shared<GaulMayerLaw>(0.4));
}

TEST(NormalLawVariants, ConsistentTangentOfTheNewLawsMatchesFiniteDifferences) {
  for (const NormalLaw& normal : {cutoff_law(), linear_law()}) {
    for (auto model : {TangentialStiffnessModel::proportional, TangentialStiffnessModel::constant}) {
      const ContactPoint cp = point(normal, 0.4, model);
      const Vec2 t0(2.0e4, -1.0e4);
      const Vec3 g0(0.0, 0.0, -4.0e-6), g1(1.0e-7, 3.0e-8, -3.5e-6);
      const ContactStep st = cp.step(t0, g0, g1);
      ASSERT_FALSE(st.open);
      for (int j = 0; j < 3; ++j) {
        const double h = 1e-12;
        const Vec3 e = Vec3::Unit(j);
        const Vec3 fd = (cp.step(t0, g0, g1 + h * e).traction - cp.step(t0, g0, g1 - h * e).traction) / (2 * h);
        EXPECT_LT((fd - st.tangent.col(j)).norm(), 1e-6 * st.tangent.norm())
            << "column " << j << (normal.kind == NormalLawKind::linear ? " linear" : " cutoff");
      }
    }
  }
}

TEST(NormalLawVariants, FrictionlessPointCarriesOnlyPressure) {
  const ContactPoint cp = point(cutoff_law(), 0.0, TangentialStiffnessModel::proportional);
  const TangentialState s = cp.tangential_state(-5e-6);
  EXPECT_FALSE(s.open);
  EXPECT_GT(s.pressure, 0.0);
  EXPECT_EQ(s.limits.stiffness, 0.0);
  EXPECT_EQ(s.limits.slip_limit, 0.0);
  const ContactStep st = cp.step(Vec2(0.0, 0.0), Vec3(0, 0, -5e-6), Vec3(3e-6, -1e-6, -5e-6));
  EXPECT_EQ(st.traction.head<2>().norm(), 0.0);
  EXPECT_EQ((st.tangent.topLeftCorner<2, 3>().norm()), 0.0);
  EXPECT_EQ(st.dissipation, 0.0);
  EXPECT_NEAR(st.traction.z(), -s.pressure, 1e-12 * s.pressure);
  // Beyond the cutoff the point is open: nothing at all.
  const ContactStep beyond = cp.step(Vec2(0.0, 0.0), Vec3(0, 0, 3e-5), Vec3(0, 0, 3e-5));
  EXPECT_TRUE(beyond.open);
  EXPECT_EQ(beyond.traction.norm(), 0.0);
  EXPECT_EQ(beyond.tangent.norm(), 0.0);
}

// p_N(g + δ) − p_N(g) for a tiny δ keeps its relative accuracy (pressure_change), where the plain
// difference of two preload-sized pressures loses it; reference: the Taylor series
// p (−λδ + (λδ)²/2 − (λδ)³/6), exact to far below round-off at λδ ≤ 1e-4. Across the cutoff
// and on the linear law it equals the plain difference.
TEST(NormalLawVariants, PressureChangeOfATinyMotionKeepsItsRelativeAccuracy) {
  for (const NormalLaw& law : {NormalLaw{3.0e6, 2.0e5, 1.0e-6}, cutoff_law()}) {
    const double gap = -4.0e-6;
    const double p = law.pressure(gap) + (std::isinf(law.cutoff_gap) ? 0.0 : 3.0e6 * std::exp(-2.0e5 * (law.cutoff_gap - 1.0e-6)));
    double worst_plain = 0.0;
    for (double delta : {1e-24, -3e-22, 1e-18, -2e-15, 5e-13, 1e-10}) {
      const double x = 2.0e5 * delta;
      const double series = p * (-x + x * x / 2.0 - x * x * x / 6.0);
      EXPECT_NEAR(law.pressure_change(gap, delta) / series, 1.0, 1e-14) << delta;
      worst_plain = std::max(worst_plain, std::abs((law.pressure(gap + delta) - law.pressure(gap)) / series - 1.0));
    }
    EXPECT_GT(worst_plain, 1e-3);  // what the plain difference loses (the test can tell them apart)
  }
  const NormalLaw cut = cutoff_law();  // one side beyond the cutoff: the plain difference
  EXPECT_EQ(cut.pressure_change(1.9e-5, 2.0e-6), cut.pressure(2.1e-5) - cut.pressure(1.9e-5));
  const NormalLaw lin = linear_law();
  EXPECT_DOUBLE_EQ(lin.pressure_change(-3.0e-6, 1e-20), -5.0e12 * 1e-20);
  EXPECT_EQ(lin.pressure_change(-2.5e-6, 1.0e-6), lin.pressure(-1.5e-6) - lin.pressure(-2.5e-6));
}

}  // namespace
}  // namespace jointhb::contact
