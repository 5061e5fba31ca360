// AFT of one 3D contact point and of an interface (hb/contact_point_aft.hpp), against independent
// references: central differences of the whole evaluation (Jacobian), the stuck linear tangent at
// the reference (small amplitude, O(a²) by the error ratio), the modified-Bessel series of the
// exponential normal law under harmonic normal motion, the closed-form dissipation of the
// tangential laws, the loop integral from the samples, and the thread count.
#include "jointhb/hb/contact_point_aft.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "jointhb/contact/closed_forms.hpp"
#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/contact/jenkins_law.hpp"

namespace jointhb::hb {
namespace {

namespace jc = jointhb::contact;
using Model = jc::TangentialStiffnessModel;

// p_N0 = 2 MPa, λ = 2e5 1/m (σ = 5 µm), μ = 0.4, χ = 0.8; reference pressure 1 MPa. With the
// proportional model g_max = μ/((1−n) χ λ) = 3.6 µm for n = 0.3, independent of the pressure.
constexpr double kLambda = 2.0e5;
constexpr double kMu = 0.4;
constexpr double kChi = 0.8;
constexpr double kExponent = 0.3;
constexpr double kPref = 1.0e6;
constexpr double kStiffness = kChi * kLambda * kPref;  // k_T at the reference (both models)
const double kGmax = kMu * kPref / ((1.0 - kExponent) * kStiffness);

jc::ContactPoint make_point(bool gaul_mayer, Model model, double gap_ratio = 1e-3) {
  jc::ContactPointOptions o;
  o.normal = {2.0e6, kLambda, 0.0};
  o.friction_coefficient = kMu;
  o.stiffness_model = model;
  o.stiffness_ratio = kChi;
  o.tangential_stiffness = kStiffness;
  o.gap_pressure_ratio = gap_ratio;
  std::shared_ptr<const jc::TangentialLaw> law;
  if (gaul_mayer) {
    law = std::make_shared<jc::GaulMayerLaw>(kExponent);
  } else {
    law = std::make_shared<jc::JenkinsLaw>();
  }
  return jc::ContactPoint(o, law);
}

ContactPointReference reference(const jc::ContactPoint& point, double t1 = 0.0, double t2 = 0.0) {
  ContactPointReference r;
  r.gap << 0.3e-6, -0.2e-6, point.options().normal.gap_at_pressure(kPref);
  r.traction << t1, t2, -kPref;
  return r;
}

// δG (m × 3) with harmonics 1..3 (as far as the basis has them), a mean, and amplitudes
// scale_t (tangential) and scale_n (normal).
Eigen::MatrixXd motion(const FourierBasis& basis, double scale_t, double scale_n) {
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(basis.size(), 3);
  const auto set = [&](int order, int component, double a, double b) {
    const int c = basis.cosine_index(order);
    if (c < 0) return;
    g(c, component) = a;
    g(c + 1, component) = b;
  };
  g.row(0) << 0.1 * scale_t, -0.05 * scale_t, 0.1 * scale_n;
  set(1, 0, scale_t, 0.3 * scale_t);
  set(1, 1, -0.2 * scale_t, 0.5 * scale_t);
  set(1, 2, 0.6 * scale_n, 0.4 * scale_n);
  set(2, 0, 0.1 * scale_t, -0.05 * scale_t);
  set(2, 2, -0.1 * scale_n, 0.05 * scale_n);
  set(3, 1, 0.07 * scale_t, 0.0);
  set(3, 2, 0.0, 0.1 * scale_n);
  return g;
}

// Central differences of ΔT along every coefficient of δG, in the Jacobian's ordering.
Eigen::MatrixXd finite_difference_jacobian(const jc::ContactPoint& point,
                                           const ContactPointReference& ref,
                                           const FourierBasis& basis, const Eigen::MatrixXd& dg,
                                           double h) {
  const Eigen::Index m = basis.size();
  Eigen::MatrixXd j(3 * m, 3 * m);
  for (Eigen::Index q = 0; q < 3 * m; ++q) {
    Eigen::MatrixXd plus = dg, minus = dg;
    plus(q % m, q / m) += h;
    minus(q % m, q / m) -= h;
    const Eigen::MatrixXd d = (evaluate_contact_point(point, ref, basis, plus).traction -
                               evaluate_contact_point(point, ref, basis, minus).traction) /
                              (2.0 * h);
    j.col(q) = d.reshaped();  // column-major: component-major rows c·m + j
  }
  return j;
}

// The Jacobian by the contact module's general sensitivity (ContactPoint::periodic_sensitivity)
// along the 3m basis functions, A · ∂t(t_i)/∂g(t_j) · E: the route the library specialises.
Eigen::MatrixXd general_jacobian(const jc::ContactPoint& point, const ContactPointReference& ref,
                                 const FourierBasis& basis, const Eigen::MatrixXd& dg) {
  const Eigen::MatrixXd g = basis.to_time(dg);
  const Eigen::MatrixXd& e = basis.synthesis_matrix();
  const Eigen::Index n = e.rows(), m = e.cols();
  std::vector<jc::Vec3> path(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    path[static_cast<std::size_t>(i)] = ref.gap + g.row(i).transpose();
  jc::PeriodicStateOptions po;
  po.tolerance = 1e-14;
  po.reference_traction = ref.traction.head<2>();
  po.reference_slip = ref.gap.head<2>();
  const auto state = point.periodic(path, po);
  Eigen::MatrixXd perturbation = Eigen::MatrixXd::Zero(3 * n, 3 * m);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index d = 0; d < 3; ++d) perturbation.block(3 * i + d, d * m, 1, m) = e.row(i);
  }
  const Eigen::MatrixXd dt = jc::ContactPoint::periodic_sensitivity(state, perturbation);
  const Eigen::MatrixXd a = basis.analysis_matrix();
  Eigen::MatrixXd j(3 * m, 3 * m);
  for (Eigen::Index c = 0; c < 3; ++c) {
    Eigen::MatrixXd component(n, 3 * m);
    for (Eigen::Index i = 0; i < n; ++i) component.row(i) = dt.row(3 * i + c);
    j.middleRows(c * m, m) = a * component;
  }
  return j;
}

// Largest error of the 3 × 3 blocks (m × m each) of a Jacobian, each relative to the largest
// entry of its block row in the reference: the normal row can exceed the tangential ones by orders
// of magnitude (λ p_N grows exponentially on closure), so a global scale would hide errors in the
// tangential rows, and a block's own scale would magnify round-off in blocks that vanish.
double blockwise_error(const Eigen::MatrixXd& j, const Eigen::MatrixXd& reference, Eigen::Index m) {
  double worst = 0.0;
  for (Eigen::Index c = 0; c < 3; ++c) {
    const double scale = reference.middleRows(c * m, m).cwiseAbs().maxCoeff();
    const double error = (j - reference).middleRows(c * m, m).cwiseAbs().maxCoeff();
    worst = std::max(worst, scale > 0.0 ? error / scale : (error > 0.0 ? 1.0 : 0.0));
  }
  return worst;
}

struct JacobianCase {
  const char* name;
  bool gaul_mayer;
  Model model;
  double scale_t;  // / g_max
  double scale_n;  // / (1/λ)
  bool expect_open;
  bool expect_slip;
};

TEST(ContactPointAft, JacobianMatchesCentralDifferences) {
  const FourierBasis basis(3, 128);
  const JacobianCase cases[] = {
      {"gaul-mayer microslip", true, Model::proportional, 0.3, 0.5, false, true},
      {"gaul-mayer gross slip", true, Model::proportional, 3.0, 0.5, false, true},
      {"gaul-mayer partially open", true, Model::proportional, 1.0, 8.0, true, true},
      {"gaul-mayer constant k, partially open", true, Model::constant, 1.0, 8.0, true, true},
      {"jenkins stick-slip", false, Model::proportional, 0.5, 0.5, false, true},
      {"jenkins partially open", false, Model::constant, 0.5, 8.0, true, true},
  };
  ContactPointAftOptions with_jacobian;
  with_jacobian.jacobian = true;
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const auto point = make_point(c.gaul_mayer, c.model);
    const auto ref = reference(point, 0.1 * kMu * kPref, -0.05 * kMu * kPref);
    const Eigen::MatrixXd dg = motion(basis, c.scale_t * kGmax, c.scale_n / kLambda);
    const auto r = evaluate_contact_point(point, ref, basis, dg, with_jacobian);
    ASSERT_TRUE(r.converged) << r.message;
    EXPECT_EQ(r.open_fraction > 0.0, c.expect_open);
    EXPECT_LT(r.open_fraction, 1.0);
    EXPECT_EQ(!r.stuck, c.expect_slip);
    EXPECT_EQ(r.shortcut, ContactPointShortcut::none);
    const double h = 1e-6 * dg.cwiseAbs().maxCoeff();
    const Eigen::MatrixXd fd = finite_difference_jacobian(point, ref, basis, dg, h);
    const Eigen::Index m = basis.size();
    const double error = blockwise_error(r.jacobian, fd, m);
    std::printf("  %-40s blockwise |J - J_fd|/|J_fd| = %.2e, open %.2f, periods %d\n", c.name,
                error, r.open_fraction, r.iterations);
    EXPECT_LT(error, 1e-6);
    EXPECT_LT(blockwise_error(r.jacobian, general_jacobian(point, ref, basis, dg), m), 1e-12);
    // The tangential-by-normal block couples the directions: it must be there.
    EXPECT_GT(r.jacobian.block(0, 2 * m, 2 * m, m).cwiseAbs().maxCoeff(),
              1e-3 * r.jacobian.block(0, 0, 2 * m, 2 * m).cwiseAbs().maxCoeff());
  }
}

