#include "jointhb/io/discrete_case.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "jointhb/io/case_file.hpp"
#include "jointhb/io/input_error.hpp"
#include "temp_file.hpp"

namespace jointhb::io {
namespace {

using testing::TempFile;

// The example of the issue, line by line (line numbers matter to the tests below).
const char* const example = R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: [[2.0, -1.0], [-1.0, 2.0]]
  damping: {rayleigh: {alpha: 0.0, beta: 0.001}}
contacts:
  - {law: jenkins, dofs: [1], kt0: 1.0, mu: 0.3, normal_force: 1.0}
  - {law: gaul-mayer, dofs: [0, 1], kt0: 1.0, mu: 0.3, normal_force: 1.0, n: 0.333}
excitation:
  - {dof: 0, amplitude: [0.05, 0.1, 0.2]}
analysis:
  frf: {omega: [0.5, 2.0], harmonics: 7, time_samples: 128, output_dof: 1}
)";

// Lines 1-4: an undamped two-DOF model.
const std::string two_dof_model = R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: [[2.0, -1.0], [-1.0, 2.0]]
)";
const std::string excitation = "excitation:\n  - {dof: 0, amplitude: 0.1}\n";
const std::string frf = "analysis:\n  frf: {omega: [0.5, 2.0]}\n";

/// A case of `two_dof_model` + `middle` + excitation + frf, with either part replaceable.
std::string with(const std::string& middle, const std::string& forces = excitation,
                 const std::string& analysis = frf) {
  return two_dof_model + middle + forces + analysis;
}

Eigen::MatrixXd dense(const hb::SparseMatrix& a) { return Eigen::MatrixXd(a); }

InputError error_of(const std::string& text) {
  try {
    (void)parse_discrete_case(text, "case.yaml");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return InputError("", 0, 0, "", "");
}

/// The 1-based column of `needle` in line `line` (1-based) of `text`.
int column_of(const std::string& text, int line, const std::string& needle) {
  std::istringstream in(text);
  std::string current;
  for (int i = 0; i < line; ++i) std::getline(in, current);
  const auto at = current.find(needle);
  EXPECT_NE(at, std::string::npos) << "'" << needle << "' not on line " << line << ": " << current;
  return static_cast<int>(at) + 1;
}

/// Expects the error of `text` at line `line`, at the first `needle` on that line, with `key`
/// and `constraint`, as one message "case.yaml:LINE:COL: key 'KEY': CONSTRAINT".
void expect_error(const std::string& text, int line, const std::string& needle,
                  const std::string& key, const std::string& constraint) {
  const InputError e = error_of(text);
  const int column = column_of(text, line, needle);
  EXPECT_EQ(std::string(e.what()), "case.yaml:" + std::to_string(line) + ":" +
                                       std::to_string(column) + ": key '" + key +
                                       "': " + constraint)
      << text;
}

TEST(io_DiscreteCase, ExampleGivesTheMatricesContactsLevelsAndFrfOptions) {
  const DiscreteCase c = parse_discrete_case(example, "case.yaml");
  EXPECT_EQ(c.source, "case.yaml");
  const hb::DiscreteSystem& s = c.system;
  ASSERT_EQ(s.dofs(), 2);
  Eigen::MatrixXd k(2, 2);
  k << 2.0, -1.0, -1.0, 2.0;
  EXPECT_EQ(dense(s.mass), Eigen::MatrixXd::Identity(2, 2));
  EXPECT_EQ(dense(s.stiffness), k);
  EXPECT_EQ(c.damping_model, "rayleigh");
  EXPECT_EQ(c.rayleigh_alpha, 0.0);
  EXPECT_EQ(c.rayleigh_beta, 0.001);
  EXPECT_EQ(dense(s.damping), 0.001 * k);
  EXPECT_EQ(s.validate(), "");

  ASSERT_EQ(s.contacts.size(), 2u);
  const hb::ContactElement& j = s.contacts[0];
  EXPECT_EQ(j.law, "jenkins");
  EXPECT_EQ(j.dof_a, 1);
  EXPECT_EQ(j.dof_b, -1);
  EXPECT_EQ(j.stiffness, 1.0);
  EXPECT_EQ(j.friction_coefficient, 0.3);
  EXPECT_EQ(j.normal_force, 1.0);
  EXPECT_EQ(j.reference_force, 0.0);
  EXPECT_EQ(j.reference_slip, 0.0);
  const hb::ContactElement& g = s.contacts[1];
  EXPECT_EQ(g.law, "gaul-mayer");
  EXPECT_EQ(g.dof_a, 0);
  EXPECT_EQ(g.dof_b, 1);
  EXPECT_EQ(g.exponent, 0.333);

  ASSERT_EQ(c.levels.size(), 3u);
  ASSERT_EQ(c.level_amplitudes.size(), 3u);
  const double amplitudes[] = {0.05, 0.1, 0.2};
  for (std::size_t l = 0; l < 3; ++l) {
    EXPECT_EQ(c.level_amplitudes[l], amplitudes[l]);
    EXPECT_EQ(c.levels[l].static_force.size(), 0);
    ASSERT_EQ(c.levels[l].forces.size(), 1u);
    EXPECT_EQ(c.levels[l].forces[0].dof, 0);
    EXPECT_EQ(c.levels[l].forces[0].amplitude, amplitudes[l]);
    EXPECT_EQ(c.levels[l].forces[0].harmonic, 1);
  }

  ASSERT_TRUE(c.frf.has_value());
  EXPECT_EQ(c.frf->omega_start, 0.5);
  EXPECT_EQ(c.frf->omega_end, 2.0);
  EXPECT_EQ(c.frf->harmonics, 7);
  EXPECT_EQ(c.frf->time_samples, 128);
  EXPECT_EQ(c.frf->output_dof, 1);
  EXPECT_EQ(c.frf->selection, hb::HarmonicSelection::automatic);
}

TEST(io_DiscreteCase, ReadsAFileAndNamesItInErrors) {
  const TempFile good(".yaml", example);
  EXPECT_EQ(read_discrete_case(good.path()).source, good.path().string());
  const TempFile bad(".yaml", with("", excitation, "analysis:\n  frf: {omega: [0.5, 0.5]}\n"));
  try {
    (void)read_discrete_case(bad.path());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), bad.path().string() +
                                         ":8:22: key 'analysis.frf.omega[1]': must differ from "
                                         "start 0.5, got 0.5");
  }
  const TempFile missing(".missing.yaml");
  try {
    (void)read_discrete_case(missing.path());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), missing.path().string());
    EXPECT_EQ(e.line(), 0);
  }
}

