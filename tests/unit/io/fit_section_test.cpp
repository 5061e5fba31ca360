// The fit: section of a discrete case: parameters, targets from CSV (relative to the case file),
// options; errors at the key, or at the CSV's line and column.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "jointhb/io/discrete_case.hpp"
#include "jointhb/io/input_error.hpp"
#include "temp_file.hpp"

namespace jointhb::io {
namespace {

using testing::TempFile;

std::string case_with(const std::string& fit) {
  return R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: [[3.0e4, -1.0e4], [-1.0e4, 1.0e4]]
  damping: {rayleigh: {alpha: 0.1, beta: 1.0e-5}}
contacts:
  - {law: jenkins, dofs: [0], kt0: 2.0e4, mu: 0.4, normal_force: 5.0}
excitation:
  - {dof: 1, amplitude: [0.01, 0.05]}
analysis:
  nonlinear_modes: {mode: 1, log10_amplitude: [-7, -3], harmonics: 3}
  frf: {frequency_hz: [10, 20], harmonics: 3, output_dof: 1}
fit:
)" + fit;
}

// The case "file" sits in the temp directory, so relative target paths resolve there.
std::string case_name() {
  return (std::filesystem::temp_directory_path() / "fit-case.yaml").string();
}

void contains(const std::string& message, const std::string& needle) {
  EXPECT_NE(message.find(needle), std::string::npos) << message;
}

std::string message_of(const std::string& text) {
  try {
    parse_discrete_case(text, case_name());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(io_FitSection, ReadsParametersTargetsAndOptions) {
  const TempFile backbone(
      "-backbone.csv",
      "# comment\namplitude,frequency_hz,damping_ratio,weight,sigma_damping_ratio\n"
      "1e-6,17.2,0.0015,2,1e-4\n2e-5,17.1,0.004,1,2e-4\n");
  const TempFile frf_file("-frf.csv", "frequency_hz,amplitude\n15,1e-5\n16,2e-5\n17,5e-5\n");
  const TempFile modal("-modal.csv", "mode,frequency_hz,damping_ratio\n2,41.6,0.002\n");
  const std::string text = case_with(
      "  parameters:\n"
      "    - {name: \"contacts[0].kt0\", lower: 1.0e3, upper: 1.0e5, start: 1.0e4, log_scale: "
      "true}\n"
      "    - name: damping.rayleigh.beta\n      lower: 0.0\n      upper: 1.0e-3\n      start: "
      "1.0e-5\n"
      "  targets:\n"
      "    - {type: backbone, mode: 1, file: " +
      backbone.path().filename().string() +
      ", use: [damping_ratio], weight: 3}\n"
      "    - {type: frf, level: 1, file: " +
      frf_file.path().string() +
      "}\n"
      "    - {type: modal, file: " +
      modal.path().string() +
      "}\n"
      "  algorithm: mlsl\n  local_algorithm: neldermead\n  xtol: 1.0e-4\n  max_evaluations: 50\n"
      "  multistart: {starts: 3, seed: 9}\n  penalty: 1.0e6\n");
  DiscreteCase c;
  try {
    c = parse_discrete_case(text, case_name());
  } catch (const std::exception& e) {
    FAIL() << e.what();
  }
  ASSERT_TRUE(c.fit.has_value());
  const FitSection& f = *c.fit;
  ASSERT_EQ(f.parameters.size(), 2u);
  EXPECT_EQ(f.parameters[0].name, "contacts[0].kt0");
  EXPECT_TRUE(f.parameters[0].log_scale);
  EXPECT_EQ(f.parameters[1].name, "damping.rayleigh.beta");
  EXPECT_FALSE(f.parameters[1].log_scale);
  ASSERT_EQ(f.targets.size(), 3u);
  const auto& b = f.targets[0];
  EXPECT_EQ(b.name, "fit.targets[0]");
  ASSERT_EQ(b.points.size(), 2u);  // damping only
  EXPECT_EQ(b.points[0].quantity, fit::Quantity::damping_ratio);
  EXPECT_EQ(b.points[0].weight, 6.0);  // target 3 × row 2
  EXPECT_EQ(b.points[0].sigma, 1e-4);
  EXPECT_EQ(b.points[0].line, 3);
  EXPECT_EQ(f.targets[1].kind, fit::TargetKind::frf);
  EXPECT_EQ(f.targets[1].level, 1);
  EXPECT_EQ(f.targets[1].points.size(), 3u);
  EXPECT_EQ(f.targets[1].points[2].scale(), 5e-5);  // relative
  EXPECT_EQ(f.targets[2].points.size(), 2u);
  EXPECT_EQ(f.options.algorithm, "mlsl");
  EXPECT_EQ(f.options.local_algorithm, "neldermead");
  EXPECT_EQ(f.options.starts, 3);
  EXPECT_EQ(f.options.seed, 9u);
  EXPECT_EQ(f.options.max_evaluations, 50);
  EXPECT_EQ(f.options.penalty, 1e6);
  EXPECT_EQ(f.options.validate(), "");
}

TEST(io_FitSection, ErrorsNameTheKeyOrTheCsvLine) {
  const TempFile good("-good.csv", "amplitude,frequency_hz,damping_ratio\n1e-6,17.2,0.0015\n");
  const std::string target =
      "  targets:\n    - {type: backbone, file: " + good.path().string() + "}\n";
  const std::string kt0 =
      "  parameters:\n    - {name: \"contacts[0].kt0\", lower: 1.0e3, upper: 1.0e5, start: "
      "1.0e4}\n";
  contains(message_of(case_with("  parameters:\n    - {name: \"contacts[0].n\", lower: 0.1, "
                                "upper: 0.9, start: 0.5}\n" +
                                target)),
           ":15:14: key 'fit.parameters[0].name': unknown parameter 'contacts[0].n'; "
           "this case has: contacts[0].kt0, contacts[0].mu, contacts[0].normal_force, "
           "damping.rayleigh.alpha, damping.rayleigh.beta");
  contains(message_of(case_with(kt0 + kt0.substr(kt0.find("    -")) + target)),
           "key 'fit.parameters[1].name': 'contacts[0].kt0' is already fit.parameters[0]");
  contains(message_of(case_with(kt0 + "  targets:\n    - {type: frf, mode: 1, file: x.csv}\n")),
           "key 'fit.targets[0].mode': only for type backbone");
  contains(message_of(case_with(kt0 + "  targets:\n    - {type: backbone, file: " +
                                good.path().string() + ", use: [amplitude]}\n")),
           "key 'fit.targets[0].use[0]': must be one of frequency_hz, damping_ratio "
           "for a backbone target, got 'amplitude'");
  const TempFile header("-header.csv", "amplitude,frequency\n1e-6,17.2\n");
  contains(message_of(case_with(
               kt0 + "  targets:\n    - {type: backbone, file: " + header.path().string() + "}\n")),
           header.path().string() +
               ":1:1: key 'fit.targets[0].file': the header must "
               "name the columns amplitude, frequency_hz, damping_ratio");
  const TempFile cells("-cells.csv", "amplitude,frequency_hz,damping_ratio\n1e-6,17.2\n");
  contains(message_of(case_with(
               kt0 + "  targets:\n    - {type: backbone, file: " + cells.path().string() + "}\n")),
           cells.path().string() +
               ":2:1: key 'fit.targets[0].file': 2 cells, the "
               "header has 3 columns");
  const TempFile zero("-zero.csv", "amplitude,frequency_hz,damping_ratio\n1e-6,17.2,0\n");
  contains(message_of(case_with(
               kt0 + "  targets:\n    - {type: backbone, file: " + zero.path().string() + "}\n")),
           "damping_ratio is 0: a relative residual needs a value != 0");
  const TempFile mode("-mode.csv", "mode,frequency_hz,damping_ratio\n3,41.6,0.002\n");
  contains(message_of(case_with(
               kt0 + "  targets:\n    - {type: modal, file: " + mode.path().string() + "}\n")),
           "mode must be an integer in [1, 2], got 3");
  contains(message_of(case_with(kt0 + target + "  multistart: {starts: 0}\n")),
           "key 'fit.multistart.starts': must be in [1, 1000], got 0");
  contains(message_of(case_with(kt0 + target + "  xtol: 0.5\n")),
           "key 'fit.xtol': must be in (0, 0.1], got 0.5");
  contains(message_of(case_with(kt0)), "key 'fit.targets': required");
}

}  // namespace
}  // namespace jointhb::io