TEST(ContactPointAft, ShortcutsEqualThePeriodicSolve) {
  const FourierBasis basis(3, 128);
  ContactPointAftOptions on, off;
  on.jacobian = off.jacobian = true;
  off.use_shortcuts = false;
  struct Case {
    const char* name;
    bool gaul_mayer;
    double gap_offset;  // added to the reference's normal gap (λ units)
    double scale_t, scale_n;
    ContactPointShortcut expected;
  };
  const Case cases[] = {
      {"jenkins stuck, constant k", false, 0.0, 0.05, 0.5, ContactPointShortcut::stuck},
      {"open throughout", true, 20.0, 0.5, 2.0, ContactPointShortcut::open},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const auto point = make_point(c.gaul_mayer, Model::constant);
    auto ref = reference(point, 0.3 * kMu * kPref, 0.2 * kMu * kPref);
    ref.gap.z() += c.gap_offset / kLambda;
    const Eigen::MatrixXd dg = motion(basis, c.scale_t * kGmax, c.scale_n / kLambda);
    const auto fast = evaluate_contact_point(point, ref, basis, dg, on);
    const auto full = evaluate_contact_point(point, ref, basis, dg, off);
    EXPECT_EQ(fast.shortcut, c.expected);
    EXPECT_EQ(full.shortcut, ContactPointShortcut::none);
    EXPECT_EQ(fast.stuck, full.stuck);
    EXPECT_EQ(fast.open_fraction, full.open_fraction);
    EXPECT_EQ(fast.dissipation, 0.0);
    EXPECT_EQ(full.dissipation, 0.0);
    const double scale = ref.traction.norm();
    EXPECT_LT((fast.traction - full.traction).cwiseAbs().maxCoeff(), 1e-13 * scale);
    EXPECT_LT(blockwise_error(fast.jacobian, full.jacobian, basis.size()), 1e-13);
  }
}