TEST(io_DiscreteCase, OmittedKeysTakeTheDocumentedDefaults) {
  const DiscreteCase c = parse_discrete_case(with(""), "case.yaml");
  EXPECT_EQ(c.damping_model, "none");
  EXPECT_EQ(c.system.damping.size(), 0);
  EXPECT_TRUE(c.system.contacts.empty());
  ASSERT_TRUE(c.frf.has_value());
  const continuation::FrfOptions defaults;
  EXPECT_EQ(c.frf->harmonics, 7);
  EXPECT_EQ(c.frf->time_samples, 128);
  EXPECT_EQ(c.frf->output_dof, 0);
  EXPECT_EQ(c.frf->selection, hb::HarmonicSelection::automatic);
  EXPECT_EQ(c.frf->periodic_tolerance, defaults.periodic_tolerance);
  EXPECT_EQ(c.frf->continuation.initial_step, defaults.continuation.initial_step);
  EXPECT_EQ(c.frf->continuation.min_step, defaults.continuation.min_step);
  EXPECT_EQ(c.frf->continuation.max_step, defaults.continuation.max_step);
  EXPECT_EQ(c.frf->continuation.max_points, defaults.continuation.max_points);
  EXPECT_EQ(c.frf->continuation.residual_tolerance, defaults.continuation.residual_tolerance);
  ASSERT_EQ(c.levels.size(), 1u);
  EXPECT_EQ(c.level_amplitudes[0], 0.1);

  // The smallest power of two >= max(128, 16 H), and within reach of the AFT bound 2H + 2.
  EXPECT_EQ(default_time_samples(1), 128);
  EXPECT_EQ(default_time_samples(8), 128);
  EXPECT_EQ(default_time_samples(9), 256);
  EXPECT_EQ(default_time_samples(20), 512);
  EXPECT_EQ(default_time_samples(256), 4096);
  const DiscreteCase h20 = parse_discrete_case(
      with("", excitation, "analysis:\n  frf: {omega: [0.5, 2.0], harmonics: 20}\n"), "c.yaml");
  EXPECT_EQ(h20.frf->time_samples, 512);
}

TEST(io_DiscreteCase, EveryFrfKeyIsRead) {
  const std::string analysis = R"(analysis:
  frf:
    frequency_hz: [2.0, 0.5]
    harmonics: 5
    time_samples: 12
    output_dof: 1
    harmonic_selection: odd
    periodic_tolerance: 1.0e-12
    continuation: {initial_step: 0.05, min_step: 1.0e-6, max_step: 0.2, max_points: 300,
                   residual_tolerance: 1.0e-9}
)";
  const DiscreteCase c = parse_discrete_case(with("", excitation, analysis), "case.yaml");
  ASSERT_TRUE(c.frf.has_value());
  const continuation::FrfOptions& o = *c.frf;
  EXPECT_DOUBLE_EQ(o.omega_start, 4.0 * std::numbers::pi);  // a sweep down is allowed
  EXPECT_DOUBLE_EQ(o.omega_end, std::numbers::pi);
  EXPECT_EQ(o.harmonics, 5);
  EXPECT_EQ(o.time_samples, 12);  // = 2H + 2, the smallest allowed
  EXPECT_EQ(o.output_dof, 1);
  EXPECT_EQ(o.selection, hb::HarmonicSelection::odd);
  EXPECT_EQ(o.periodic_tolerance, 1e-12);
  EXPECT_EQ(o.continuation.initial_step, 0.05);
  EXPECT_EQ(o.continuation.min_step, 1e-6);
  EXPECT_EQ(o.continuation.max_step, 0.2);
  EXPECT_EQ(o.continuation.max_points, 300);
  EXPECT_EQ(o.continuation.residual_tolerance, 1e-9);

  const DiscreteCase all = parse_discrete_case(
      with("", excitation, "analysis:\n  frf: {omega: [1, 2], harmonic_selection: all}\n"), "c");
  EXPECT_EQ(all.frf->selection, hb::HarmonicSelection::all);
}

