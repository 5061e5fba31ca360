// Identification of discrete models from synthetic data: curves generated with known parameters,
// noise added, fitted from starts far away. Small H and few points keep each test to seconds.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "jointhb/continuation/frf.hpp"
#include "jointhb/pipeline/discrete_fit_model.hpp"
#include "jointhb/fit/fitter.hpp"
#include "jointhb/io/discrete_case.hpp"

namespace jointhb::fit {
using namespace jointhb::pipeline;  // the discrete adapter (pipeline/discrete_fit_model.hpp)
namespace {

// Case 03 (one mass, Gaul–Mayer joint to ground) at H = 3.
const char* const one_dof = R"(model:
  type: discrete
  mass: 1.0
  stiffness: 1.0e4
  damping: {modal: [0.002]}
contacts:
  - {law: gaul-mayer, dofs: [0], kt0: 3.0e4, mu: 0.2, normal_force: 5.0, n: 0.3333333333333333}
analysis:
  nonlinear_modes: {mode: 1, log10_amplitude: [-7, -3.5], harmonics: 3}
)";

// Case 04 (two masses, two Gaul–Mayer joints) at H = 3.
const char* const two_dof = R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: [[3.0e4, -1.0e4], [-1.0e4, 1.0e4]]
  damping: {modal: [0.002, 0.002]}
contacts:
  - {law: gaul-mayer, dofs: [0], kt0: 2.0e4, mu: 0.4, normal_force: 5.0, n: 0.3333333333333333}
  - {law: gaul-mayer, dofs: [0, 1], kt0: 1.0e4, mu: 0.1, normal_force: 5.0, n: 0.3333333333333333}
analysis:
  nonlinear_modes: {mode: [1, 2], log10_amplitude: [-7, -3], harmonics: 3, continuation: {max_points: 300}}
)";

// Gaussian pseudo-noise, reproducible on every platform (Box–Muller on mt19937_64).
struct Noise {
  std::mt19937_64 rng{12345};
  double uniform() { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; }
  double normal() {
    return std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * M_PI * uniform());
  }
};

// A backbone target of `mode` at amplitudes 10^lo .. 10^hi (count points), frequency and damping
// with relative noise (σ_f, σ_ζ), measured = model(truth) (1 + σ n); residual scale σ |measured|.
Target backbone_target(const io::DiscreteCase& truth, int mode, double lo, double hi, int count,
                       double sigma_f, double sigma_z, Noise& noise) {
  Target t;
  t.name = "synthetic mode " + std::to_string(mode);
  t.kind = TargetKind::backbone;
  t.mode = mode;
  for (int i = 0; i < count; ++i) {
    const double q = std::pow(10.0, lo + (hi - lo) * i / (count - 1));
    t.points.push_back({q, Quantity::frequency_hz, 0.0, 1.0, 0.0, 0});
    t.points.push_back({q, Quantity::damping_ratio, 0.0, 1.0, 0.0, 0});
  }
  const ModelPrediction exact = predict(truth, {t});
  EXPECT_TRUE(exact.curves[0].ok) << exact.curves[0].message;
  for (std::size_t i = 0; i < t.points.size(); ++i) {
    auto& p = t.points[i];
    const double s = p.quantity == Quantity::frequency_hz ? sigma_f : sigma_z;
    const double value = exact.curves[0].at_points[i];
    p.measured = value * (1.0 + s * noise.normal());
    p.sigma = s * std::abs(p.measured);
  }
  return t;
}

