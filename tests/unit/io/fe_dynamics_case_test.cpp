// The dynamic analyses of a finite-element case (io/fe_dynamics_case.hpp, read by io/fe_case.hpp):
// what a valid file gives, and that every bad value stops at its line and key with the violated
// constraint.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "jointhb/io/case_file.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/input_error.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"

namespace pipeline = jointhb::pipeline;

namespace {

using namespace jointhb::io;

// A small lap (the dynamic keys are read after the model is built, so the mesh must exist).
const std::string kModel = R"(model:
  type: fe
  materials:
    al: {youngs_modulus: 70.0e9, poissons_ratio: 0.33, density: 2700.0}
  parts:
    - {name: lower, material: al, box: {origin: [0, 0, 0], size: [0.04, 0.01, 0.004], divisions: [4, 1, 1]}}
    - {name: upper, material: al, box: {origin: [0.02, 0, 0.004], size: [0.04, 0.01, 0.004], divisions: [4, 1, 1]}}
  interfaces:
    - {name: lap, bottom: lower.zmax, top: upper.zmin, region: {min: [0.02, 0, 0.0039], max: [0.04, 0.01, 0.0041]},
       contact: {pressure: 1.0e6, decay: 1.0e6, mu: 0.3, law: gaul-mayer}}
analysis:
)";  // analysis entries follow from line 12

std::string with_analysis(const std::string& analysis) { return kModel + analysis; }