TEST(io_DiscreteCase, OneDofModelAcceptsPlainNumbers) {
  const std::string text = R"(model:
  type: discrete
  mass: 2.0
  stiffness: 8.0
  damping: {matrix: 0.04}
contacts:
  - {law: jenkins, dofs: [0], kt0: 4.0, mu: 0.5, normal_force: 2.0, reference_force: -1.0,
     reference_slip: 0.25}
excitation:
  - {dof: 0, amplitude: 0.5}
analysis:
  frf: {omega: [1, 3]}
)";
  const DiscreteCase c = parse_discrete_case(text, "case.yaml");
  ASSERT_EQ(c.system.dofs(), 1);
  EXPECT_EQ(dense(c.system.mass)(0, 0), 2.0);
  EXPECT_EQ(dense(c.system.stiffness)(0, 0), 8.0);
  EXPECT_EQ(c.damping_model, "matrix");
  EXPECT_EQ(dense(c.system.damping)(0, 0), 0.04);
  EXPECT_EQ(c.system.contacts[0].reference_force, -1.0);
  EXPECT_EQ(c.system.contacts[0].reference_slip, 0.25);
}

TEST(io_DiscreteCase, RayleighDampingIsAlphaMPlusBetaK) {
  const std::string text = R"(model:
  type: discrete
  mass: [[2.0, 0.5], [0.5, 1.0]]
  stiffness: [[3.0, -1.0], [-1.0, 1.0]]
  damping:
    rayleigh: {alpha: 0.1, beta: 0.01}
)" + excitation + frf;
  const DiscreteCase c = parse_discrete_case(text, "case.yaml");
  const Eigen::MatrixXd expected = 0.1 * dense(c.system.mass) + 0.01 * dense(c.system.stiffness);
  EXPECT_TRUE(dense(c.system.damping).isApprox(expected, 1e-15)) << dense(c.system.damping);
  EXPECT_EQ(dense(c.system.damping)(0, 0), 0.1 * 2.0 + 0.01 * 3.0);
  EXPECT_EQ(c.rayleigh_alpha, 0.1);
  EXPECT_EQ(c.rayleigh_beta, 0.01);
}

TEST(io_DiscreteCase, ModalDampingGivesTwoZetaOmegaInModalCoordinates) {
  const std::string damping[] = {"  damping: {modal: [0.01, 0.05]}\n",
                                 "  damping: {modal: [0.02]}\n"};
  const std::vector<double> ratios[] = {{0.01, 0.05}, {0.02, 0.0}};
  for (int t = 0; t < 2; ++t) {
    const std::string text = R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 2.0]]
  stiffness: [[3.0, -1.0], [-1.0, 1.0]]
)" + damping[t] + excitation +
                             frf;
    const DiscreteCase c = parse_discrete_case(text, "case.yaml");
    EXPECT_EQ(c.damping_model, "modal");
    const hb::LinearModes modes = hb::linear_modes(c.system, false);
    const Eigen::MatrixXd modal = modes.shapes.transpose() * dense(c.system.damping) * modes.shapes;
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(2, 2);
    for (int i = 0; i < 2; ++i) expected(i, i) = 2.0 * ratios[t][i] * modes.omega[i];
    EXPECT_LT((modal - expected).cwiseAbs().maxCoeff(), 1e-14) << modal;
    EXPECT_GT(modes.omega[1], modes.omega[0]);
  }
}

TEST(io_DiscreteCase, ExcitationLevelsBroadcastAndAddStaticForces) {
  const std::string forces = R"(excitation:
  - {dof: 0, amplitude: [1.0, -3.0]}
  - {dof: 1, amplitude: 2.0, harmonic: 3}
  - {dof: 1, static: 0.5}
  - {dof: 1, amplitude: 0.25, static: 0.25}
)";
  const DiscreteCase c = parse_discrete_case(with("", forces), "case.yaml");
  ASSERT_EQ(c.levels.size(), 2u);
  EXPECT_EQ(c.level_amplitudes, (std::vector<double>{2.0, 3.0}));
  for (std::size_t l = 0; l < 2; ++l) {
    const hb::Excitation& e = c.levels[l];
    ASSERT_EQ(e.static_force.size(), 2);
    EXPECT_EQ(e.static_force[0], 0.0);
    EXPECT_EQ(e.static_force[1], 0.75);
    ASSERT_EQ(e.forces.size(), 3u);
    EXPECT_EQ(e.forces[0].amplitude, l == 0 ? 1.0 : -3.0);
    EXPECT_EQ(e.forces[1].dof, 1);
    EXPECT_EQ(e.forces[1].amplitude, 2.0);
    EXPECT_EQ(e.forces[1].harmonic, 3);
    EXPECT_EQ(e.forces[2].amplitude, 0.25);
  }
}