TEST(DiscreteFit, ParameterNamesAndSettingThem) {
  io::DiscreteCase c = io::parse_discrete_case(two_dof, "two.yaml");
  const auto names = discrete_parameter_names(c);
  ASSERT_EQ(names.size(), 10u);
  EXPECT_EQ(names[0], "contacts[0].kt0");
  EXPECT_EQ(names[3], "contacts[0].n");
  EXPECT_EQ(names[8], "damping.modal[0]");
  set_model_parameters(c, {"contacts[1].normal_force", "damping.modal[1]"}, {7.0, 0.01});
  EXPECT_EQ(c.system.contacts[1].normal_force, 7.0);
  const io::DiscreteCase ref =
      io::parse_discrete_case(std::string(two_dof).replace(
                                  std::string(two_dof).find("[0.002, 0.002]"), 14, "[0.002, 0.01]"),
                              "ref.yaml");
  EXPECT_LT((Eigen::MatrixXd(c.system.damping) - Eigen::MatrixXd(ref.system.damping)).norm(),
            1e-12 * Eigen::MatrixXd(ref.system.damping).norm());
  try {
    set_model_parameters(c, {"contacts[2].mu"}, {0.1});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown parameter 'contacts[2].mu'; this case has: "
                                         "contacts[0].kt0"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(set_model_parameters(c, {"contacts[0].mu"}, {-1.0}), std::invalid_argument);
  EXPECT_THROW(set_model_parameters(c, {"contacts[0].n"}, {1.5}), std::invalid_argument);
}

TEST(DiscreteFit, OneDofRecoversSlipLimitAndStiffnessFromFarStarts) {
  const io::DiscreteCase truth = io::parse_discrete_case(one_dof, "one.yaml");
  Noise noise;
  const Target t = backbone_target(truth, 1, -6.0, -3.8, 8, 0.002, 0.02, noise);
  const std::vector<std::string> names = {"contacts[0].normal_force", "contacts[0].kt0"};
  io::DiscreteCase start = truth;
  const std::vector<FitParameter> p = {{names[0], 0.5, 50.0, 40.0, true},
                                       {names[1], 3e3, 3e5, 5e3, true}};
  FitOptions o;
  o.xtol = 1e-5;
  const FitResult r = fit(discrete_model(start, names, {t}), p, o);
  ASSERT_TRUE(r.ok && r.has_jacobian) << r.jacobian_message;
  EXPECT_TRUE(r.unresolved.empty());
  EXPECT_LT(std::abs(r.best[0] - 5.0), 3 * r.standard_errors[0])
      << r.best[0] << " +- " << r.standard_errors[0];
  EXPECT_LT(std::abs(r.best[1] - 3e4), 3 * r.standard_errors[1])
      << r.best[1] << " +- " << r.standard_errors[1];
  EXPECT_LT(r.standard_errors[0], 0.05 * 5.0);  // informative data: a few % at most
  EXPECT_LT(r.standard_errors[1], 0.05 * 3e4);
  // With σ-scaled residuals s² estimates 1.
  EXPECT_GT(r.s2, 0.2);
  EXPECT_LT(r.s2, 3.0);
}

TEST(DiscreteFit, TwoDofRecoversBothJointsFromTwoModes) {
  const io::DiscreteCase truth = io::parse_discrete_case(two_dof, "two.yaml");
  Noise noise;
  const std::vector<Target> targets = {
      backbone_target(truth, 1, -5.5, -3.5, 6, 0.002, 0.02, noise),
      backbone_target(truth, 2, -5.5, -3.5, 6, 0.002, 0.02, noise)};
  const std::vector<std::string> names = {"contacts[0].kt0", "contacts[1].normal_force"};
  const std::vector<FitParameter> p = {{names[0], 2e3, 2e5, 1e5, true},
                                       {names[1], 0.5, 50.0, 1.0, true}};
  FitOptions o;
  o.xtol = 1e-4;
  // Two starts: from the given one BOBYQA ends in a local minimum (S = 2.68e5 after 46
  // evaluations, against 40.7 at the truth's basin, found by the Latin-hypercube start). A single
  // start passed until stop 47 only because one curve on its way failed and its penalty steered
  // the search off that basin (docs/continuation.md, "Natural-parameter fallback at corners").
  o.starts = 2;
  const FitResult r = fit(discrete_model(truth, names, targets), p, o);
  ASSERT_TRUE(r.ok && r.has_jacobian) << r.jacobian_message;
  EXPECT_TRUE(r.unresolved.empty());
  EXPECT_LT(std::abs(r.best[0] - 2e4), 3 * r.standard_errors[0])
      << r.best[0] << " +- " << r.standard_errors[0];
  EXPECT_LT(std::abs(r.best[1] - 5.0), 3 * r.standard_errors[1])
      << r.best[1] << " +- " << r.standard_errors[1];
}

TEST(DiscreteFit, JenkinsMuAndNormalForceOnlyAsProductAreFlagged) {
  std::string text = one_dof;
  text.replace(text.find("gaul-mayer"), 10, "jenkins");
  text.replace(text.find(", n: 0.3333333333333333"), 23, "");
  const io::DiscreteCase truth = io::parse_discrete_case(text, "jenkins.yaml");
  Noise noise;
  const Target t = backbone_target(truth, 1, -6.0, -3.8, 6, 0.002, 0.02, noise);
  const std::vector<std::string> names = {"contacts[0].mu", "contacts[0].normal_force"};
  // Start with slip inside the measured range (μ F_N = 1.8 N): a Jenkins joint that sticks
  // throughout the data gives no gradient at all.
  const std::vector<FitParameter> p = {{names[0], 0.02, 2.0, 0.3, true},
                                       {names[1], 0.5, 50.0, 6.0, true}};
  FitOptions o;
  o.xtol = 1e-5;
  const FitResult r = fit(discrete_model(truth, names, {t}), p, o);
  ASSERT_TRUE(r.ok && r.has_jacobian);
  EXPECT_NEAR(r.best[0] * r.best[1], 1.0, 0.05);  // μ F_N is determined
  ASSERT_EQ(r.unresolved.size(), 1u);
  EXPECT_NEAR(std::abs(r.unresolved[0].components[0]), std::sqrt(0.5), 1e-2);
  EXPECT_NEAR(r.unresolved[0].components[0], -r.unresolved[0].components[1], 2e-2);
  EXPECT_TRUE(std::isinf(r.standard_errors[0]));
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("not separately identifiable"), std::string::npos);
}