// Small amplitude: ΔT = C_ref δG + O(a²) with the sticking tangent at the reference,
//   C_ref = diag(k_T, k_T, λ p_ref) on every coefficient,
// except the mean of the tangential traction under Gaul–Mayer. That law has no elastic range and
// no memory of reversal points: the steady loop centres itself on the midrange of the slip, so
// its small-amplitude limit t_T ≈ k (g_T − midrange) is positively homogeneous but not linear in
// δG, and any mean tangential traction relaxes (docs/theory.md §5, §10). With a half-wave
// symmetric tangential path (mean + odd harmonics) the midrange is the mean: ΔT_T,0 = −t_ref,T
// (0 here) whatever the mean slip, and the harmonics follow C_ref. The normal motion is arbitrary.
// The error must fall by 4 when a halves.
TEST(ContactPointAft, SmallAmplitudeIsTheStuckTangentToSecondOrder) {
  const FourierBasis basis(3, 256);
  struct Case {
    const char* name;
    bool gaul_mayer;
    Model model;
    double t_ref;   // tangential reference traction / μ p_ref
    double normal;  // normal amplitude relative to the tangential one (in 1/λ and g_max units)
  };
  const Case cases[] = {
      {"gaul-mayer, constant k, 3D motion", true, Model::constant, 0.0, 1.0},
      {"gaul-mayer, proportional k, tangential motion", true, Model::proportional, 0.0, 0.0},
      {"jenkins, constant k, t_ref != 0, 3D motion", false, Model::constant, 0.5, 1.0},
  };
  const Eigen::Index m = basis.size();
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const auto point = make_point(c.gaul_mayer, c.model);
    const auto ref = reference(point, c.t_ref * 0.6 * kMu * kPref, c.t_ref * 0.8 * kMu * kPref);
    const auto error = [&](double a) {
      Eigen::MatrixXd dg = motion(basis, a * kGmax, c.normal * a / kLambda);
      if (c.gaul_mayer) dg.block(basis.cosine_index(2), 0, 2, 2).setZero();  // half-wave symmetric
      const auto r = evaluate_contact_point(point, ref, basis, dg);
      EXPECT_TRUE(r.converged) << r.message;
      Eigen::MatrixXd linear(m, 3);
      linear.leftCols<2>() = kStiffness * dg.leftCols<2>();
      if (c.gaul_mayer) linear.row(0).head<2>() = -ref.traction.head<2>().transpose();
      linear.col(2) = kLambda * kPref * dg.col(2);
      return (r.traction - linear).cwiseAbs().maxCoeff();
    };
    const double e1 = error(4e-3), e2 = error(2e-3), e3 = error(1e-3);
    std::printf("  %-48s |ΔT - C δG| / (k a g_max) = %.2e at a = 4e-3 g_max, ratios %.3f %.3f\n",
                c.name, e1 / (kStiffness * 4e-3 * kGmax), e1 / e2, e2 / e3);
    EXPECT_LT(e1, 0.05 * kStiffness * 4e-3 * kGmax);  // well below the linear response
    EXPECT_NEAR(e1 / e2, 4.0, 0.3);
    EXPECT_NEAR(e2 / e3, 4.0, 0.3);
  }
}