TEST(io_DiscreteCase, UnknownKeysAreReportedAtEveryLevel) {
  expect_error(two_dof_model + "solver: 1\n" + excitation + frf, 5, "solver", "solver",
               "unknown key; allowed: analysis, contacts, excitation, fit, model, study");
  expect_error("model:\n  type: discrete\n  masss: 1.0\n", 3, "masss", "model.masss",
               "unknown key; allowed: damping, mass, stiffness, type");
  expect_error(with("  damping: {raleigh: {alpha: 1}}\n"), 5, "raleigh", "model.damping.raleigh",
               "unknown key; allowed: matrix, modal, rayleigh");
  expect_error(with("  damping: {rayleigh: {alfa: 1}}\n"), 5, "alfa", "model.damping.rayleigh.alfa",
               "unknown key; allowed: alpha, beta");
  expect_error(
      with("contacts:\n  - {law: jenkins, dofs: [1], kt0: 1, mu: 0.3, normal_force: 1, kto: 2}\n"),
      6, "kto", "contacts[0].kto",
      "unknown key; allowed: dofs, kn, kt0, law, mu, n, normal_force, reference_force, "
      "reference_slip");
  expect_error(with("", "excitation:\n  - {dof: 0, amp: 0.1}\n"), 6, "amp", "excitation[0].amp",
               "unknown key; allowed: amplitude, dof, harmonic, static");
  expect_error(with("", excitation, "analysis:\n  frd: {}\n"), 8, "frd", "analysis.frd",
               "unknown key; allowed: frf, nonlinear_modes");
  expect_error(with("", excitation, "analysis:\n  frf: {omega: [1, 2], harmonic: 3}\n"), 8,
               "harmonic", "analysis.frf.harmonic",
               "unknown key; allowed: accuracy, check_jacobian, continuation, error_estimate, frequency_hz, "
               "harmonic_selection, harmonics, "
               "max_output_change, omega, output_dof, periodic_tolerance, stability, stability_method, time_samples");
  expect_error(with("", excitation, "analysis:\n  frf: {omega: [1, 2], continuation: {step: 1}}\n"),
               8, "step", "analysis.frf.continuation.step",
               "unknown key; allowed: initial_step, max_points, max_step, min_step, "
               "residual_tolerance");
}

TEST(io_DiscreteCase, NonlinearModesAreRead) {
  const DiscreteCase c = parse_discrete_case(
      "model: {type: discrete, mass: 1.0, stiffness: 4.0}\n"
      "contacts:\n  - {law: jenkins, dofs: [0], kt0: 1.0, mu: 0.5, normal_force: 2.0}\n"
      "analysis:\n  nonlinear_modes: {log10_amplitude: [-6, -1], harmonics: 5,\n"
      "                    continuation: {max_points: 77}}\n",
      "case.yaml");
  ASSERT_TRUE(c.nonlinear_modes.has_value());
  EXPECT_FALSE(c.frf.has_value());
  EXPECT_EQ(c.nonlinear_modes->mode.mode, 1);
  EXPECT_EQ(c.nonlinear_modes->log10_amplitude_start, -6.0);
  EXPECT_EQ(c.nonlinear_modes->log10_amplitude_end, -1.0);
  EXPECT_EQ(c.nonlinear_modes->mode.harmonics, 5);
  EXPECT_EQ(c.nonlinear_modes->mode.time_samples, 128);
  EXPECT_EQ(c.nonlinear_modes->continuation.max_points, 77);
  EXPECT_EQ(c.nonlinear_modes->max_damping_ratio, 0.0);  // default: no end at a damping ratio
  EXPECT_EQ(c.modes, std::vector<int>{1});
  const DiscreteCase overdamped = parse_discrete_case(
      "model: {type: discrete, mass: 1.0, stiffness: 4.0}\n"
      "analysis:\n  nonlinear_modes: {log10_amplitude: [-6, -1], max_damping_ratio: 1}\n",
      "case.yaml");
  EXPECT_EQ(overdamped.nonlinear_modes->max_damping_ratio, 1.0);
  try {
    (void)parse_discrete_case(
        "model: {type: discrete, mass: 1.0, stiffness: 4.0}\n"
        "analysis:\n  nonlinear_modes: {log10_amplitude: [-6, -1], max_damping_ratio: -0.5}\n",
        "case.yaml");
    ADD_FAILURE() << "a negative max_damping_ratio accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "analysis.nonlinear_modes.max_damping_ratio");
  }
  try {
    (void)parse_discrete_case(
        "model: {type: discrete, mass: 1.0, stiffness: 4.0}\n"
        "analysis:\n  nonlinear_modes: {mode: 2, log10_amplitude: [-6, -1]}\n",
        "case.yaml");
    ADD_FAILURE() << "mode 2 of a 1-DOF model accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "analysis.nonlinear_modes.mode");
  }
}

TEST(io_DiscreteCase, AnalysesOfOtherKindsAreNamed) {
  const InputError modes = error_of(with("", excitation, "analysis:\n  nonlinear_modes: {}\n"));
  EXPECT_EQ(modes.key(), "analysis.nonlinear_modes.log10_amplitude");
  EXPECT_EQ(modes.constraint(), "required: [start, end] of log10 of the modal amplitude");
  const InputError sweep = error_of(with("", excitation, "analysis:\n  loop_sweep: {}\n"));
  EXPECT_EQ(sweep.key(), "analysis.loop_sweep");
  EXPECT_EQ(sweep.line(), 8);
  EXPECT_NE(sweep.constraint().find("a case without model"), std::string::npos);
}

