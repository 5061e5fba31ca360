#include "jointhb/io/loop_sweep_case.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "jointhb/io/input_error.hpp"
#include "temp_file.hpp"

namespace jointhb::io {
namespace {

using testing::TempFile;

const char* const valid_case = R"(# every key of the loop sweep
analysis:
  loop_sweep:
    law: gaul-mayer
    n: 0.25
    mu: 0.2
    normal_force: 50.0
    kt0: 2.0e6
    amplitude_over_gmax: [1.0e-4, 5.0]
    points: 41
    time_samples: 128
)";

// Reads `text` from a temp file and returns the InputError it must raise.
InputError error_of(const TempFile& file) {
  try {
    (void)read_loop_sweep_case(file.path());
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << file.contents();
  return InputError("", 0, 0, "", "");
}

std::string sweep(const std::string& entries) { return "analysis:\n  loop_sweep:\n" + entries; }

TEST(io_LoopSweepCase, ValidFileSetsEveryField) {
  const TempFile file(".yaml", valid_case);
  const LoopSweepCase c = read_loop_sweep_case(file.path());
  EXPECT_EQ(c.law, "gaul-mayer");
  EXPECT_EQ(c.exponent, 0.25);
  EXPECT_EQ(c.friction_coefficient, 0.2);
  EXPECT_EQ(c.normal_force, 50.0);
  EXPECT_EQ(c.stiffness, 2.0e6);
  EXPECT_EQ(c.ratio_min, 1.0e-4);
  EXPECT_EQ(c.ratio_max, 5.0);
  EXPECT_EQ(c.points, 41);
  EXPECT_EQ(c.time_samples, 128);
  EXPECT_EQ(c.source, file.path().string());
  EXPECT_DOUBLE_EQ(c.full_slip_span(), 0.2 * 50.0 / (0.75 * 2.0e6));
}

TEST(io_LoopSweepCase, OmittedKeysTakeTheBuiltInDefaults) {
  const TempFile file(".yaml", sweep("    mu: 0.5\n"));
  const LoopSweepCase c = read_loop_sweep_case(file.path());
  const LoopSweepCase d = default_loop_sweep_case();
  EXPECT_EQ(c.friction_coefficient, 0.5);
  EXPECT_EQ(c.law, d.law);
  EXPECT_EQ(c.exponent, d.exponent);
  EXPECT_EQ(c.points, d.points);
  EXPECT_EQ(c.time_samples, d.time_samples);
}

TEST(io_LoopSweepCase, DefaultCaseIsTheDocumentedOne) {
  const LoopSweepCase d = default_loop_sweep_case();
  EXPECT_EQ(d.source, "built-in");
  EXPECT_EQ(d.law, "gaul-mayer");
  EXPECT_EQ(d.exponent, 1.0 / 3.0);
  EXPECT_EQ(d.friction_coefficient, 0.3);
  EXPECT_EQ(d.normal_force, 100.0);
  EXPECT_EQ(d.stiffness, 1.0e6);
  EXPECT_EQ(d.points, 25);
  EXPECT_EQ(d.time_samples, 256);
  // g_max = μF_N/((1-n)k) = 3 μF_N/(2k) for n = 1/3.
  EXPECT_NEAR(d.full_slip_span(), 4.5e-5, 1e-20);
}

TEST(io_LoopSweepCase, RatiosAreLogSpacedWithExactEnds) {
  const LoopSweepCase d = default_loop_sweep_case();
  const auto r = d.amplitude_ratios();
  ASSERT_EQ(r.size(), 25u);
  EXPECT_EQ(r.front(), 1.0e-6);
  EXPECT_EQ(r.back(), 10.0);
  const double step = std::log(r[1] / r[0]);
  for (std::size_t i = 1; i < r.size(); ++i) {
    EXPECT_NEAR(std::log(r[i] / r[i - 1]), step, 1e-12);
  }
}

TEST(io_LoopSweepCase, JenkinsFullSlipSpanIsWhereTheSliderMoves) {
  const TempFile file(".yaml", sweep("    law: jenkins\n"));
  const LoopSweepCase c = read_loop_sweep_case(file.path());
  EXPECT_DOUBLE_EQ(c.full_slip_span(), 0.3 * 100.0 / 1.0e6);
}

TEST(io_LoopSweepCase, UnknownKeyNamesFileLineColumnAndKeyPath) {
  const TempFile file(".yaml", sweep("    mu: 0.3\n    muu: 0.4\n"));
  const InputError e = error_of(file);
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.column(), 5);
  EXPECT_EQ(e.key(), "analysis.loop_sweep.muu");
  const std::string expected_start =
      file.path().string() + ":4:5: key 'analysis.loop_sweep.muu': unknown key";
  EXPECT_EQ(std::string(e.what()).rfind(expected_start, 0), 0u) << e.what();
}

TEST(io_LoopSweepCase, UnknownKeysAreRejectedAtEveryLevel) {
  const TempFile top(".yaml", "analysis:\n  loop_sweep: {}\nsolver: 1\n");
  EXPECT_EQ(error_of(top).key(), "solver");
  EXPECT_EQ(error_of(top).line(), 3);
  const TempFile analysis(".yaml", "analysis:\n  frf: {}\n");
  EXPECT_EQ(error_of(analysis).key(), "analysis.frf");
}

TEST(io_LoopSweepCase, WrongTypesAreReported) {
  const TempFile sequence(".yaml", sweep("    mu: [1, 2]\n"));
  EXPECT_EQ(error_of(sequence).constraint(), "must be a number, got a sequence");
  const TempFile quoted(".yaml", sweep("    mu: \"0.3\"\n"));
  EXPECT_EQ(error_of(quoted).constraint(), "must be a number, got string '0.3'");
  const TempFile word(".yaml", sweep("    normal_force: heavy\n"));
  EXPECT_EQ(error_of(word).key(), "analysis.loop_sweep.normal_force");
  const TempFile fraction(".yaml", sweep("    points: 41.5\n"));
  EXPECT_EQ(error_of(fraction).constraint(), "must be an integer, got '41.5'");
  const TempFile empty_value(".yaml", sweep("    kt0:\n"));
  EXPECT_EQ(error_of(empty_value).constraint(), "must be a number, got nothing");
  const TempFile not_a_map(".yaml", "analysis: 3\n");
  EXPECT_EQ(error_of(not_a_map).key(), "analysis");
}

TEST(io_LoopSweepCase, NegativeMuNamesTheConstraintAndPosition) {
  const TempFile file(".yaml", sweep("    mu: -1\n"));
  const InputError e = error_of(file);
  EXPECT_EQ(std::string(e.what()),
            file.path().string() + ":3:9: key 'analysis.loop_sweep.mu': must be > 0, got -1");
}

TEST(io_LoopSweepCase, NonFiniteValuesAreRejected) {
  for (const char* spelling : {"nan", ".nan", ".inf", "-.inf", "1e999"}) {
    const TempFile file(".yaml", sweep(std::string("    kt0: ") + spelling + "\n"));
    const InputError e = error_of(file);
    EXPECT_EQ(e.key(), "analysis.loop_sweep.kt0") << spelling;
    EXPECT_EQ(e.constraint().rfind("must be finite, got ", 0), 0u) << e.what();
  }
}

TEST(io_LoopSweepCase, NonPhysicalValuesAreRejected) {
  struct Bad {
    const char* entry;
    const char* key;
    const char* constraint;
  };
  const Bad cases[] = {
      {"    n: 1.5\n", "analysis.loop_sweep.n", "must be in (0, 1), got 1.5"},
      {"    n: 0\n", "analysis.loop_sweep.n", "must be in (0, 1), got 0"},
      {"    normal_force: 0\n", "analysis.loop_sweep.normal_force", "must be > 0, got 0"},
      {"    law: coulomb\n", "analysis.loop_sweep.law",
       "must be one of gaul-mayer, jenkins, got 'coulomb'"},
      {"    points: 1\n", "analysis.loop_sweep.points", "must be in [2, 100000], got 1"},
      {"    time_samples: 3\n", "analysis.loop_sweep.time_samples",
       "must be in [4, 1048576], got 3"},
      {"    amplitude_over_gmax: [0, 1]\n", "analysis.loop_sweep.amplitude_over_gmax[0]",
       "must be > 0, got 0"},
      {"    amplitude_over_gmax: [2, 1]\n", "analysis.loop_sweep.amplitude_over_gmax[1]",
       "must be > min 2, got 1"},
      {"    amplitude_over_gmax: [1]\n", "analysis.loop_sweep.amplitude_over_gmax",
       "must be a range [min, max] of two numbers"},
  };
  for (const Bad& bad : cases) {
    const TempFile file(".yaml", sweep(bad.entry));
    const InputError e = error_of(file);
    EXPECT_EQ(e.key(), bad.key) << bad.entry;
    EXPECT_EQ(e.constraint(), bad.constraint) << bad.entry;
    EXPECT_EQ(e.line(), 3) << bad.entry;
  }
}

TEST(io_LoopSweepCase, DuplicateKeysAreRejected) {
  const TempFile file(".yaml", sweep("    mu: 0.3\n    mu: 0.4\n"));
  const InputError e = error_of(file);
  EXPECT_EQ(e.constraint(), "duplicate key");
  EXPECT_EQ(e.line(), 4);
}

TEST(io_LoopSweepCase, SyntaxErrorsHaveAPosition) {
  const TempFile file(".yaml", "analysis:\n  loop_sweep:\n    mu: [0.3\n");
  const InputError e = error_of(file);
  EXPECT_GT(e.line(), 0);
  EXPECT_NE(std::string(e.what()).find("invalid YAML"), std::string::npos) << e.what();
}

TEST(io_LoopSweepCase, MissingPartsAreRequired) {
  const TempFile empty(".yaml", "");
  EXPECT_EQ(error_of(empty).key(), "analysis");
  const TempFile no_sweep(".yaml", "analysis: {}\n");
  EXPECT_EQ(error_of(no_sweep).key(), "analysis.loop_sweep");
}

TEST(io_LoopSweepCase, UnreadableFileIsAnInputErrorNamingIt) {
  const TempFile missing(".yaml");
  const InputError e = error_of(missing);
  EXPECT_EQ(e.file(), missing.path().string());
  EXPECT_NE(std::string(e.what()).find("cannot open case file"), std::string::npos);
}

TEST(io_LoopSweepCase, ASecondYamlDocumentIsRefusedNotIgnored) {
  // Issue 20, item 7: everything after '---' was silently ignored.
  const TempFile file(".yaml", std::string(valid_case) + "---\nanalysis:\n  loop_sweep: {mu: 0.9}\n");
  const InputError e = error_of(file);
  EXPECT_EQ(e.line(), 13) << e.what();
  EXPECT_NE(e.constraint().find("a second YAML document"), std::string::npos) << e.what();
  // An empty trailing document holds nothing to ignore.
  const TempFile empty(".yaml", std::string(valid_case) + "---\n");
  EXPECT_EQ(read_loop_sweep_case(empty.path()).points, 41);
}

}  // namespace
}  // namespace jointhb::io