InputError dynamics_error_of(const std::string& text) {
  try {
    (void)parse_fe_case(text, "case.yaml");
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return InputError("", 0, 0, "", "");
}

void expect_error(const std::string& analysis, int line, const std::string& key, const std::string& constraint) {
  const InputError e = dynamics_error_of(with_analysis(analysis));
  EXPECT_EQ(e.line(), line) << e.what();
  EXPECT_EQ(e.key(), key) << e.what();
  EXPECT_NE(e.constraint().find(constraint), std::string::npos) << e.what();
}

TEST(io_FeDynamics, ValidCaseGivesTheSettingsAndTheNearestNodes) {
  const FeCase c = parse_fe_case(with_analysis(R"(  damping: {ratio: 0.01, frequency_hz: 900}
  reduction: {cutoff_hz: 20000}
  excitation: {point: [0.0601, 0.0099, 0.008], direction: [0, 0, 2]}
  outputs: [{name: tip, point: [0.06, 0.01, 0.008], direction: [1, 0, 0]}, {name: far, point: [0, 0, 0]}]
  nonlinear_modes: {mode: [1, 3], log10_amplitude: [-8, -5], frequency_drop: 0.04, harmonics: 3,
                    tangential_stiffness: instantaneous, continuation: {max_step: 0.2}, fields: 3,
                    volume_fields: false}
  frf: {frequency_hz: [900, 1000], force: [0.5, 2.0], output: far, harmonics: 2}
)"), "case.yaml");
  ASSERT_TRUE(c.dynamics.has_value());
  const FeDynamicsSpec& d = *c.dynamics;
  EXPECT_EQ(d.damping_ratio, 0.01);
  EXPECT_EQ(d.damping_frequency_hz, 900.0);
  EXPECT_EQ(d.cutoff_hz, 20000.0);
  // The nearest node to the excitation point is the upper plate's corner (0.06, 0.01, 0.008).
  EXPECT_NEAR((c.mesh.coordinates.col(d.excitation.node) - Eigen::Vector3d(0.06, 0.01, 0.008)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(d.excitation.distance, std::hypot(1e-4, 1e-4), 1e-12);
  EXPECT_EQ(d.excitation.direction, Eigen::Vector3d::UnitZ());  // normalised
  const Eigen::VectorXd f = d.excitation.functional(c.mesh.num_dofs());
  EXPECT_EQ(f.sum(), 1.0);
  EXPECT_EQ(f[3 * d.excitation.node + 2], 1.0);
  ASSERT_EQ(d.outputs.size(), 2u);
  EXPECT_EQ(d.outputs[0].name, "tip");
  EXPECT_EQ(d.outputs[0].node, d.excitation.node);
  ASSERT_TRUE(d.nonlinear_modes && d.frf);
  EXPECT_EQ(d.nonlinear_modes->modes, (std::vector<int>{1, 3}));
  EXPECT_EQ(d.nonlinear_modes->balance.harmonics, 3);
  EXPECT_EQ(d.nonlinear_modes->balance.time_samples, 64);  // max(32, 16 H) rounded up to 2^k
  EXPECT_FALSE(d.nonlinear_modes->balance.preloaded_tangential_stiffness);
  EXPECT_EQ(d.nonlinear_modes->continuation.max_step, 0.2);
  EXPECT_EQ(d.nonlinear_modes->frequency_drop, 0.04);
  EXPECT_EQ(d.nonlinear_modes->fields, 3);
  EXPECT_FALSE(d.nonlinear_modes->volume_fields);
  EXPECT_NEAR(d.frf->omega_start, 2.0 * std::numbers::pi * 900.0, 1e-9);
  EXPECT_EQ(d.frf->forces, (std::vector<double>{0.5, 2.0}));
  EXPECT_EQ(d.frf->output, 1);
  EXPECT_EQ(d.frf->balance.time_samples, 32);
  EXPECT_TRUE(d.frf->balance.preloaded_tangential_stiffness);
}

TEST(io_FeDynamics, DefaultsAndTheDriveOutput) {
  const FeCase c = parse_fe_case(with_analysis("  excitation: {point: [0.06, 0.01, 0.008]}\n  nonlinear_modes: {}\n"), "case.yaml");
  ASSERT_TRUE(c.dynamics && c.dynamics->nonlinear_modes);
  EXPECT_EQ(c.dynamics->cutoff_factor, 20.0);
  EXPECT_EQ(c.dynamics->damping_ratio, 0.0);
  ASSERT_EQ(c.dynamics->outputs.size(), 1u);
  EXPECT_EQ(c.dynamics->outputs[0].name, "drive");
  EXPECT_EQ(c.dynamics->nonlinear_modes->modes, (std::vector<int>{1}));
  EXPECT_EQ(c.dynamics->nonlinear_modes->balance.harmonics, 1);
  // The dynamic keys do not enter the preload and modes cache keys.
  const FeCase plain = parse_fe_case(kModel + "  preload: {load_steps: 4}\n", "case.yaml");
  const FeCase dyn = parse_fe_case(kModel + "  preload: {load_steps: 4}\n  nonlinear_modes: {harmonics: 3}\n", "case.yaml");
  EXPECT_EQ(pipeline::fe_stage_keys(plain, plain).preload, pipeline::fe_stage_keys(dyn, dyn).preload);
  EXPECT_EQ(pipeline::fe_stage_keys(plain, plain).modes, pipeline::fe_stage_keys(dyn, dyn).modes);
}

TEST(io_FeDynamics, BadValuesNameLineKeyAndConstraint) {
  expect_error("  damping: {ratio: 0.01}\n", 12, "analysis.damping", "neither is given");
  expect_error("  nonlinear_modes: {harmonics: 0}\n", 12, "analysis.nonlinear_modes.harmonics", "in [1, 64]");
  expect_error("  nonlinear_modes: {mode: [1, 1]}\n", 12, "analysis.nonlinear_modes.mode[1]", "listed twice");
  expect_error("  nonlinear_modes: {log10_amplitude: [-8, -8]}\n", 12, "analysis.nonlinear_modes.log10_amplitude[1]",
               "differ");
  expect_error("  nonlinear_modes: {frequency_drop: 1.5}\n", 12, "analysis.nonlinear_modes.frequency_drop", "[0, 0.9]");
  expect_error("  nonlinear_modes: {fields: -1}\n", 12, "analysis.nonlinear_modes.fields", "[0, 1000]");
  expect_error("  nonlinear_modes: {volume_fields: yes}\n", 12, "analysis.nonlinear_modes.volume_fields", "true");
  expect_error("  nonlinear_modes: {time_samples: 3}\n", 12, "analysis.nonlinear_modes.time_samples", "in [4, 65536]");
  expect_error("  nonlinear_modes: {tangential_stiffness: soft}\n", 12, "analysis.nonlinear_modes.tangential_stiffness",
               "preloaded");
  expect_error("  nonlinear_modes: {continuation: {max_step: 0.01}}\n", 12,
               "analysis.nonlinear_modes.continuation.max_step", "initial_step");
  expect_error("  nonlinear_modes: {}\n  damping: {ratio: 1.5}\n", 13, "analysis.damping.ratio", "(0, 1)");
  expect_error("  nonlinear_modes: {}\n  damping: {ratio: 0.01, rayleigh: {alpha: 1}}\n", 13, "analysis.damping.rayleigh",
               "not both");
  expect_error("  nonlinear_modes: {}\n  reduction: {cutoff_hz: 1000, cutoff_factor: 5}\n", 13,
               "analysis.reduction.cutoff_factor", "not both");
  expect_error("  nonlinear_modes: {}\n  excitation: {point: [0, 0]}\n", 13, "analysis.excitation.point", "3 numbers");
  expect_error("  nonlinear_modes: {}\n  excitation: {point: [0, 0, 0], direction: [0, 0, 0]}\n", 13,
               "analysis.excitation.direction", "not be zero");
  expect_error("  frf: {frequency_hz: [900, 1000], force: 1}\n", 12, "analysis.excitation", "required by analysis.frf");
  expect_error("  excitation: {point: [0, 0, 0]}\n  frf: {frequency_hz: [900, 1000]}\n", 13, "analysis.frf.force", "required");
  expect_error("  excitation: {point: [0, 0, 0]}\n  frf: {frequency_hz: [900, 1000], force: -1}\n", 13, "analysis.frf.force",
               "> 0");
  expect_error("  excitation: {point: [0, 0, 0]}\n  frf: {frequency_hz: [900, 1000], force: 1, output: tip}\n", 13,
               "analysis.frf.output", "unknown output 'tip'");
  expect_error("  excitation: {point: [0, 0, 0]}\n  frf: {omega: [1, 2], frequency_hz: [1, 2], force: 1}\n", 13,
               "analysis.frf.omega", "not both");
  expect_error("  nonlinear_modes: {}\n  outputs: [{name: a, point: [0, 0, 0]}, {name: a, point: [0, 0, 0]}]\n", 13,
               "analysis.outputs[1]", "used twice");
  expect_error("  nonlinear_modes: {foo: 1}\n", 12, "analysis.nonlinear_modes.foo", "unknown key");
}

TEST(io_FeDynamics, PointsOffTheModelAreRefused) {
  // Issue 20, item 7: an excitation 173 m from the nearest node was accepted (the nearest node,
  // some corner, was driven). The lap's longest element edge is 0.01 m: within 0.02 m passes.
  expect_error("  nonlinear_modes: {}\n  excitation: {point: [100.0, 140.0, 0.008]}\n", 13, "analysis.excitation.point",
               "must lie on the model (within 2 x its longest element edge = 0.02 m of a node), but lies 172 m from the nearest node");
  expect_error("  nonlinear_modes: {}\n  outputs: [{name: tip, point: [0.06, 0.01, 0.5]}]\n", 13,
               "analysis.outputs[0].point", "lies 0.492 m from the nearest node");
  const FeCase c = parse_fe_case(with_analysis("  nonlinear_modes: {}\n  excitation: {point: [0.06, 0.01, 0.025]}\n"), "case.yaml");
  EXPECT_NEAR(c.dynamics->excitation.distance, 0.017, 1e-12);
}

TEST(io_FeDynamics, ModesThatCannotExistAreRefusedBeforeAnyStage) {
  // Issue 20, item 7: mode 50 with count 12 was found only after the preload. The small lap has
  // no constraints: 6 of the computed modes are rigid-body modes.
  const std::string drive = "  excitation: {point: [0.06, 0.01, 0.008]}\n";
  expect_error("  modes: {count: 12}\n" + drive + "  nonlinear_modes: {mode: 50}\n", 14, "analysis.nonlinear_modes.mode",
               "elastic mode 50 cannot exist: analysis.modes.count = 12 modes, 6 of them rigid-body modes (the model "
               "has no constraints) leave at most 6 elastic modes; raise analysis.modes.count to at least 56");
  expect_error("  modes: {count: 12}\n" + drive + "  nonlinear_modes: {mode: [2, 7]}\n", 14,
               "analysis.nonlinear_modes.mode[1]", "elastic mode 7 cannot exist");
  expect_error(drive + "  nonlinear_modes: {mode: 15}\n", 13, "analysis.nonlinear_modes.mode",
               "the default analysis.modes.count = 20 modes");
  expect_error("  modes: {count: 6}\n" + drive + "  frf: {frequency_hz: [900, 1000], force: 1}\n", 12,
               "analysis.modes.count", "must leave at least one elastic mode");
  // The last elastic mode there is still accepted.
  const FeCase c = parse_fe_case(with_analysis("  modes: {count: 12}\n" + drive + "  nonlinear_modes: {mode: 6}\n"), "case.yaml");
  EXPECT_EQ(c.dynamics->nonlinear_modes->modes, std::vector<int>{6});
}

TEST(io_FeDynamics, TheBuiltInDefaultCaseIsTheLapDampingCurve) {
  const CaseFile c = parse_case_file(default_case_text(), "built-in default case");
  const auto* fe = std::get_if<FeCase>(&c);
  ASSERT_NE(fe, nullptr);
  ASSERT_TRUE(fe->dynamics && fe->dynamics->nonlinear_modes);
  EXPECT_EQ(fe->interfaces.size(), 1u);
  EXPECT_EQ(fe->interfaces[0].geometry.num_points(), 192);
  EXPECT_EQ(fe->dynamics->nonlinear_modes->frequency_drop, 0.03);
}

}  // namespace

// Identification parameters of an FE case (pipeline/fe_pipeline.hpp): the names offered, the
// values set exactly, and which stage keys a value enters.
TEST(io_FeFitParameters, NamesValuesAndStageKeys) {
  const std::string text = with_analysis("  damping: {ratio: 0.005}\n  nonlinear_modes: {mode: 1}\n");
  const FeCase base = parse_fe_case(text, "case.yaml");
  pipeline::FePipeline p(base, base);
  EXPECT_EQ(p.parameter_names(),
            (std::vector<std::string>{"interfaces.lap.pressure", "interfaces.lap.decay", "interfaces.lap.mu",
                                      "interfaces.lap.n", "interfaces.lap.stiffness_ratio", "damping.ratio"}));
  const pipeline::FeStageKeys k0 = p.keys();
  const double mu = 0.1 + 1.0 / 3.0, zeta = 2.0 / 3.0 * 1e-2;
  p.set_parameter("interfaces.lap.mu", mu);
  EXPECT_EQ(p.parameter("interfaces.lap.mu"), mu);
  EXPECT_EQ(p.model().interfaces[0].law.options().friction_coefficient, mu);
  const pipeline::FeStageKeys ka = p.keys();
  EXPECT_NE(ka.model, k0.model);  // μ enters the (frictional) preload
  p.set_parameter("damping.ratio", zeta);
  EXPECT_EQ(p.analysis().dynamics->damping_ratio, zeta);
  EXPECT_EQ(p.keys().modes, ka.modes);  // the damping enters no stage key
  p.set_parameter("interfaces.lap.stiffness_ratio", 0.7);
  EXPECT_EQ(p.model().interfaces[0].law.options().stiffness_ratio, 0.7);
  EXPECT_NE(p.keys().model, ka.model);
  // the same values give the same keys (the stage store hits)
  p.set_parameter("interfaces.lap.stiffness_ratio", base.interfaces[0].law.options().stiffness_ratio);
  EXPECT_EQ(p.keys().modes, ka.modes);
  // μ for the dynamics only: no stage key changes, the parameter reads the dynamic value
  p.set_parameter("interfaces.lap.mu", 0.25, pipeline::ParameterScope::dynamics);
  EXPECT_EQ(p.keys().modes, ka.modes);
  EXPECT_EQ(p.parameter("interfaces.lap.mu"), 0.25);
  EXPECT_THROW(p.set_parameter("interfaces.other.mu", 1.0), std::invalid_argument);
  EXPECT_THROW(p.set_parameter("bolts.b1.preload", 1.0), std::invalid_argument);
  EXPECT_THROW(p.set_parameter("interfaces.lap.mu", -0.1), std::invalid_argument);
  EXPECT_THROW(p.set_parameter("interfaces.lap.decay", 1.0, pipeline::ParameterScope::dynamics), std::invalid_argument);
  EXPECT_THROW(p.set_parameter("damping.ratio", 1.5), std::invalid_argument);
  EXPECT_EQ(p.parameter("damping.ratio"), zeta);  // a rejected value changes nothing
}
