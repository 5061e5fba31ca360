// Contact point (contact_point.hpp): pressure-dependent limits, gapping guard, consistent tangent
// and periodic sensitivity (with normal motion) against finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/contact/gaul_mayer_law.hpp"

namespace jc = jointhb::contact;
using jc::Vec2;
using jc::Vec3;

namespace {

jc::ContactPoint make_point(jc::TangentialStiffnessModel model) {
  jc::ContactPointOptions o;
  o.normal = {2.0e6, 2.0e5, 0.0};  // p_N0 = 2 MPa, λ = 2e5 1/m (σ = 5 µm)
  o.friction_coefficient = 0.4;
  o.stiffness_model = model;
  o.stiffness_ratio = 0.8;
  o.tangential_stiffness = 1.0e11;
  return jc::ContactPoint(o, std::make_shared<jc::GaulMayerLaw>(0.3));
}

}  // namespace

TEST(ContactPoint, LimitsFollowThePressure) {
  const auto cp = make_point(jc::TangentialStiffnessModel::proportional);
  const auto s = cp.tangential_state(-1.0e-6);
  const double p = 2.0e6 * std::exp(2.0e5 * 1.0e-6);
  EXPECT_NEAR(s.pressure, p, 1e-9 * p);
  EXPECT_NEAR(s.limits.slip_limit, 0.4 * p, 1e-9 * p);
  EXPECT_NEAR(s.limits.stiffness, 0.8 * 2.0e5 * p, 1e-9 * 2.0e5 * p);  // χ λ p_N
}

TEST(ContactPoint, OpenPointHasZeroTractionAndFiniteTangent) {
  const auto cp = make_point(jc::TangentialStiffnessModel::proportional);
  const double far = 1.0e-3;  // exp(-200): far below the gapping floor
  const auto st = cp.step(Vec2(1e3, 0.0), Vec3(0, 0, far), Vec3(1e-6, 2e-6, far));
  EXPECT_TRUE(st.open);
  EXPECT_EQ(st.traction.head<2>().norm(), 0.0);
  EXPECT_TRUE(st.tangent.allFinite());
  EXPECT_GE(st.traction.z(), -1e-70);  // t_N = -p_N, tiny
}

TEST(ContactPoint, ConsistentTangentMatchesFiniteDifferences) {
  for (auto model :
       {jc::TangentialStiffnessModel::proportional, jc::TangentialStiffnessModel::constant}) {
    const auto cp = make_point(model);
    const Vec2 t0(3.0e5, -1.0e5);
    const Vec3 g0(0.0, 0.0, -2.0e-6);
    const Vec3 g1(4.0e-6, 1.0e-6, -1.5e-6);
    const auto st = cp.step(t0, g0, g1);
    for (int j = 0; j < 3; ++j) {
      const double h = 1e-12;
      const Vec3 e = Vec3::Unit(j);
      const Vec3 fd =
          (cp.step(t0, g0, g1 + h * e).traction - cp.step(t0, g0, g1 - h * e).traction) / (2 * h);
      EXPECT_LT((fd - st.tangent.col(j)).norm(), 1e-6 * st.tangent.norm()) << "column " << j;
    }
  }
}

TEST(ContactPoint, PeriodicSensitivityWithNormalMotionMatchesFiniteDifferences) {
  const auto cp = make_point(jc::TangentialStiffnessModel::proportional);
  const int n = 40;
  std::vector<Vec3> path;
  for (int i = 0; i < n; ++i) {
    const double th = 2.0 * std::numbers::pi * i / n;
    path.emplace_back(3e-6 * std::cos(th), 1e-6 * std::sin(2 * th),
                      -2e-6 + 1.5e-6 * std::cos(th + 0.4));
  }
  const auto base = cp.periodic(path);
  ASSERT_EQ(base.tangential.termination, jointhb::Termination::converged);
  Eigen::MatrixXd dir(3 * n, 1);
  for (int i = 0; i < n; ++i) {
    const double th = 2.0 * std::numbers::pi * i / n;
    dir(3 * i, 0) = std::sin(th);
    dir(3 * i + 1, 0) = 0.5 * std::cos(th);
    dir(3 * i + 2, 0) = 0.3 * std::cos(2 * th);
  }
  const Eigen::MatrixXd analytic = jc::ContactPoint::periodic_sensitivity(base, dir);
  const double h = 1e-12;
  auto plus = path, minus = path;
  for (int i = 0; i < n; ++i) {
    plus[i] += h * dir.block<3, 1>(3 * i, 0);
    minus[i] -= h * dir.block<3, 1>(3 * i, 0);
  }
  const auto rp = cp.periodic(plus), rm = cp.periodic(minus);
  double error = 0.0, size = 0.0;
  for (int i = 0; i < n; ++i) {
    const Vec3 fd = (rp.traction[i] - rm.traction[i]) / (2 * h);
    error = std::max(error, (fd - analytic.block<3, 1>(3 * i, 0)).norm());
    size = std::max(size, fd.norm());
  }
  EXPECT_LT(error, 1e-5 * size);
}

TEST(ContactPoint, InvalidOptionsNameTheField) {
  jc::ContactPointOptions o;
  o.friction_coefficient = -1.0;
  try {
    jc::ContactPoint cp(o, std::make_shared<jc::GaulMayerLaw>(0.3));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("friction_coefficient"), std::string::npos);
  }
}