// A Jenkins point that sticks throughout without normal motion is exactly the spring anchored at
// the reference, whatever the stiffness model and the path: ΔT_T = k_T δG_T (mean included).
TEST(ContactPointAft, StuckJenkinsIsTheAnchoredSpring) {
  const FourierBasis basis(3, 128);
  for (const Model model : {Model::proportional, Model::constant}) {
    const auto point = make_point(false, model);
    const auto ref = reference(point, 0.3 * kMu * kPref, 0.4 * kMu * kPref);
    const Eigen::MatrixXd dg = motion(basis, 0.1 * kGmax, 0.0);
    const auto r = evaluate_contact_point(point, ref, basis, dg);
    EXPECT_TRUE(r.stuck);
    EXPECT_EQ(r.dissipation, 0.0);
    EXPECT_LT((r.traction.leftCols<2>() - kStiffness * dg.leftCols<2>()).cwiseAbs().maxCoeff(),
              1e-12 * kMu * kPref);
    EXPECT_EQ(r.traction.col(2).cwiseAbs().maxCoeff(), 0.0);
  }
}

// A Gaul–Mayer point at small amplitude about a reference with a tangential traction: the mean
// relaxes to zero, i.e. ΔT_T,0 = −t_ref,T, not the O(a) of a linear tangent (docs/theory.md §5).
TEST(ContactPointAft, GaulMayerRelaxesTheReferenceTraction) {
  const FourierBasis basis(3, 128);
  const auto point = make_point(true, Model::proportional);
  const auto ref = reference(point, 0.3 * kMu * kPref, -0.2 * kMu * kPref);
  Eigen::MatrixXd dg = Eigen::MatrixXd::Zero(basis.size(), 3);
  dg(1, 0) = 1e-3 * kGmax;
  const auto r = evaluate_contact_point(point, ref, basis, dg);
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_NEAR(r.traction(0, 0), -ref.traction.x(), 1e-9 * kMu * kPref);
  EXPECT_NEAR(r.traction(0, 1), -ref.traction.y(), 1e-9 * kMu * kPref);
}

// The proportional stiffness k = χ λ p_N under elliptical motion, δg_T1 = a_T cos θ,
// δg_N = a_N sin θ: the elastic increments no longer telescope, ∮ k dg_T = π k_ref λ a_N a_T per
// period, while the Gaul–Mayer loop contracts offsets only by 1 − M ≈ 2n F̂/L = 2n k a_T/L. The
// mean tangential traction is therefore ratcheted by
//   Δt̄_T1 = π λ a_N μ p_ref / (2n)     (T-21, first order in a_N, independent of a_T),
// an O(a) mean that no linear tangent at the reference contains. Its sign follows the phase.
TEST(ContactPointAft, ProportionalStiffnessRatchetsTheMeanOfGaulMayer) {
  const FourierBasis basis(3, 256);
  const auto point = make_point(true, Model::proportional);
  const auto ref = reference(point);
  const double predicted_per_a = std::numbers::pi * kMu * kPref / (2.0 * kExponent);  // λa_N = a
  double previous = 0.0;
  for (const double a : {2e-3, 1e-3}) {
    Eigen::MatrixXd dg = Eigen::MatrixXd::Zero(basis.size(), 3);
    dg(basis.cosine_index(1), 0) = a * kGmax;        // a_T cos θ
    dg(basis.cosine_index(1) + 1, 2) = a / kLambda;  // a_N sin θ
    const auto r = evaluate_contact_point(point, ref, basis, dg);
    ASSERT_TRUE(r.converged) << r.message;
    const double deviation = r.traction(0, 0) / (predicted_per_a * a) - 1.0;
    EXPECT_LT(std::abs(deviation), 0.01 * a / 1e-3) << a;
    std::printf("  a = %.0e: mean Δt_T1 / (π λ a_N μ p_ref/(2n)) - 1 = %.2e\n", a, deviation);
    if (previous != 0.0) {
      EXPECT_NEAR(previous / deviation, 2.0, 0.2);  // O(a)
    }
    previous = deviation;
    dg *= -1.0;  // the opposite phase in both components keeps the ellipse's sense
    const auto same = evaluate_contact_point(point, ref, basis, dg);
    EXPECT_NEAR(same.traction(0, 0), r.traction(0, 0), 1e-6 * std::abs(r.traction(0, 0)));
    dg.col(2) *= -1.0;  // reversed sense: the ratchet reverses
    const auto reversed = evaluate_contact_point(point, ref, basis, dg);
    EXPECT_NEAR(reversed.traction(0, 0), -r.traction(0, 0), 1e-6 * std::abs(r.traction(0, 0)));
  }
}

