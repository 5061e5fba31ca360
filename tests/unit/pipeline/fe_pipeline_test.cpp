// The finite-element pipeline object (pipeline/fe_pipeline.hpp) on the built-in default case (the
// bolted lap, 63 node pairs): stages computed once and kept while their keys hold, a parameter
// change recomputing exactly the stages it enters (counted), a memory store returning to earlier
// parameters bit-identically, the damping curve against closed forms and the modes stage, the
// callbacks, and the failure of a stage reported to the stages after it.
#include "jointhb/pipeline/fe_pipeline.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <variant>

#include "jointhb/io/case_file.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/input_error.hpp"
#include "jointhb/io/stage_cache.hpp"

namespace {

using namespace jointhb;
using pipeline::FePipeline;

const io::FeCase& lap_case() {
  static const io::FeCase c = [] {
    io::CaseFile f = io::parse_case_file(io::default_case_text(), "built-in default case");
    return std::get<io::FeCase>(std::move(f));
  }();
  return c;
}

// The damping curve from the linear limit into early microslip (short: a test).
pipeline::FeNonlinearModesSpec short_curve() {
  pipeline::FeNonlinearModesSpec nm = *lap_case().dynamics->nonlinear_modes;
  nm.log10_amplitude_end = -5.5;
  nm.frequency_drop = 0.0;
  return nm;
}

TEST(pipeline_FePipeline, StagesAreComputedOnceAndKeptWhileTheirKeysHold) {
  FePipeline p(lap_case(), lap_case());
  EXPECT_TRUE(p.needs_preload());
  ASSERT_TRUE(p.preload().status().ok());
  ASSERT_EQ(p.modes().termination, jointhb::Termination::converged);
  (void)p.modes();
  (void)p.interface_stage();
  (void)p.interface_stage();
  const pipeline::StageCounters& k = p.counters();
  EXPECT_EQ(k.assembled, 1);
  EXPECT_EQ(k.preload_solved, 1);
  EXPECT_EQ(k.modes_solved, 1);
  EXPECT_GE(k.modes_reused, 1);  // also the condensation's own request
  EXPECT_EQ(k.condensed, 1);
  EXPECT_GE(k.condensation_reused, 1);
  // The merge of coincident points (exact with nodal integration): 192 points, 63 node pairs.
  EXPECT_EQ(p.interface_stage().fine_points, 192);
  EXPECT_EQ(p.interface_stage().model.num_points(), 63);
}

// The place each stage's message names ("interface model: from cache (FILE)") is the file the
// disk cache wrote: the message once named interface-<key>.bin for interface_model-<key>.bin.
TEST(pipeline_FePipeline, StageMessagesNameTheFilesTheCacheWrites) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("jointhb-stage-names-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  auto cache = std::make_shared<io::StageCache>(dir, true);
  FePipeline p(lap_case(), lap_case(), cache);
  ASSERT_TRUE(p.preload().status().ok());
  ASSERT_EQ(p.modes().termination, jointhb::Termination::converged);
  const pipeline::InterfaceStage& s = p.interface_stage();
  for (const std::string& place : {p.preload_info().location, p.modes_info().location, s.info.location}) {
    EXPECT_TRUE(std::filesystem::is_regular_file(place)) << place;
  }
  EXPECT_EQ(std::filesystem::path(s.info.location).filename().string(), "interface_model-" + s.info.key + ".bin");
  std::filesystem::remove_all(dir);
}

TEST(pipeline_FePipeline, AParameterRecomputesExactlyTheStagesItEnters) {
  FePipeline p(lap_case(), lap_case());
  const double b0 = p.interface_stage().model.rayleigh_stiffness;
  // Damping: no stage; the kept model gets b = 2ζ/ω₁ (stiffness-proportional at the followed mode).
  p.set_parameter("damping.ratio", 0.01);
  const pipeline::InterfaceStage& s = p.interface_stage();
  EXPECT_EQ(p.counters().condensed, 1);
  EXPECT_EQ(p.counters().preload_solved, 1);
  const double f1 = pipeline::elastic_frequencies(p.modes())[0];
  EXPECT_NEAR(s.model.rayleigh_stiffness, 2.0 * 0.01 / (2.0 * std::numbers::pi * f1), 1e-18);
  EXPECT_NEAR(s.model.rayleigh_stiffness / b0, 2.0, 1e-12);
  // Friction for the dynamics only: the laws of the kept model, no stage.
  p.set_parameter("interfaces.lap.mu", 0.2, pipeline::ParameterScope::dynamics);
  EXPECT_EQ(p.interface_stage().model.groups[0].law.options().friction_coefficient, 0.2);
  EXPECT_EQ(p.counters().condensed, 1);
  EXPECT_EQ(p.counters().preload_solved, 1);
  // A bolt preload: preload, modes and condensation again.
  p.set_parameter("bolts.bolt-1.preload", 4000.0);
  (void)p.interface_stage();
  EXPECT_EQ(p.counters().preload_solved, 2);
  EXPECT_EQ(p.counters().modes_solved, 2);
  EXPECT_EQ(p.counters().condensed, 2);
  EXPECT_EQ(p.counters().assembled, 1);  // K_s holds k_b b bᵀ, not the preload
  // The clamping force follows the bolts (5 + 4 kN) to the preload's tolerance.
  EXPECT_NEAR(p.preload().interfaces[0].clamping_force, 9000.0, 1e-4);
  // The dynamics-only friction survives the recondensation.
  EXPECT_EQ(p.interface_stage().model.groups[0].law.options().friction_coefficient, 0.2);
}

TEST(pipeline_FePipeline, AMemoryStoreReturnsToEarlierParametersBitIdentically) {
  auto store = std::make_shared<pipeline::MemoryStageStore>();
  FePipeline p(lap_case(), lap_case(), store);
  const Eigen::VectorXd u0 = p.preload().displacement;
  const Eigen::VectorXd f0 = p.modes().frequencies_hz;
  p.set_parameter("interfaces.lap.mu", 0.25);
  EXPECT_NE(p.preload().displacement, u0);  // frictional preload: μ changes the state
  EXPECT_NE(p.modes().frequencies_hz, f0);
  EXPECT_EQ(p.counters().preload_solved, 2);
  EXPECT_EQ(p.counters().modes_solved, 2);
  p.set_parameter("interfaces.lap.mu", 0.3);
  EXPECT_EQ(p.preload().displacement, u0);
  EXPECT_EQ(p.modes().frequencies_hz, f0);
  EXPECT_EQ(p.counters().preload_solved, 2);
  EXPECT_EQ(p.counters().preload_read, 1);
  EXPECT_EQ(p.counters().modes_read, 1);
}

TEST(pipeline_FePipeline, TheDampingCurveStartsAtTheLinearModeAndItsDamping) {
  FePipeline p(lap_case(), lap_case());
  int seen = 0;
  const pipeline::BackboneCurve b = p.backbone(1, short_curve(), [&](const pipeline::BackbonePoint& pt) {
    ++seen;
    EXPECT_EQ(pt.mode, 1);
    EXPECT_TRUE(std::isfinite(pt.output_amplitude) && pt.output_amplitude >= 0.0);
    return true;
  });
  ASSERT_TRUE(b.status().ok()) << b.stop_message;
  ASSERT_GE(b.points.size(), 3u);
  EXPECT_EQ(seen, static_cast<int>(b.points.size()));
  EXPECT_EQ(b.status().termination, Termination::reached_end) << b.status().brief();
  EXPECT_EQ(b.status().message, b.stop_message);
  const pipeline::BackbonePoint& first = b.points.front();
  // Linear limit: the first elastic mode of K_t (the condensation keeps it to the cutoff's
  // truncation error) and ζ = the case's 0.5 % (b = 2ζ/ω₁ at that mode), up to that frequency
  // error and the microslip at the first amplitude (the Gaul–Mayer law has no sharp stick).
  const double f1 = pipeline::elastic_frequencies(p.modes())[0];
  EXPECT_NEAR(first.frequency_hz / f1, 1.0, 1e-4);
  EXPECT_NEAR(first.damping_ratio / 0.005, 1.0, 1e-3);
  // Microslip softens and damps: f falls and ζ rises along the curve.
  EXPECT_LT(b.points.back().frequency_hz, first.frequency_hz);
  EXPECT_GT(b.points.back().damping_ratio, first.damping_ratio);
  // The curve's points are the continuation's, in the same order.
  ASSERT_EQ(b.curve.points.size(), b.points.size());
  for (std::size_t i = 0; i < b.points.size(); ++i)
    EXPECT_EQ(b.points[i].amplitude, b.curve.points[i].state.amplitude);
  EXPECT_EQ(p.counters().curves, 1);
}

TEST(pipeline_FePipeline, ACallbackStopsTheCurveWithItsPointsKept) {
  FePipeline p(lap_case(), lap_case());
  int calls = 0;
  const pipeline::BackboneCurve b = p.backbone(1, short_curve(), [&](const pipeline::BackbonePoint&) { return ++calls < 3; });
  EXPECT_EQ(b.points.size(), 3u);
  EXPECT_TRUE(b.stopped_by_callback);
  EXPECT_FALSE(b.status().ok());
  EXPECT_EQ(b.stop_message, "stopped by the caller");
  EXPECT_EQ(b.status().termination, Termination::stopped_by_user);
  EXPECT_EQ(b.status().brief(), "stopped_by_user: stopped by the caller");
}

// The pipeline's own reasons to end a curve, which the continuation records alike as
// stopped_by_user (the accept callback returned false): the flags tell them apart.
TEST(pipeline_FePipeline, CurveStatusesTellTheFrequencyDropTheCallerAndANonFinitePointApart) {
  pipeline::BackboneCurve b;
  b.curve.reason = continuation::StopReason::stopped_by_user;
  b.stop_message = "a point is not finite";
  EXPECT_EQ(b.status().termination, Termination::failed);
  b.stopped_by_callback = true;
  EXPECT_EQ(b.status().termination, Termination::stopped_by_user);
  b.stopped_by_callback = false;
  b.reached_frequency_drop = true;
  EXPECT_EQ(b.status().termination, Termination::reached_end);
  EXPECT_TRUE(b.status().ok());  // the goal it was given
  b.reached_frequency_drop = false;
  b.curve.reason = continuation::StopReason::max_points;
  EXPECT_EQ(b.status().termination, Termination::no_convergence);
  EXPECT_FALSE(b.status().ok());

  pipeline::FrfCurve f;
  f.curve.reason = continuation::StopReason::reached_end;
  f.curve.message = "reached";
  EXPECT_EQ(f.status().termination, Termination::reached_end);
  EXPECT_TRUE(f.status().ok());
  f.curve.reason = continuation::StopReason::stopped_by_user;
  EXPECT_EQ(f.status().termination, Termination::failed);
  f.stopped_by_callback = true;
  EXPECT_EQ(f.status().termination, Termination::stopped_by_user);
  f.curve.reason = continuation::StopReason::min_step;
  f.stopped_by_callback = false;
  EXPECT_EQ(f.status().brief(), "failed: reached");
}

TEST(pipeline_FePipeline, AFailedPreloadIsReportedToTheStagesAfterIt) {
  pipeline::FeAnalysis a = lap_case();
  a.preload.max_iterations = 1;
  a.preload.max_line_search = 0;
  FePipeline p(lap_case(), a);
  EXPECT_NE(p.preload().termination, Termination::converged);
  EXPECT_FALSE(p.preload().status().ok());
  EXPECT_EQ(p.preload().status().message, p.preload().message);
  try {
    (void)p.modes();
    FAIL() << "modes() after a failed preload must throw";
  } catch (const pipeline::StageError& e) {
    EXPECT_NE(std::string(e.what()).find("preload"), std::string::npos) << e.what();
  }
}

TEST(pipeline_FePipeline, ParameterNamesMatchTheCaseAndUnknownNamesAreRejected) {
  FePipeline p(lap_case(), lap_case());
  EXPECT_EQ(p.parameter_names(),
            (std::vector<std::string>{"interfaces.lap.pressure", "interfaces.lap.decay", "interfaces.lap.mu",
                                      "interfaces.lap.n", "interfaces.lap.stiffness_ratio", "bolts.bolt-1.preload",
                                      "bolts.bolt-2.preload", "damping.ratio"}));
  for (const std::string& name : p.parameter_names()) EXPECT_TRUE(std::isfinite(p.parameter(name))) << name;
  EXPECT_EQ(p.parameter("interfaces.lap.n"), 0.3333333333333333);
  EXPECT_THROW((void)p.parameter("interfaces.lap.kt"), std::invalid_argument);
  EXPECT_THROW(p.set_parameter("interfaces.lap.n", 1.5), std::invalid_argument);  // n ∈ (0, 1)
  EXPECT_THROW(p.set_parameter("bolts.bolt-1.preload", -1.0), std::invalid_argument);
  EXPECT_THROW(p.set_parameter("nonsense", 1.0), std::invalid_argument);
}

// Names address parameters (bolts.<name>.preload, interfaces.<name>.mu): the reader refuses a
// name used twice, at its line and key.
TEST(pipeline_FePipeline, ParameterNamesAreUniqueInTheCase) {
  std::string text = io::default_case_text();
  const auto at = text.find("name: bolt-2");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 12, "name: bolt-1");
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  try {
    (void)io::parse_case_file(text, "case.yaml");
    FAIL() << "a bolt name used twice must be refused";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.key(), "model.bolts[1].name");
    EXPECT_EQ(e.line(), line);
    EXPECT_NE(e.constraint().find("used twice"), std::string::npos) << e.what();
  }
}

}  // namespace