TEST(io_DiscreteCase, WrongTypesAreReported) {
  expect_error(with("", "excitation:\n  - {dof: 0, amplitude: \"0.1\"}\n"), 6, "\"0.1\"",
               "excitation[0].amplitude", "must be a number, got string '0.1'");
  expect_error(with("", "excitation:\n  - {dof: 1.0, amplitude: 0.1}\n"), 6, "1.0",
               "excitation[0].dof", "must be an integer, got '1.0'");
  expect_error(with("contacts: {law: jenkins}\n"), 5, "{", "contacts",
               "must be a list of contact elements, got a mapping");
  expect_error("model:\n  type: discrete\n  mass: {m: 1}\n", 3, "{", "model.mass",
               "must be a square matrix (a list of rows, or a number for one DOF), got a mapping");
  expect_error("model:\n  type: discrete\n  mass: [1.0, 2.0]\n", 3, "1.0", "model.mass[0]",
               "must be a row (a list of numbers), got '1.0'");
  expect_error(with("", excitation, "analysis:\n  frf: {omega: [1, 2], harmonics: 7.5}\n"), 8,
               "7.5", "analysis.frf.harmonics", "must be an integer, got '7.5'");
  expect_error(with("", excitation, "analysis:\n  frf: {omega: 1.5}\n"), 8, "1.5",
               "analysis.frf.omega", "must be a range [start, end] of two numbers");
  expect_error(with("", excitation, "analysis: [frf]\n"), 7, "[", "analysis",
               "must be a mapping, got a sequence");
}

TEST(io_DiscreteCase, NonFiniteNumbersAreRejected) {
  expect_error("model:\n  type: discrete\n  mass: [[.nan, 0.0], [0.0, 1.0]]\n", 3, ".nan",
               "model.mass[0][0]", "must be finite, got not-a-number");
  expect_error(
      with("contacts:\n  - {law: jenkins, dofs: [1], kt0: .inf, mu: 0.3, normal_force: 1}\n"), 6,
      ".inf", "contacts[0].kt0", "must be finite, got inf");
  expect_error(with("", "excitation:\n  - {dof: 0, amplitude: [0.1, 1e999]}\n"), 6, "1e999",
               "excitation[0].amplitude[1]", "must be finite, got inf");
}

TEST(io_DiscreteCase, ModelTypeAndMatrixShapesAreChecked) {
  expect_error("model:\n  type: shell\n", 2, "shell", "model.type",
               "must be discrete here (fe: a finite-element case, docs/case-files.md), got 'shell'");
  expect_error("model:\n  mass: 1.0\n", 2, "mass", "model.type", "required (discrete)");
  expect_error("model:\n  type: discrete\n  mass: 1.0\n", 2, "type", "model.stiffness", "required");
  expect_error("model:\n  type: discrete\n  mass: [[1.0, 0.0], [0.0, 1.0, 0.0]]\n", 3,
               "[0.0, 1.0, 0.0]", "model.mass[1]",
               "must have 2 entries (a square matrix of 2 rows), got 3");
  expect_error("model:\n  type: discrete\n  mass: []\n", 3, "[]", "model.mass",
               "must be a non-empty square matrix, got no rows");
  expect_error(R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: [[2.0, -1.0], [-1.0, 2.0, 0.0]]
)",
               4, "[-1.0, 2.0, 0.0]", "model.stiffness[1]",
               "must have 2 entries like model.mass, got 3");
  expect_error(R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: [[2.0]]
)",
               4, "[[", "model.stiffness", "must have 2 rows like model.mass, got 1");
  expect_error(R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: 2.0
)",
               4, "2.0", "model.stiffness", "must be a 2 x 2 matrix like model.mass, got a number");
}

TEST(io_DiscreteCase, SystemConstraintsAreReportedAtTheMatrix) {
  // DiscreteSystem::validate() finds these; the reader points at the entry or matrix concerned.
  expect_error(R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: [[2.0, -1.0], [-1.5, 2.0]]
)" + excitation + frf,
               4, "-1.5", "model.stiffness[1][0]",
               "must equal model.stiffness[0][1] = -1 (the matrix must be symmetric), got -1.5");
  expect_error(R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, -1.0]]
  stiffness: [[2.0, -1.0], [-1.0, 2.0]]
)" + excitation + frf,
               3, "[[", "model.mass", "must be positive definite, got smallest eigenvalue -1");
  expect_error(R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: [[1.0, 0.0], [0.0, -2.0]]
)" + excitation + frf,
               4, "[[", "model.stiffness",
               "must be positive semi-definite, got smallest eigenvalue -2");
  expect_error(with("  damping:\n    matrix: [[0.1, 0.2], [0.0, 0.1]]\n"), 6, "0.0",
               "model.damping.matrix[1][0]",
               "must equal model.damping.matrix[0][1] = 0.2 (the matrix must be symmetric), got 0");
  // A singular K (a free-free chain) is fine.
  EXPECT_NO_THROW((void)parse_discrete_case(R"(model:
  type: discrete
  mass: [[1.0, 0.0], [0.0, 1.0]]
  stiffness: [[1.0, -1.0], [-1.0, 1.0]]
)" + excitation + frf,
                                            "case.yaml"));
}