// Case 04's system with an FRF around mode 1 (force 0.05 N on DOF 1), H = 3.
const char* const two_dof_frf = R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: [[3.0e4, -1.0e4], [-1.0e4, 1.0e4]]
  damping: {modal: [0.002, 0.002]}
contacts:
  - {law: gaul-mayer, dofs: [0], kt0: 2.0e4, mu: 0.4, normal_force: 5.0, n: 0.3333333333333333}
  - {law: gaul-mayer, dofs: [0, 1], kt0: 1.0e4, mu: 0.1, normal_force: 5.0, n: 0.3333333333333333}
excitation:
  - {dof: 1, amplitude: 0.05}
analysis:
  frf: {frequency_hz: [13.0, 20.0], harmonics: 3, output_dof: 1}
)";

TEST(DiscreteFit, FrfAndModalPredictionsAreTheCurvesOwnValues) {
  const io::DiscreteCase c = io::parse_discrete_case(two_dof_frf, "frf.yaml");
  const continuation::FrfCurve curve = continuation::trace_frf(c.system, c.levels[0], *c.frf);
  ASSERT_TRUE(curve.completed());
  Target frf;
  frf.name = "frf";
  frf.kind = TargetKind::frf;
  std::vector<double> expected;
  for (std::size_t k = 5; k < curve.points.size(); k += 17) {  // at accepted points exactly
    frf.points.push_back(
        {curve.points[k].omega / (2 * M_PI), Quantity::amplitude, 1.0, 1.0, 0.0, 0});
    expected.push_back(curve.points[k].amplitude_h1);
  }
  Target modal;
  modal.name = "modal";
  modal.kind = TargetKind::modal;
  modal.points = {{2, Quantity::frequency_hz, 1.0, 1.0, 0.0, 0},
                  {1, Quantity::damping_ratio, 1.0, 1.0, 0.0, 0}};
  const ModelPrediction p = predict(c, {frf, modal});
  ASSERT_TRUE(p.curves[0].ok) << p.curves[0].message;
  ASSERT_EQ(p.curves[0].at_points.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(p.curves[0].at_points[i], expected[i], 1e-7 * expected[i]);
  }
  const hb::LinearModes modes = hb::linear_modes(c.system, true);
  const ResidualEvaluation r = residuals({frf, modal}, p);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_NEAR(r.predicted[expected.size()], modes.omega[1] / (2 * M_PI), 1e-12 * modes.omega[1]);
  const Eigen::VectorXd phi = modes.shapes.col(0);
  const double zeta = phi.dot(Eigen::MatrixXd(c.system.damping) * phi) / (2 * modes.omega[0]);
  EXPECT_NEAR(r.predicted[expected.size() + 1], zeta, 1e-12);
  EXPECT_GT(zeta, 0.0);
}