// A Jenkins point with k = χ λ p_N that sticks under elliptical motion drifts by ∮ k dg_T per
// period (M = I, nothing contracts the offset) until it reaches the limit and slides there: its
// steady state lies on the limit, thousands of periods away (docs/theory.md §10). Tangential
// cos θ and normal sin θ motion (a quarter period out of phase): the T-21 ratchet.
Eigen::MatrixXd ratcheting_motion(const FourierBasis& basis) {
  Eigen::MatrixXd dg = Eigen::MatrixXd::Zero(basis.size(), 3);
  dg(basis.cosine_index(1), 0) = 1e-3 * kGmax;
  dg(basis.cosine_index(1) + 1, 2) = 1e-3 / kLambda;
  return dg;
}

// The periodic solver crosses the creep by extrapolated fixed-point steps (docs/theory.md §5) and
// finds the state that brute-force cycling of exact steps reaches; with too few periods allowed
// it reports the point as not converged, naming it.
TEST(ContactPointAft, StuckJenkinsRatchetReachesTheStateOfCyclingOrIsReported) {
  const FourierBasis basis(3, 128);
  const auto point = make_point(false, Model::proportional);
  const auto ref = reference(point);
  const Eigen::MatrixXd dg = ratcheting_motion(basis);
  const auto r = evaluate_contact_point(point, ref, basis, dg);
  ASSERT_TRUE(r.converged) << r.message;
  // Independent checks with exact steps: one period from the solver's state returns to it, and
  // brute-force cycling from the anchored reference creeps towards it (still far after 20 000
  // periods: the creep is what the solver crosses).
  const Eigen::MatrixXd g = basis.to_time(dg);
  std::vector<jc::Vec3> path;
  for (Eigen::Index i = 0; i < g.rows(); ++i) path.push_back(ref.gap + g.row(i).transpose());
  const auto period = [&](jc::Vec2 t) {
    for (std::size_t i = 0; i < path.size(); ++i) t = point.step(t, path[i], path[(i + 1) % path.size()]).traction.head<2>();
    return t;
  };
  const double limit = point.tangential_state(path[0].z()).limits.slip_limit;
  const jc::Vec2 steady = r.traction_samples.row(0).head<2>().transpose() + ref.traction.head<2>();
  EXPECT_LT((period(steady) - steady).norm(), 1e-9 * limit);
  jc::Vec2 t = ref.traction.head<2>() + point.tangential_state(path[0].z()).limits.stiffness * (path[0] - ref.gap).head<2>();
  double previous = (t - steady).norm();
  for (int block = 0; block < 4; ++block) {
    for (int k = 0; k < 5000; ++k) t = period(t);
    const double distance = (t - steady).norm();
    EXPECT_LT(distance, previous);
    previous = distance;
  }
  std::printf("ratchet: the solver's steady state |t_T| = %.6g (limit %.6g) in %d periods; cycling after 20 000 periods "
              "still %.3g away\n", steady.norm(), limit, r.iterations, previous);
  EXPECT_LE(steady.norm(), limit * (1.0 + 1e-12));
  ContactPointAftOptions few;
  few.max_iterations = 3;
  const auto cut = evaluate_contact_point(point, ref, basis, dg, few);
  EXPECT_FALSE(cut.converged);
  EXPECT_FALSE(cut.message.empty());
  const std::vector<jc::ContactPoint> laws{point};
  const std::vector<ContactPointReference> refs{ref};
  const auto all = evaluate_interface_aft(laws, refs, basis, dg, few);
  EXPECT_FALSE(all.converged);
  EXPECT_NE(all.message.find("points[0]"), std::string::npos) << all.message;
}