TEST(io_DiscreteCase, DampingModelsAreChecked) {
  expect_error(with("  damping: {rayleigh: {alpha: 0.1}, modal: [0.01]}\n"), 5, "modal",
               "model.damping.modal",
               "only one damping model is allowed; 'rayleigh' is already given");
  expect_error(with("  damping: {}\n"), 5, "{", "model.damping",
               "must give one of matrix, modal, rayleigh");
  expect_error(with("  damping: {rayleigh: {beta: -0.1}}\n"), 5, "-0.1",
               "model.damping.rayleigh.beta", "must be >= 0, got -0.1");
  expect_error(with("  damping: {modal: [0.01, 0.02, 0.03]}\n"), 5, "[", "model.damping.modal",
               "must have 1 to 2 entries (one per mode, lowest first), got 3");
  expect_error(with("  damping: {modal: [0.01, -0.02]}\n"), 5, "-0.02", "model.damping.modal[1]",
               "must be >= 0, got -0.02");
}

TEST(io_DiscreteCase, ContactConstraintsAreChecked) {
  const auto contact = [](const std::string& entry) {
    return with(
        "contacts:\n  - {law: jenkins, dofs: [1], kt0: 1, mu: 0.3, normal_force: 1}\n"
        "  - {" +
        entry + "}\n");
  };
  expect_error(contact("law: jenkins, dofs: [2], kt0: 1, mu: 0.3, normal_force: 1"), 7, "2]",
               "contacts[1].dofs[0]", "must be in [0, 1], got 2");
  expect_error(contact("law: jenkins, dofs: [1, 1], kt0: 1, mu: 0.3, normal_force: 1"), 7, "1]",
               "contacts[1].dofs[1]",
               "must differ from contacts[1].dofs[0] = 1 (a contact joins two different DOFs)");
  expect_error(contact("law: jenkins, dofs: [0, 1, 0], kt0: 1, mu: 0.3, normal_force: 1"), 7, "[0",
               "contacts[1].dofs",
               "must be [a] (to ground) or [a, b] (between two DOFs), got 3 entries");
  expect_error(contact("law: jenkins, dofs: [1], kt0: -1, mu: 0.3, normal_force: 1"), 7, "-1",
               "contacts[1].kt0", "must be > 0, got -1");
  expect_error(contact("law: jenkins, dofs: [1], kt0: 1, mu: 0.3, normal_force: 1, n: 0.5"), 7,
               "n:", "contacts[1].n",
               "not a parameter of the jenkins law (only gaul-mayer has an exponent)");
  expect_error(contact("law: gaul-mayer, dofs: [1], kt0: 1, mu: 0.3, normal_force: 1"), 7, "{",
               "contacts[1].n", "required for law gaul-mayer (in (0, 1))");
  expect_error(contact("law: gaul-mayer, dofs: [1], kt0: 1, mu: 0.3, normal_force: 1, n: 1"), 7,
               "1}", "contacts[1].n", "must be in (0, 1), got 1");
  expect_error(contact("law: coulomb, dofs: [1], kt0: 1, mu: 0.3, normal_force: 1"), 7, "coulomb",
               "contacts[1].law", "must be one of gaul-mayer, jenkins, normal-exponential, got 'coulomb'");
  expect_error(contact("law: jenkins, dofs: [1], kt0: 1, normal_force: 1"), 7, "{",
               "contacts[1].mu", "required for law jenkins");
  expect_error(contact("law: jenkins, dofs: [1], kt0: 1, mu: 0.3, mu: 0.4, normal_force: 1"), 7,
               "mu: 0.4", "contacts[1].mu", "duplicate key");
  expect_error(
      contact("law: jenkins, dofs: [1], kt0: 1, mu: 0.3, normal_force: 2, reference_force: 0.7"), 7,
      "0.7", "contacts[1].reference_force",
      "must be in [-mu normal_force, mu normal_force] = [-0.6, 0.6], got 0.7");
}

