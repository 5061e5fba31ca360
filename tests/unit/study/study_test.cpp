// Parameter studies (study/study.hpp): what a sample reports against closed forms, the statistics
// against hand values, and the runner — the same table for any number of workers, restart from
// the sample files, failed and stopped samples.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <thread>
#include <variant>

#include <unistd.h>

#include "jointhb/contact/closed_forms.hpp"
#include "jointhb/io/case_file.hpp"
#include "jointhb/study/sample_models.hpp"
#include "jointhb/study/study.hpp"

namespace jointhb::study {
namespace {

namespace fs = std::filesystem;

// A unit mass on a spring k = 1e4 N/m with a Jenkins element (k_t, slip force μ F_N): its damping
// curve at H = 1 (the study's outputs at four amplitudes, two of them slipping), for a design over
// k_t and F_N.
const char* kJenkinsCase = R"(
model: {type: discrete, mass: 1.0, stiffness: 1.0e4, damping: {matrix: [[0.0]]}}
contacts:
  - {law: jenkins, dofs: [0], kt0: 1.0e4, mu: 0.2, normal_force: 20.0}
analysis:
  nonlinear_modes: {mode: 1, log10_amplitude: [-5, -2], harmonics: 1, time_samples: 512}
study:
  sampling: latin_hypercube
  samples: 12
  seed: 5
  parameters:
    - {name: "contacts[0].kt0", lower: 3.0e3, upper: 3.0e4, log_scale: true}
    - {name: "contacts[0].normal_force", lower: 5, upper: 50}
  amplitudes: [1.0e-5, 1.0e-4, 1.0e-3, 3.0e-3]
)";

io::DiscreteCase jenkins_case(const std::string& text = kJenkinsCase) {
  return std::get<io::DiscreteCase>(io::parse_case_file(text, "study.yaml"));
}

std::vector<std::string> names(const StudySpec& spec) {
  std::vector<std::string> out;
  for (const auto& p : spec.sampling.parameters) out.push_back(p.name);
  return out;
}

StudyResult run(const io::DiscreteCase& c, RunOptions options = {}) {
  return run_study(*c.study, discrete_sample_models(c, names(*c.study), c.study->outputs), options);
}

// One harmonic of a Jenkins element (stiffness k_t, slip displacement x_s) at amplitude X > x_s:
// the equivalent stiffness k_t (β − sin 2β / 2)/π with cos β = 1 − 2 x_s / X (T. K. Caughey,
// J. Appl. Mech. 27 (1960) 649–652, the bilinear hysteretic oscillator), and the dissipation per
// cycle 4 μF_N (X − x_s). For the EPMC of m = 1: ω² = k + k_eq, ζ = W_D / (2π ω² X²).
struct OneHarmonic {
  double frequency_hz, damping_ratio;
};
OneHarmonic jenkins_epmc(double k, double kt, double slip_force, double x) {
  const double xs = slip_force / kt;
  double keq = kt, wd = 0.0;
  if (x > xs) {
    const double beta = std::acos(1.0 - 2.0 * xs / x);
    keq = kt * (beta - 0.5 * std::sin(2.0 * beta)) / std::numbers::pi;
    wd = contact::closed_form::dissipation_jenkins(x, slip_force, kt);
  }
  const double w2 = k + keq;
  return {std::sqrt(w2) / (2.0 * std::numbers::pi), wd / (2.0 * std::numbers::pi * w2 * x * x)};
}

TEST(Study, JenkinsSamplesMatchTheOneHarmonicClosedForm) {
  const io::DiscreteCase c = jenkins_case();
  const StudyResult r = run(c);
  ASSERT_EQ(r.samples.size(), 12u);
  EXPECT_TRUE(r.status().ok()) << r.status().message;
  ASSERT_EQ(r.keys.size(), 8u);  // f and ζ at four amplitudes
  int slipping = 0;
  for (const SampleResult& s : r.samples) {
    ASSERT_TRUE(s.status.ok()) << s.status.message;
    const double kt = s.values[0], slip = 0.2 * s.values[1];
    for (std::size_t k = 0; k < r.keys.size(); k += 2) {
      const double q = r.keys[k].abscissa;
      const OneHarmonic exact = jenkins_epmc(1.0e4, kt, slip, q);
      ASSERT_TRUE(s.outputs[k] && s.outputs[k + 1]);
      EXPECT_NEAR(*s.outputs[k] / exact.frequency_hz, 1.0, 2e-4) << "sample " << s.sample << " q " << q;
      EXPECT_NEAR(*s.outputs[k + 1], exact.damping_ratio, 2e-4 * std::max(exact.damping_ratio, 1e-3))
          << "sample " << s.sample << " q " << q;
      slipping += exact.damping_ratio > 0.0 ? 1 : 0;
    }
  }
  EXPECT_GT(slipping, 12);  // the design reaches the slipping regime in most samples
}

TEST(Study, TheTableIsTheSameForAnyNumberOfWorkers) {
  const io::DiscreteCase c = jenkins_case();
  RunOptions one;
  RunOptions three;
  three.jobs = 3;
  const StudyResult a = run(c, one), b = run(c, three);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  EXPECT_EQ(b.jobs, 3);
  for (std::size_t i = 0; i < a.samples.size(); ++i) {
    EXPECT_EQ(a.samples[i].outputs, b.samples[i].outputs) << "sample " << i;  // bitwise: operator== on doubles
    ASSERT_EQ(a.samples[i].curves.size(), b.samples[i].curves.size());
    EXPECT_EQ(a.samples[i].curves[0].frequency_hz, b.samples[i].curves[0].frequency_hz) << "sample " << i;
  }
  for (std::size_t k = 0; k < a.statistics.size(); ++k) {
    EXPECT_EQ(a.statistics[k].mean, b.statistics[k].mean);
    EXPECT_EQ(a.statistics[k].quantiles, b.statistics[k].quantiles);
  }
}

TEST(Study, ARestartReusesTheSampleFilesOfTheSameStudyOnly) {
  const io::DiscreteCase c = jenkins_case();
  const fs::path dir = fs::temp_directory_path() / fs::path("jointhb-study-test-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  RunOptions o;
  o.sample_directory = dir;
  o.identity = "case A";
  const StudyResult first = run(c, o);
  EXPECT_EQ(first.computed, 12u);
  o.resume = true;
  fs::remove(dir / "sample_000004.json");
  {
    std::ofstream(dir / "sample_000007.json") << "{ not json";
  }
  std::size_t reported = 0;
  o.on_sample = [&](const SampleResult&, std::size_t, std::size_t) { return ++reported > 0; };
  const StudyResult second = run(c, o);
  EXPECT_EQ(second.reused, 10u);
  EXPECT_EQ(second.computed, 2u);
  EXPECT_EQ(reported, 12u);
  ASSERT_EQ(second.warnings.size(), 1u);
  EXPECT_NE(second.warnings[0].find("sample_000007.json"), std::string::npos) << second.warnings[0];
  for (std::size_t i = 0; i < 12; ++i) EXPECT_EQ(first.samples[i].outputs, second.samples[i].outputs) << i;
  o.identity = "case B";  // another case: nothing reused
  const StudyResult third = run(c, o);
  EXPECT_EQ(third.reused, 0u);
  EXPECT_EQ(third.computed, 12u);
  EXPECT_EQ(third.warnings.size(), 12u);
  fs::remove_all(dir);
}

TEST(Study, AFailedSampleKeepsItsReasonAndStopsNoOther) {
  io::DiscreteCase c = jenkins_case();
  c.study->sampling.kind = SamplingKind::list;
  c.study->sampling.parameters[0].values = {1.0e4, -1.0, 2.0e4};  // k_t < 0: the model rejects it
  c.study->sampling.parameters[1].values = {20.0, 20.0, 20.0};
  const StudyResult r = run(c);
  ASSERT_EQ(r.samples.size(), 3u);
  EXPECT_TRUE(r.samples[0].status.ok());
  EXPECT_FALSE(r.samples[1].status.ok());
  EXPECT_NE(r.samples[1].status.message.find("kt0"), std::string::npos) << r.samples[1].status.message;
  EXPECT_TRUE(r.samples[2].status.ok());
  EXPECT_EQ(r.failed, 1u);
  EXPECT_EQ(r.status().termination, Termination::no_convergence);
  const auto& f = r.statistics[0];  // the statistics count the two that reached the output
  EXPECT_EQ(f.count, 2u);
}

TEST(Study, StoppingLeavesTheRestNotRun) {
  const io::DiscreteCase c = jenkins_case();
  RunOptions o;
  o.on_sample = [](const SampleResult&, std::size_t done, std::size_t) { return done < 3; };
  const StudyResult r = run(c, o);
  EXPECT_GE(r.computed, 3u);
  EXPECT_GT(r.not_run, 0u);
  EXPECT_EQ(r.status().termination, Termination::stopped_by_user);
}

// FRF outputs: a unit mass on k = 1e4 N/m with a Jenkins element that never slips (slip force
// 1e6 N) is linear, |x̂₁|(Ω) = F / √((k + k_t − Ω²)² + (cΩ)²): the amplitudes at the study's
// frequencies against it, and the peak (the largest accepted point) within the point spacing.
TEST(Study, FrfOutputsMatchTheLinearReceptance) {
  const io::DiscreteCase c = jenkins_case(R"(
model: {type: discrete, mass: 1.0, stiffness: 1.0e4, damping: {matrix: [[2.0]]}}
contacts:
  - {law: jenkins, dofs: [0], kt0: 1.0e4, mu: 1.0, normal_force: 1.0e6}
excitation:
  - {dof: 0, amplitude: [1.0, 3.0]}
analysis:
  frf: {omega: [100.0, 200.0], harmonics: 1, time_samples: 64, output_dof: 0}
study:
  sampling: list
  parameters:
    - {name: "contacts[0].kt0", values: [1.0e4, 2.0e4]}
  frequencies_hz: [18.0, 21.0, 25.0]
)");
  const StudyResult r = run(c);
  ASSERT_EQ(r.keys.size(), 10u);  // per level: three frequencies, the peak, its frequency
  EXPECT_TRUE(r.status().ok()) << r.status().message;
  for (const SampleResult& s : r.samples) {
    const double k = 1.0e4 + s.values[0];
    for (std::size_t i = 0; i < r.keys.size(); ++i) {
      const OutputKey& key = r.keys[i];
      const double force = key.index == 0 ? 1.0 : 3.0;
      ASSERT_TRUE(s.outputs[i].has_value()) << key.label();
      if (key.quantity == "amplitude") {
        const double w = 2.0 * std::numbers::pi * key.abscissa;
        const double exact = force / std::hypot(k - w * w, 2.0 * w);
        EXPECT_NEAR(*s.outputs[i] / exact, 1.0, 1e-8) << key.label() << " sample " << s.sample;
      } else if (key.quantity == "peak_amplitude") {
        const double peak = force / (2.0 * std::sqrt(k - 1.0));  // F / (c ω_d), c = 2, ω_d² = k − c²/4
        EXPECT_NEAR(*s.outputs[i] / peak, 1.0, 1e-3) << key.label() << " sample " << s.sample;
      } else {
        EXPECT_NEAR(*s.outputs[i] / (std::sqrt(k - 2.0) / (2.0 * std::numbers::pi)), 1.0, 1e-3) << key.label();
      }
    }
  }
}

// Dynamic scheduling: a slow sample holds up only the worker evaluating it; the other worker takes
// every other sample meanwhile, so the slow one is reported last.
TEST(Study, ASlowSampleStallsNoOtherWorker) {
  StudySpec spec;
  spec.sampling.kind = SamplingKind::list;
  StudyParameter p;
  p.name = "x";
  p.values = {0, 1, 2, 3, 4, 5, 6, 7};
  spec.sampling.parameters = {p};
  spec.outputs.modes = {1};
  spec.outputs.amplitudes = {1e-4};
  const SampleModelFactory factory = [] {
    return SampleModel([](const std::vector<double>& values) {
      if (values[0] == 0.0) std::this_thread::sleep_for(std::chrono::milliseconds(1500));
      fit::ModelPrediction prediction;
      fit::PredictedCurve c;
      c.abscissa = {1e-5, 1e-3};
      c.frequency_hz = {10.0 + values[0], 10.0 + values[0]};
      c.damping_ratio = {0.01, 0.01};
      prediction.curves.push_back(c);
      return prediction;
    });
  };
  RunOptions o;
  o.jobs = 2;
  std::vector<std::size_t> order;
  o.on_sample = [&](const SampleResult& s, std::size_t, std::size_t) {
    order.push_back(s.sample);
    return true;
  };
  const StudyResult r = run_study(spec, factory, o);
  ASSERT_EQ(order.size(), 8u);
  EXPECT_EQ(order.back(), 0u);  // the seven others finished while sample 0 was running
  EXPECT_TRUE(r.status().ok()) << r.status().message;
  for (std::size_t i = 0; i < 8; ++i) EXPECT_EQ(*r.samples[i].outputs[0], 10.0 + static_cast<double>(i));
}

// An interrupt (RunOptions::interrupt, what a signal sets) stops handing out samples; the running
// ones finish and are kept.
TEST(Study, AnInterruptKeepsWhatRanAndLeavesTheRest) {
  const io::DiscreteCase c = jenkins_case();
  std::atomic<bool> interrupt{false};
  RunOptions o;
  o.jobs = 2;
  o.interrupt = &interrupt;
  o.on_sample = [&](const SampleResult&, std::size_t done, std::size_t) {
    if (done == 2) interrupt = true;
    return true;
  };
  const StudyResult r = run(c, o);
  EXPECT_GE(r.computed, 2u);
  EXPECT_LE(r.computed, 4u);  // the two running when it came may finish
  EXPECT_EQ(r.computed + r.not_run, 12u);
  EXPECT_EQ(r.status().termination, Termination::stopped_by_user);
  for (std::size_t i = 0; i < 12; ++i) {
    if (r.done[i]) EXPECT_TRUE(r.samples[i].status.ok()) << i;
  }
}

// A sample whose curve ends before an output: that output is missing, the others are read off
// the curve, and the sample fails naming the output.
TEST(Study, OutputsBeyondTheCurveAreMissingAndNamed) {
  StudyOutputs o;
  o.modes = {1};
  o.amplitudes = {1e-4, 1e-2};
  const SampleModel model = [](const std::vector<double>&) {
    fit::ModelPrediction p;
    fit::PredictedCurve c;
    c.abscissa = {1e-5, 1e-4, 1e-3};
    c.frequency_hz = {5.0, 4.0, 3.0};  // linear in log10 q: interpolated exactly
    c.damping_ratio = {0.01, 0.02, 0.03};
    c.message = "the continuation stopped";
    p.curves.push_back(c);
    return p;
  };
  const SampleResult s = evaluate_sample(model, o, 0, {1.0});
  ASSERT_EQ(s.outputs.size(), 4u);
  EXPECT_DOUBLE_EQ(*s.outputs[0], 4.0);
  EXPECT_DOUBLE_EQ(*s.outputs[1], 0.02);
  EXPECT_FALSE(s.outputs[2].has_value());
  EXPECT_FALSE(s.outputs[3].has_value());
  EXPECT_FALSE(s.status.ok());
  EXPECT_NE(s.status.message.find("frequency_hz at 0.01 not reached"), std::string::npos) << s.status.message;
  EXPECT_NE(s.status.message.find("the continuation stopped"), std::string::npos) << s.status.message;
}

TEST(Study, QuantilesAreHyndmanFanDefinitionSeven) {
  // numpy.quantile([1, 2, 3, 4], [0, 0.25, 0.5, 0.9, 1]) = [1, 1.75, 2.5, 3.7, 4]
  const std::vector<double> x = {1, 2, 3, 4};
  EXPECT_DOUBLE_EQ(quantile(x, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(quantile(x, 0.25), 1.75);
  EXPECT_DOUBLE_EQ(quantile(x, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(quantile(x, 0.9), 3.7);
  EXPECT_DOUBLE_EQ(quantile(x, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(quantile({7.0}, 0.3), 7.0);
}

TEST(Study, ASampleRecordReadsBackBitIdentical) {
  SampleResult s;
  s.sample = 17;
  s.values = {0.1, 1.0 / 3.0, 6.02214076e23};
  s.status = {Termination::failed, "a \"quoted\" reason"};
  s.outputs = {std::nextafter(1.0, 2.0), std::nullopt, -4.9e-324};
  fit::PredictedCurve c;
  c.abscissa = {1e-300, std::nan("")};
  s.curves.push_back(c);
  std::string identity;
  const SampleResult back = sample_from_json(sample_to_json(s, "id"), identity);
  EXPECT_EQ(identity, "id");
  EXPECT_EQ(back.sample, 17u);
  EXPECT_EQ(back.values, s.values);
  EXPECT_EQ(back.outputs, s.outputs);
  EXPECT_EQ(back.status.message, s.status.message);
  EXPECT_EQ(back.status.termination, Termination::failed);
  EXPECT_EQ(back.curves[0].abscissa[0], 1e-300);
  EXPECT_TRUE(std::isnan(back.curves[0].abscissa[1]));
  EXPECT_THROW((void)sample_from_json("[]", identity), std::runtime_error);
}

}  // namespace
}  // namespace jointhb::study