// The drift acceptance (ContactPointAftOptions::drift_limit/drift_ratio): the same ratcheting
// point is accepted only when its drift per period is within the stated bound, and then reports
// the drift and the flag; a bound just below the drift still rejects it.
TEST(ContactPointAft, RatchetIsAcceptedOnlyWithinTheDriftBound) {
  const FourierBasis basis(3, 128);
  const auto point = make_point(false, Model::proportional);
  const auto ref = reference(point);
  const Eigen::MatrixXd dg = ratcheting_motion(basis);
  ContactPointAftOptions o;
  o.max_iterations = 3;  // stopped in the middle of the creep
  const auto strict = evaluate_contact_point(point, ref, basis, dg, o);
  ASSERT_FALSE(strict.converged);
  ASSERT_GT(strict.drift, 0.0);
  o.drift_limit = 1.01 * strict.drift;
  const auto loose = evaluate_contact_point(point, ref, basis, dg, o);
  EXPECT_TRUE(loose.converged);
  EXPECT_TRUE(loose.drifting);
  EXPECT_NEAR(loose.drift, strict.drift, 1e-12 * strict.drift);
  EXPECT_TRUE(loose.traction.allFinite());
  o.drift_limit = 0.99 * strict.drift;
  const auto tight = evaluate_contact_point(point, ref, basis, dg, o);
  EXPECT_FALSE(tight.converged);
  EXPECT_FALSE(tight.drifting);
  o.drift_limit = -1.0;
  EXPECT_THROW(evaluate_contact_point(point, ref, basis, dg, o), std::invalid_argument);
}

// Pure normal motion δg_N = a cos θ: p(θ) = p_ref exp(−λa cos θ)
//   = p_ref [I_0(λa) + 2 Σ_k (−1)^k I_k(λa) cos kθ],
// so Δt_N has the mean −p_ref (I_0(λa) − 1) (the rectified normal force: the mean pressure rises),
// cosine coefficients −2 p_ref (−1)^k I_k(λa), no sine terms and every order, even ones included.
TEST(ContactPointAft, PureNormalMotionGivesTheBesselSeries) {
  const FourierBasis basis(7, 256);
  const auto point = make_point(true, Model::proportional, 1e-12);
  const auto ref = reference(point);
  const double z = 2.0;  // λ a
  Eigen::MatrixXd dg = Eigen::MatrixXd::Zero(basis.size(), 3);
  dg(basis.cosine_index(1), 2) = z / kLambda;
  ContactPointAftOptions o;
  o.jacobian = true;
  const auto r = evaluate_contact_point(point, ref, basis, dg, o);
  ASSERT_TRUE(r.converged);
  const double tol = 1e-12 * kPref * std::cyl_bessel_i(0.0, z);
  EXPECT_NEAR(r.traction(0, 2), -kPref * (std::cyl_bessel_i(0.0, z) - 1.0), tol);
  EXPECT_LT(r.traction(0, 2), -0.2 * kPref);  // a visible mean shift: I_0(2) − 1 = 1.28
  const Eigen::Index m = basis.size();
  for (int k = 1; k <= 7; ++k) {
    const int c = basis.cosine_index(k);
    const double sign = k % 2 ? -1.0 : 1.0;
    EXPECT_NEAR(r.traction(c, 2), -2.0 * kPref * sign * std::cyl_bessel_i(k, z), tol) << k;
    EXPECT_NEAR(r.traction(c + 1, 2), 0.0, tol) << k;
    // The Jacobian's column along a_1 is d/da of the series: I_k' = (I_{k−1} + I_{k+1})/2.
    const double d_ik = 0.5 * (std::cyl_bessel_i(k - 1, z) + std::cyl_bessel_i(k + 1, z));
    EXPECT_NEAR(r.jacobian(2 * m + c, 2 * m + basis.cosine_index(1)),
                -2.0 * kPref * kLambda * sign * d_ik, tol * kLambda)
        << k;
  }
  EXPECT_NEAR(r.jacobian(2 * m, 2 * m + basis.cosine_index(1)),
              -kPref * kLambda * std::cyl_bessel_i(1.0, z), tol * kLambda);
  // No tangential traction appears (t_ref,T = 0, no tangential motion).
  EXPECT_EQ(r.traction.leftCols<2>().cwiseAbs().maxCoeff(), 0.0);
}