TEST(io_DiscreteCase, ExcitationConstraintsAreChecked) {
  expect_error(with("", R"(excitation:
  - {dof: 0, amplitude: [0.1, 0.2, 0.3]}
  - {dof: 1, amplitude: [0.1, 0.2]}
)"),
               7, "[", "excitation[1].amplitude",
               "must have 3 entries (one per level, like excitation[0].amplitude) or 1, got 2");
  expect_error(with("", "excitation:\n  - {dof: 2, amplitude: 0.1}\n"), 6, "2,",
               "excitation[0].dof", "must be in [0, 1], got 2");
  expect_error(with("", "excitation:\n  - {dof: 0}\n"), 6, "{", "excitation[0]",
               "must give amplitude (a harmonic force) or static (a constant force)");
  expect_error(with("", "excitation:\n  - {dof: 0, static: 1.0, harmonic: 2}\n"), 6, "harmonic",
               "excitation[0].harmonic", "only with amplitude (a harmonic force)");
  expect_error(with("", "excitation:\n  - {dof: 0, amplitude: 0.1, harmonic: 0}\n"), 6, "0}",
               "excitation[0].harmonic", "must be in [1, 256], got 0");
  expect_error(with("", "excitation: []\n"), 5, "[", "excitation",
               "must be a non-empty list of forces, got an empty list");
  // What the FRF needs of the excitation.
  expect_error(with("", "", "analysis:\n  frf: {omega: [1, 2]}\n"), 6, "frf", "excitation",
               "required by analysis.frf (a list of forces)");
  expect_error(with("", "excitation:\n  - {dof: 0, static: 1.0}\n"), 6, "-", "excitation",
               "analysis.frf needs a harmonic force (an entry with amplitude)");
  expect_error(with("", "excitation:\n  - {dof: 0, amplitude: [0.1, 0.0]}\n"), 6, "-", "excitation",
               "level 1 has only zero amplitudes (analysis.frf needs a force at every level)");
  expect_error(with("", "excitation:\n  - {dof: 0, amplitude: 0.1, harmonic: 3}\n",
                    "analysis:\n  frf: {omega: [1, 2], harmonics: 2}\n"),
               6, "3}", "excitation[0].harmonic", "must be <= analysis.frf.harmonics = 2, got 3");
  expect_error(with("", "excitation:\n  - {dof: 0, amplitude: 0.1, static: 0.1}\n",
                    "analysis:\n  frf: {omega: [1, 2], harmonic_selection: odd}\n"),
               8, "odd", "analysis.frf.harmonic_selection",
               "odd needs a symmetric case, but excitation[0] is a static force (use auto or all)");
  expect_error(with("", "excitation:\n  - {dof: 0, amplitude: 0.1, harmonic: 2}\n",
                    "analysis:\n  frf: {omega: [1, 2], harmonic_selection: odd}\n"),
               8, "odd", "analysis.frf.harmonic_selection",
               "odd needs a symmetric case, but excitation[0] forces the even harmonic 2 (use auto "
               "or all)");
}

TEST(io_DiscreteCase, FrfConstraintsAreChecked) {
  const auto frf_with = [](const std::string& entries) {
    return with("", excitation, "analysis:\n  frf: {" + entries + "}\n");
  };
  expect_error(frf_with("omega: [1, 2], harmonics: 7, time_samples: 15"), 8, "15",
               "analysis.frf.time_samples", "must be in [2 harmonics + 2 = 16, 1048576], got 15");
  expect_error(frf_with("time_samples: 15, harmonics: 7, omega: [1, 2]"), 8, "15",
               "analysis.frf.time_samples", "must be in [2 harmonics + 2 = 16, 1048576], got 15");
  expect_error(frf_with("omega: [1, 2], harmonics: 257"), 8, "257", "analysis.frf.harmonics",
               "must be in [1, 256], got 257");
  expect_error(frf_with("omega: [1, 2], frequency_hz: [0.1, 0.3]"), 8, "frequency_hz",
               "analysis.frf.frequency_hz",
               "give either omega [rad/s] or frequency_hz [Hz], not both");
  expect_error(frf_with("frequency_hz: [0.1, 0.3], omega: [1, 2]"), 8, "omega",
               "analysis.frf.omega", "give either omega [rad/s] or frequency_hz [Hz], not both");
  expect_error(frf_with("harmonics: 3"), 8, "{", "analysis.frf.omega",
               "required: the range [start, end] in rad/s (or frequency_hz in Hz)");
  expect_error(frf_with("omega: [0, 2]"), 8, "0,", "analysis.frf.omega[0]", "must be > 0, got 0");
  expect_error(frf_with("omega: [1, 2], output_dof: 2"), 8, "2}", "analysis.frf.output_dof",
               "must be in [0, 1], got 2");
  expect_error(frf_with("omega: [1, 2], harmonic_selection: even"), 8, "even",
               "analysis.frf.harmonic_selection", "must be one of auto, all, odd, got 'even'");
  expect_error(frf_with("omega: [1, 2], periodic_tolerance: 0.01"), 8, "0.01",
               "analysis.frf.periodic_tolerance", "must be in (0, 0.001], got 0.01");
  expect_error(frf_with("omega: [1, 2], continuation: {min_step: 0.1}"), 8, "0.1",
               "analysis.frf.continuation.min_step",
               "must be <= initial_step = 0.01 (the default), got 0.1");
  expect_error(frf_with("omega: [1, 2], continuation: {initial_step: 0.5, max_step: 0.2}"), 8,
               "0.5", "analysis.frf.continuation.initial_step",
               "must be <= max_step = 0.2, got 0.5");
  expect_error(frf_with("omega: [1, 2], continuation: {max_step: 0.001}"), 8, "0.001",
               "analysis.frf.continuation.max_step",
               "must be >= initial_step = 0.01 (the default), got 0.001");
  expect_error(frf_with("omega: [1, 2], continuation: {max_points: 0}"), 8, "0}",
               "analysis.frf.continuation.max_points", "must be in [1, 100000], got 0");
  expect_error(frf_with("omega: [1, 2], continuation: {residual_tolerance: 0}"), 8, "0}",
               "analysis.frf.continuation.residual_tolerance", "must be in (0, 1), got 0");
}