TEST(DiscreteFit, FrfRecoversTheSlipLimitOfTheUpperJoint) {
  const io::DiscreteCase truth = io::parse_discrete_case(two_dof_frf, "frf.yaml");
  Target t;
  t.name = "frf";
  t.kind = TargetKind::frf;
  for (int i = 0; i < 10; ++i)
    t.points.push_back({14.0 + 0.5 * i, Quantity::amplitude, 0.0, 1.0, 0.0, 0});
  const ModelPrediction exact = predict(truth, {t});
  ASSERT_TRUE(exact.curves[0].ok) << exact.curves[0].message;
  Noise noise;
  for (std::size_t i = 0; i < t.points.size(); ++i) {
    t.points[i].measured = exact.curves[0].at_points[i] * (1.0 + 0.01 * noise.normal());
    t.points[i].sigma = 0.01 * t.points[i].measured;
  }
  const std::vector<std::string> names = {"contacts[1].normal_force"};
  FitOptions o;
  o.xtol = 1e-5;
  const FitResult r =
      fit(discrete_model(truth, names, {t}), {{names[0], 0.5, 50.0, 30.0, true}}, o);
  ASSERT_TRUE(r.ok && r.has_jacobian);
  EXPECT_LT(std::abs(r.best[0] - 5.0), 3 * r.standard_errors[0])
      << r.best[0] << " +- " << r.standard_errors[0];
  EXPECT_LT(r.standard_errors[0], 0.1);
}

TEST(DiscreteFit, InvalidParameterValuesArePenalisedNotFatal) {
  // Linear bounds that include kt0 <= 0, and a start at kt0 = 0: the model rejects those values
  // (DiscreteSystem::validate), the search is penalised there and still finds the truth.
  const io::DiscreteCase truth = io::parse_discrete_case(one_dof, "one.yaml");
  Noise noise;
  const Target t = backbone_target(truth, 1, -6.0, -3.8, 6, 0.002, 0.02, noise);
  const std::vector<std::string> names = {"contacts[0].kt0"};
  const FitResult r =
      fit(discrete_model(truth, names, {t}), {{names[0], -1e4, 1e5, 0.0, false}}, FitOptions{});
  ASSERT_TRUE(r.ok && r.has_jacobian);
  EXPECT_GE(r.failed_evaluations, 1);
  EXPECT_LT(std::abs(r.best[0] - 3e4), 3 * r.standard_errors[0])
      << r.best[0] << " +- " << r.standard_errors[0];
}

TEST(DiscreteFit, MeasuredAmplitudeBeyondTheCurveIsAFailedEvaluation) {
  const io::DiscreteCase c = io::parse_discrete_case(one_dof, "one.yaml");
  Target t;
  t.name = "far";
  t.points.push_back({1e-2, Quantity::frequency_hz, 20.0, 1.0, 0.0, 3});  // beyond 10^-3.5
  const Evaluation e = discrete_model(c, {"contacts[0].kt0"}, {t})({3e4});
  EXPECT_FALSE(e.ok);
  EXPECT_NE(e.message.find("outside the predicted curve"), std::string::npos) << e.message;
}

}  // namespace
}  // namespace jointhb::fit