// Tangential motion at constant pressure along a direction φ of the tangential plane: W_D of the
// steady loop of the point's μ p_ref and k_T (closed_forms.hpp), and the loop integral
// ∮ t_T·dg_T (jointhb's sign: t_T = +k g_T in stick, so the work is positive) from the samples
// (trapezoidal, O(1/N²)) and from the coefficients, π Σ_k k (a_k^t b_k^g − b_k^t a_k^g).
TEST(ContactPointAft, DissipationEqualsTheClosedFormsAtConstantPressure) {
  const FourierBasis basis(7, 1024);
  const double phi = 0.7;
  const jc::closed_form::MicroslipParameters params{kExponent, kMu * kPref, kStiffness};
  for (const bool gaul_mayer : {true, false}) {
    for (const double ratio : {0.2, 0.8, 3.0}) {  // of g_max: microslip, near onset, gross slip
      SCOPED_TRACE(std::string(gaul_mayer ? "gaul-mayer" : "jenkins") + " a/g_max " +
                   std::to_string(ratio));
      const auto point = make_point(gaul_mayer, Model::proportional);
      const auto ref = reference(point);
      const double a = ratio * kGmax;
      Eigen::MatrixXd dg = Eigen::MatrixXd::Zero(basis.size(), 3);
      dg(1, 0) = a * std::cos(phi);
      dg(1, 1) = a * std::sin(phi);
      const auto r = evaluate_contact_point(point, ref, basis, dg);
      ASSERT_TRUE(r.converged) << r.message;
      const double expected =
          gaul_mayer ? jc::closed_form::symmetric_loop(a, params).dissipation
                     : jc::closed_form::dissipation_jenkins(a, kMu * kPref, kStiffness);
      if (!gaul_mayer && ratio < 1.0 - kExponent) {  // Jenkins sticks below a = μp/k
        EXPECT_EQ(expected, 0.0);
        EXPECT_EQ(r.dissipation, 0.0);
        continue;
      }
      ASSERT_GT(expected, 0.0);
      EXPECT_NEAR(r.dissipation, expected, 1e-13 * expected);

      const Eigen::MatrixXd g = basis.to_time(dg);
      double trapezoid = 0.0;
      const Eigen::Index n = g.rows();
      for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Index next = (i + 1) % n;
        const Eigen::Vector2d t_mid =
            0.5 * (r.traction_samples.row(i) + r.traction_samples.row(next)).head<2>();
        trapezoid += t_mid.dot((g.row(next) - g.row(i)).head<2>());
      }
      EXPECT_NEAR(trapezoid, expected, 2e-5 * expected);
      double fourier = 0.0;
      for (int k = 1; k <= 7; ++k) {
        const int c = basis.cosine_index(k);
        for (int d = 0; d < 2; ++d) {
          fourier += std::numbers::pi * k *
                     (r.traction(c, d) * dg(c + 1, d) - r.traction(c + 1, d) * dg(c, d));
        }
      }
      EXPECT_NEAR(fourier, expected, 2e-5 * expected);
      std::printf(
          "  %-10s a/g_max %.1f: W_D/closed form - 1 = %9.2e, trapezoid %9.2e, Fourier %9.2e\n",
          gaul_mayer ? "gaul-mayer" : "jenkins", ratio, r.dissipation / expected - 1.0,
          trapezoid / expected - 1.0, fourier / expected - 1.0);
    }
  }
}

// A small interface: every regime at once, shared and per-point laws.
struct Interface {
  std::vector<jc::ContactPoint> laws;
  std::vector<ContactPointReference> refs;
  Eigen::MatrixXd dg;
  std::vector<double> areas;
};

Interface mixed_interface(const FourierBasis& basis) {
  Interface s;
  const double scales[][2] = {{0.3, 0.5}, {3.0, 0.5}, {1.0, 8.0}, {0.05, 0.3},
                              {0.5, 2.0}, {0.2, 0.1}, {2.0, 4.0}};
  const int np = 7;
  s.dg.resize(basis.size(), 3 * np);
  for (int p = 0; p < np; ++p) {
    const bool gm = p % 3 != 2;
    s.laws.push_back(make_point(gm, p % 2 ? Model::constant : Model::proportional));
    auto ref = reference(s.laws.back(), 0.1 * p * kMu * kPref, -0.05 * kMu * kPref);
    if (p == 4) ref.gap.z() += 20.0 / kLambda;  // open throughout
    s.refs.push_back(ref);
    s.dg.middleCols(3 * p, 3) = motion(basis, scales[p][0] * kGmax, scales[p][1] / kLambda);
    s.areas.push_back(1e-6 * (1.0 + 0.1 * p));
  }
  return s;
}