TEST(io_DiscreteCase, AnAnalysisIsRequired) {
  const InputError none = error_of(two_dof_model + excitation);
  EXPECT_EQ(std::string(none.what()),
            "case.yaml:1:1: key 'analysis': required; known analyses: frf, nonlinear_modes");
  expect_error(with("", excitation, "analysis: {}\n"), 7, "{", "analysis",
               "must name at least one analysis; known: frf, nonlinear_modes");
  const InputError empty = error_of("");
  EXPECT_EQ(empty.key(), "model");
  EXPECT_EQ(empty.constraint(), "required (the file is empty)");
}

// ---- the dispatcher
// ------------------------------------------------------------------------------

std::filesystem::path repository_file(const std::string& relative) {
  // tests/unit/io/this_file.cpp -> repository root
  return std::filesystem::path(__FILE__).parent_path().parent_path().parent_path().parent_path() /
         relative;
}

TEST(io_CaseFile, AModelMakesADiscreteCase) {
  const CaseFile c = parse_case_file(example, "case.yaml");
  ASSERT_TRUE(std::holds_alternative<DiscreteCase>(c));
  EXPECT_EQ(std::get<DiscreteCase>(c).levels.size(), 3u);
}

TEST(io_CaseFile, NoModelMakesALoopSweepCase) {
  const CaseFile c =
      parse_case_file("analysis:\n  loop_sweep:\n    mu: 0.2\n    points: 5\n", "case.yaml");
  ASSERT_TRUE(std::holds_alternative<LoopSweepCase>(c));
  EXPECT_EQ(std::get<LoopSweepCase>(c).friction_coefficient, 0.2);
  EXPECT_EQ(std::get<LoopSweepCase>(c).points, 5);
  // Errors are the loop-sweep reader's.
  try {
    (void)parse_case_file("analysis:\n  loop_sweep:\n    mu: -1\n", "case.yaml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "case.yaml:3:9: key 'analysis.loop_sweep.mu': must be > 0, got -1");
  }
}

TEST(io_CaseFile, WhatOnlyAModelCanHaveAsksForTheModel) {
  try {
    (void)parse_case_file("analysis:\n  frf: {omega: [1, 2]}\n", "case.yaml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "case.yaml:2:3: key 'model': required by analysis.frf (a case without model: can "
              "only run analysis.loop_sweep)");
  }
  try {
    (void)parse_case_file("excitation: []\nanalysis:\n  loop_sweep: {}\n", "case.yaml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "model");
    EXPECT_EQ(e.line(), 1);
  }
  try {
    (void)parse_case_file("model:\n  type: discrete\n  mass: [1\n", "case.yaml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("invalid YAML"), std::string::npos) << e.what();
    EXPECT_GT(e.line(), 0);
  }
}

TEST(io_CaseFile, TheShippedCasesParse) {
  const auto loop = repository_file("cases/01-contact-loop/case.yaml");
  ASSERT_TRUE(std::filesystem::exists(loop)) << loop;
  const CaseFile first = read_case_file(loop);
  ASSERT_TRUE(std::holds_alternative<LoopSweepCase>(first));
  EXPECT_EQ(std::get<LoopSweepCase>(first).points, 41);

  const auto frf_case = repository_file("cases/02-two-dof-frf/case.yaml");
  ASSERT_TRUE(std::filesystem::exists(frf_case)) << frf_case;
  const CaseFile second = read_case_file(frf_case);
  ASSERT_TRUE(std::holds_alternative<DiscreteCase>(second));
  const DiscreteCase& c = std::get<DiscreteCase>(second);
  EXPECT_EQ(c.source, frf_case.string());
  EXPECT_EQ(c.system.dofs(), 2);
  EXPECT_EQ(c.system.contacts.size(), 2u);
  EXPECT_EQ(c.level_amplitudes, (std::vector<double>{0.05, 0.5, 1.5}));
  ASSERT_TRUE(c.frf.has_value());
  EXPECT_EQ(c.frf->output_dof, 1);

  // Case 15: a preloaded normal contact (law normal-exponential: kn held as the stiffness).
  const auto fold_case = repository_file("cases/15-normal-contact-fold/case.yaml");
  const CaseFile third = read_case_file(fold_case);
  ASSERT_TRUE(std::holds_alternative<DiscreteCase>(third));
  const hb::ContactElement& normal = std::get<DiscreteCase>(third).system.contacts.at(0);
  EXPECT_TRUE(normal.normal());
  EXPECT_EQ(normal.stiffness, 1.0e9);
  EXPECT_EQ(normal.normal_force, 2000.0);
  EXPECT_EQ(normal.slip_limit(), 2000.0);
}

TEST(io_CaseFile, UnreadableFileIsAnInputError) {
  const TempFile missing(".yaml");
  try {
    (void)read_case_file(missing.path());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), missing.path().string());
    EXPECT_NE(std::string(e.what()).find("cannot open case file"), std::string::npos);
  }
}

}  // namespace
}  // namespace jointhb::io