TEST(ContactPointAft, InterfaceDoesNotDependOnTheThreadCountAndEqualsThePoints) {
  const FourierBasis basis(3, 128);
  const Interface s = mixed_interface(basis);
  ContactPointAftOptions o;
  o.jacobian = true;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto one = evaluate_interface_aft(s.laws, s.refs, basis, s.dg, o, s.areas);
  omp_set_num_threads(2);
  const auto two = evaluate_interface_aft(s.laws, s.refs, basis, s.dg, o, s.areas);
  omp_set_num_threads(saved);
  ASSERT_TRUE(one.converged) << one.message;
  EXPECT_EQ(one.open_points, 1);
  EXPECT_GE(one.stuck_points, 1);
  EXPECT_TRUE(one.traction == two.traction);
  EXPECT_EQ(one.dissipation, two.dissipation);
  double total = 0.0;
  for (std::size_t p = 0; p < s.refs.size(); ++p) {
    SCOPED_TRACE(p);
    EXPECT_TRUE(one.points[p].jacobian == two.points[p].jacobian);
    const auto single = evaluate_contact_point(
        s.laws[p], s.refs[p], basis, s.dg.middleCols(3 * static_cast<Eigen::Index>(p), 3), o);
    EXPECT_TRUE(single.traction == one.points[p].traction);
    EXPECT_TRUE(single.jacobian == one.points[p].jacobian);
    EXPECT_TRUE(one.traction.middleCols(3 * static_cast<Eigen::Index>(p), 3) == single.traction);
    total += s.areas[p] * single.dissipation;
  }
  EXPECT_GT(one.dissipation, 0.0);
  EXPECT_EQ(one.dissipation, total);

  // One law shared by every point = that law given per point.
  const std::vector<jc::ContactPoint> shared{s.laws[0]};
  std::vector<jc::ContactPoint> repeated(s.refs.size(), s.laws[0]);
  const auto a = evaluate_interface_aft(shared, s.refs, basis, s.dg, o);
  const auto b = evaluate_interface_aft(repeated, s.refs, basis, s.dg, o);
  EXPECT_TRUE(a.traction == b.traction);
  EXPECT_EQ(a.dissipation, b.dissipation);
}

TEST(ContactPointAft, ReferencesFromTheInterfaceState) {
  Eigen::VectorXd gap(6), traction(6);
  gap << 1, 2, 3, 4, 5, 6;
  traction << -1, -2, -3, -4, -5, -6;
  const auto refs = contact_point_references(gap, traction);
  ASSERT_EQ(refs.size(), 2u);
  EXPECT_EQ(refs[1].gap, Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(refs[1].traction, Eigen::Vector3d(-4, -5, -6));
  EXPECT_THROW((void)contact_point_references(gap, traction.head(3)), std::invalid_argument);
}

// The message names the offending field.
template <class F>
void expect_invalid(F&& f, const std::string& field) {
  try {
    f();
    ADD_FAILURE() << "no exception, expected one naming " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(ContactPointAft, RejectsBadInput) {
  const auto point = make_point(true, Model::proportional);
  const auto ref = reference(point);
  const FourierBasis basis(3, 64);
  const FourierBasis odd(3, 64, true);
  const Eigen::MatrixXd dg = motion(basis, kGmax, 1.0 / kLambda);
  expect_invalid([&] { (void)evaluate_contact_point(point, ref, odd, dg.bottomRows(odd.size())); },
                 "basis");
  expect_invalid([&] { (void)evaluate_contact_point(point, ref, basis, dg.topRows(5)); },
                 "delta_g");
  expect_invalid([&] { (void)evaluate_contact_point(point, ref, basis, dg.leftCols(2)); },
                 "delta_g");
  Eigen::MatrixXd bad = dg;
  bad(1, 1) = std::nan("");
  expect_invalid([&] { (void)evaluate_contact_point(point, ref, basis, bad); }, "delta_g");
  ContactPointAftOptions o;
  o.periodic_tolerance = 0.0;
  expect_invalid([&] { (void)evaluate_contact_point(point, ref, basis, dg, o); },
                 "periodic_tolerance");
  o = {};
  o.max_iterations = 0;
  expect_invalid([&] { (void)evaluate_contact_point(point, ref, basis, dg, o); }, "max_iterations");
  ContactPointReference nan_ref = ref;
  nan_ref.gap.x() = std::nan("");
  expect_invalid([&] { (void)evaluate_contact_point(point, nan_ref, basis, dg); }, "reference");

  const std::vector<jc::ContactPoint> laws{point, point};
  const std::vector<ContactPointReference> refs{ref, ref, ref};
  Eigen::MatrixXd all(basis.size(), 9);
  for (int p = 0; p < 3; ++p) all.middleCols(3 * p, 3) = dg;
  expect_invalid([&] { (void)evaluate_interface_aft(laws, refs, basis, all); }, "points");
  expect_invalid([&] { (void)evaluate_interface_aft(laws, refs, basis, all.leftCols(6)); },
                 "delta_g");
  expect_invalid(
      [&] {
        (void)evaluate_interface_aft({laws.data(), 1}, refs, odd, all.bottomRows(odd.size()));
      },
      "basis");
  const std::vector<double> areas{1.0, -1.0, 1.0};
  expect_invalid(
      [&] {
        (void)evaluate_interface_aft({laws.data(), 1}, refs, basis, all, {}, areas);
      },
      "areas");
  expect_invalid(
      [&] {
        (void)evaluate_interface_aft({laws.data(), 1}, refs, basis, all, {}, {areas.data(), 2});
      },
      "areas");
}

}  // namespace
}  // namespace jointhb::hb
