// Implicit time integration of the full FE model about the preloaded state (timeint/fe_newmark.hpp)
// on a coarse two-plate bolted lap (cases/05-bolted-lap with 10 mm elements, Jenkins contact):
// the stuck linear limit against the frequency response of the stuck tangent (with the trapezoidal
// rule's frequency warping and its Δt² convergence), the energy balance at a microslip level,
// rigid-body drift under a self-equilibrated load, and input checks.
#include "jointhb/timeint/fe_newmark.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseLU>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/sparse_cholesky.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/modal/modes.hpp"

namespace ti = jointhb::timeint;
namespace pl = jointhb::preload;
namespace fe = jointhb::fe;

namespace {

// Two 100 × 30 × 4 mm aluminium plates overlapping by 40 mm, two M5 bolts at 5 kN, free-free.
std::string newmark_lap_yaml(const std::string& divisions) {
  std::string yaml = R"(model:
  type: fe
  materials:
    aluminium: {youngs_modulus: 70.0e9, poissons_ratio: 0.33, density: 2700.0}
  parts:
    - {name: lower, material: aluminium, element: C3D8I,
       box: {origin: [0.0, 0.0, 0.0], size: [0.100, 0.030, 0.004], divisions: DIV}}
    - {name: upper, material: aluminium, element: C3D8I,
       box: {origin: [0.060, 0.0, 0.004], size: [0.100, 0.030, 0.004], divisions: DIV}}
  interfaces:
    - name: lap
      bottom: lower.zmax
      top: upper.zmin
      region: {min: [0.060, 0.0, 0.0039], max: [0.100, 0.030, 0.0041]}
      integration: nodal
      contact: {pressure: 1.0e6, decay: 1.0e6, mu: 0.3, law: jenkins, stiffness_ratio: 0.8}
  bolts:
    - {name: bolt-1, point: [0.070, 0.015, 0.0], direction: [0.0, 0.0, 1.0],
       head: {surface: upper.zmax, radius: 0.006}, nut: {surface: lower.zmin, radius: 0.006},
       stiffness: 5.0e8, preload: 5000.0}
    - {name: bolt-2, point: [0.090, 0.015, 0.0], direction: [0.0, 0.0, 1.0],
       head: {surface: upper.zmax, radius: 0.006}, nut: {surface: lower.zmin, radius: 0.006},
       stiffness: 5.0e8, preload: 5000.0}
)";
  for (std::size_t at; (at = yaml.find("DIV")) != std::string::npos;) yaml.replace(at, 3, divisions);
  return yaml;
}

struct NewmarkLap {
  jointhb::io::FeCase c;
  pl::PreloadModel model;
  pl::PreloadResult preload;
  double omega1 = 0.0;  // first elastic mode of the stuck tangent [rad/s]
};

// constant_kt > 0: the constant tangential stiffness model k_T = constant_kt instead of
// k_T = 0.8 λ p_N.
std::unique_ptr<NewmarkLap> make_lap(const std::string& divisions, double constant_kt = 0.0) {
  auto p = std::make_unique<NewmarkLap>();
  std::string yaml = newmark_lap_yaml(divisions);
  if (constant_kt > 0.0) {
    const std::string ratio = "stiffness_ratio: 0.8";
    yaml.replace(yaml.find(ratio), ratio.size(), "kt: " + std::to_string(constant_kt));
  }
  p->c = jointhb::io::parse_fe_case(yaml, "lap.yaml");
  p->model.mesh = &p->c.mesh;
  p->model.structure = fe::assemble(p->c.mesh, p->c.material_per_part);
  p->model.interfaces = p->c.interfaces;
  p->model.bolts = p->c.bolts;
  pl::PreloadOptions o;
  o.load_steps = 4;
  p->preload = pl::solve_preload(p->model, o);
  jointhb::modal::ModalOptions mo;
  mo.count = 8;
  mo.shift = -std::pow(2.0 * std::numbers::pi * 10.0, 2);
  const auto modes =
      jointhb::modal::compute_modes(p->preload.dynamic_stiffness, p->model.structure.mass, mo);
  p->omega1 = std::sqrt(modes.eigenvalues[6]);
  return p;
}

// 10 mm elements: 792 DOFs, 44 interface points.
const NewmarkLap& newmark_lap() {
  static const std::unique_ptr<NewmarkLap> l = make_lap("[10, 3, 2]");
  return *l;
}

int node_at(const fe::Mesh& mesh, double x, double y, double z) {
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if ((mesh.coordinates.col(i) - Eigen::Vector3d(x, y, z)).norm() < 1e-9) return i;
  }
  throw std::logic_error("no node there");
}

// The linear FRF of the stuck tangent, X = (K_t − ω²M + iωb K_t)⁻¹ F at one DOF (full model,
// i.e. modal superposition over all modes with the same Rayleigh damping).
std::complex<double> stuck_frf(const NewmarkLap& l, int dof, int out, double force, double omega,
                               double b) {
  using C = std::complex<double>;
  const Eigen::SparseMatrix<double>& k = l.preload.dynamic_stiffness;
  Eigen::SparseMatrix<C> z = (k - omega * omega * l.model.structure.mass).cast<C>() +
                             C(0.0, omega * b) * k.cast<C>();
  z.makeCompressed();
  Eigen::SparseLU<Eigen::SparseMatrix<C>> lu(z);
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(k.rows());
  f[dof] = force;
  return Eigen::VectorXcd(lu.solve(f))[out];
}

}  // namespace

TEST(FeNewmark, PreloadConverged) {
  const NewmarkLap& l = newmark_lap();
  ASSERT_TRUE(l.preload.status().ok()) << l.preload.message;
  EXPECT_GT(l.omega1, 2.0 * std::numbers::pi * 100.0);
}

// A tiny force: the joint stays (almost) stuck and the response is that of K_t. The trapezoidal
// rule's steady state under e^{iΩt} is exactly the FRF at the warped Ω̃ = (2/Δt) tan(ΩΔt/2);
// against the FRF at Ω the error falls like Δt² (ratio 4 for N = 32 → 64).
TEST(FeNewmark, StuckLimitMatchesLinearResponseWithDtSquaredWarping) {
  const NewmarkLap& l = newmark_lap();
  ASSERT_TRUE(l.preload.status().ok());
  const int tip = node_at(l.c.mesh, 0.0, 0.0, 0.0);
  const int dof = 3 * tip + 2;
  const double force = 1e-3;  // N
  const double omega = 0.9 * l.omega1;
  const double b = 2.0 * 0.03 / l.omega1;  // ζ = 3 % at the first elastic mode
  ti::FeExcitation ex;
  ex.forces.push_back({dof, force});
  const std::complex<double> exact = stuck_frf(l, dof, dof, force, omega, b);

  double error[2] = {0.0, 0.0};
  const int per_period[2] = {32, 64};
  for (int s = 0; s < 2; ++s) {
    ti::FeSteadyStateOptions o;
    o.steps_per_period = per_period[s];
    o.harmonics = 3;
    o.tolerance = 1e-5;
    o.max_periods = 100;
    o.output_dofs = {dof};
    o.integrator.stiffness_damping = b;
    const double dt = 2.0 * std::numbers::pi / omega / per_period[s];
    const double warped = 2.0 / dt * std::tan(0.5 * omega * dt);
    // Started from the stuck linear state at Ω̃ (w₀ = Re X(Ω̃), ẇ₀ = Re iΩ̃X(Ω̃): the scheme's own
    // steady state of the stuck linearisation). What is left to decay comes from the contact
    // points' microslip, slowly for the stiff contact modes under the trapezoidal rule: the period
    // repeats to 1e-5 after 79 (N = 32) and 38 (N = 64) periods, not to 1e-6 within 100; 1e-5 is
    // far below what is compared here.
    o.integrator.time_step = dt;
    auto start = ti::stuck_linear_fe_state(l.model, l.preload, ex, warped, o.integrator);
    ASSERT_TRUE(start.has_value());
    const auto r = ti::fe_forced_steady_state(l.model, l.preload, ex, omega, o, std::move(start));
    ASSERT_EQ(r.termination, jointhb::Termination::converged) << r.message;
    EXPECT_NEAR(r.time_step, dt, 1e-15 * dt);
    const std::complex<double> x(r.coefficients(0, 1), -r.coefficients(0, 2));  // a cos + b sin
    const std::complex<double> discrete = stuck_frf(l, dof, dof, force, warped, b);
    std::printf("N = %d: |X| = %.9e, FRF(Ω) %.9e, FRF(Ω̃) %.9e; %d periods, %.2f Newton "
                "it/step, %d factorisations, %.3f ms/step\n",
                per_period[s], std::abs(x), std::abs(exact), std::abs(discrete), r.periods,
                static_cast<double>(r.newton_iterations) / static_cast<double>(r.steps), r.factorizations,
                1e3 * r.seconds_per_step);
    EXPECT_LT(std::abs(x - discrete), 1e-5 * std::abs(discrete));
    error[s] = std::abs(x - exact) / std::abs(exact);
  }
  std::printf("relative error vs FRF(Ω): %.4e (N = 32), %.4e (N = 64), ratio %.3f\n", error[0],
              error[1], error[0] / error[1]);
  EXPECT_GT(error[0], 1e-3);  // the warping is visible
  EXPECT_NEAR(error[0] / error[1], 4.0, 0.2);
}

// A force at which the lap's edge points slip: over a period the input work equals the change of
// the stored energy plus the viscous and the friction dissipation. Exactly (for the scheme) with
// the trapezoidal contact work; with the exact increments' dissipation up to the trapezoidal
// rule's O(Δt²) at the stick/slip transitions. The balance holds over any period, so the test
// checks the third period from the stuck linear state rather than the steady state (33 periods,
// 194 s under the sanitizers on a loaded machine).
TEST(FeNewmark, EnergyBalanceOverAPeriodWithMicroslip) {
  const NewmarkLap& l = newmark_lap();
  ASSERT_TRUE(l.preload.status().ok());
  const int tip = node_at(l.c.mesh, 0.0, 0.0, 0.0);
  const int dof = 3 * tip + 2;
  const double omega = 0.9 * l.omega1;
  ti::FeExcitation ex;
  ex.forces.push_back({dof, 20.0});
  ti::FeSteadyStateOptions o;
  o.steps_per_period = 128;
  o.harmonics = 3;
  o.tolerance = 1e-5;
  o.max_periods = 3;
  o.progress = [](int p, double change) { std::printf("period %d: change %.3e\n", p, change); };
  o.output_dofs = {dof};
  o.integrator.stiffness_damping = 2.0 * 0.01 / l.omega1;
  const auto r = ti::fe_forced_steady_state(l.model, l.preload, ex, omega, o);
  // (With the default frozen k_T, T-30, the period repeats to 1e-5 after 33 periods; with k_T
  // following p_N(t) the stuck tractions ratchet, T-21. The balance includes ΔE either way.)
  ASSERT_NE(r.termination, jointhb::Termination::failed) << r.message;
  ASSERT_EQ(r.periods, 3);
  EXPECT_GT(std::abs(r.stored_energy_change), 1e-6 * r.external_work);  // not yet periodic: ΔE counts
  std::printf("%s; ΔE %.3e J\n", r.message.c_str(), r.stored_energy_change);
  const double friction = r.contact_dissipation.at(0);
  std::printf("amplitude %.4e m, W_ext %.6e J, viscous %.6e J, friction %.6e J, contact work "
              "%.6e J; %d periods, %.2f Newton it/step (max %d), %d factorisations, %.3f "
              "ms/step\n",
              std::abs(r.coefficients(0, 1)), r.external_work, r.viscous_dissipation, friction,
              r.contact_work, r.periods, static_cast<double>(r.newton_iterations) / static_cast<double>(r.steps),
              r.max_step_iterations, r.factorizations, 1e3 * r.seconds_per_step);
  EXPECT_GT(friction, 0.05 * r.external_work);  // the joint dissipates a visible share
  const double stored = r.stored_energy_change;
  EXPECT_NEAR(stored + r.viscous_dissipation + r.contact_work, r.external_work,
              1e-8 * r.external_work);
  EXPECT_NEAR(stored + r.viscous_dissipation + friction, r.external_work, 1e-3 * r.external_work);
}

// preloaded_tangential_stiffness (eq. T-30) with a law that already has a constant k_T: the
// per-point laws are the interface's law unchanged, and the integration is bit-identical.
TEST(FeNewmark, PreloadedTangentialStiffnessChangesNothingForAConstantLaw) {
  const auto l = make_lap("[10, 3, 2]", 6.7e12);
  ASSERT_TRUE(l->preload.status().ok()) << l->preload.message;
  const int dof = 3 * node_at(l->c.mesh, 0.0, 0.0, 0.0) + 2;
  ti::FeExcitation ex;
  ex.forces.push_back({dof, 20.0});  // microslip: the slip limit follows p_N(t) in both runs
  ti::FeNewmarkOptions o;
  o.time_step = 2.0 * std::numbers::pi / (0.9 * l->omega1) / 64.0;
  o.stiffness_damping = 2.0 * 0.01 / (l->omega1);
  ti::FeState final_state[2];
  double dissipation[2] = {0.0, 0.0};
  for (const bool frozen : {true, false}) {
    o.preloaded_tangential_stiffness = frozen;
    for (const auto& laws : ti::fe_point_laws(l->model, l->preload, o))
      for (const auto& law : laws) {
        EXPECT_EQ(law.options().stiffness_model, jointhb::contact::TangentialStiffnessModel::constant);
        EXPECT_EQ(law.options().tangential_stiffness, 6.7e12);
      }
    const auto start = ti::stuck_linear_fe_state(l->model, l->preload, ex, 0.9 * l->omega1, o);
    ASSERT_TRUE(start.has_value());
    const auto r = ti::integrate_fe(l->model, l->preload, ex, 0.9 * l->omega1, *start, 64, o);  // a period
    ASSERT_EQ(r.termination, jointhb::Termination::reached_end) << r.message;
    final_state[frozen ? 0 : 1] = r.final_state;
    dissipation[frozen ? 0 : 1] = r.contact_dissipation.at(0);
  }
  EXPECT_GT(dissipation[0], 0.0);  // the points do slip
  EXPECT_EQ(dissipation[0], dissipation[1]);
  EXPECT_TRUE(final_state[0].displacement == final_state[1].displacement);
  EXPECT_TRUE(final_state[0].traction.at(0) == final_state[1].traction.at(0));
}

// The frozen stiffness k_T(p_pre) equals the proportional one at the preload and the stuck
// tangent has no first-order T–N coupling of k_T (theory.md §10–11), so the two models differ
// only at second order in the amplitude: their relative difference after one period from the
// stuck linear state falls in proportion to the force (×1/10 per decade) and vanishes in the
// stuck limit, while at a microslip force it is visible. The frozen laws are the preloaded
// stiffnesses.
TEST(FeNewmark, PreloadedTangentialStiffnessKeepsTheStuckLimit) {
  const NewmarkLap& l = newmark_lap();
  ASSERT_TRUE(l.preload.status().ok());
  const int dof = 3 * node_at(l.c.mesh, 0.0, 0.0, 0.0) + 2;
  const double omega = 0.9 * l.omega1;
  ti::FeNewmarkOptions o;
  o.time_step = 2.0 * std::numbers::pi / omega / 64.0;
  o.stiffness_damping = 2.0 * 0.01 / l.omega1;
  {
    const auto laws = ti::fe_point_laws(l.model, l.preload, o);
    const auto& law = l.model.interfaces[0].law;
    const auto& gap = l.preload.interfaces[0].state.gap;
    double worst = 0.0;
    for (std::size_t p = 0; p < laws.at(0).size(); ++p) {
      const double k = law.tangential_state(gap[3 * static_cast<Eigen::Index>(p) + 2]).limits.stiffness;
      EXPECT_EQ(laws[0][p].options().stiffness_model, jointhb::contact::TangentialStiffnessModel::constant);
      if (k > 0.0) worst = std::max(worst, std::abs(laws[0][p].options().tangential_stiffness / k - 1.0));
    }
    EXPECT_EQ(worst, 0.0);
  }
  const auto difference = [&](double force) {
    ti::FeExcitation ex;
    ex.forces.push_back({dof, force});
    Eigen::VectorXd w[2];
    for (const bool frozen : {true, false}) {
      o.preloaded_tangential_stiffness = frozen;
      const auto start = ti::stuck_linear_fe_state(l.model, l.preload, ex, omega, o);
      EXPECT_TRUE(start.has_value());
      const auto r = ti::integrate_fe(l.model, l.preload, ex, omega, *start, 64, o);
      EXPECT_EQ(r.termination, jointhb::Termination::reached_end) << r.message;
      w[frozen ? 0 : 1] = r.final_state.displacement;
    }
    return (w[0] - w[1]).cwiseAbs().maxCoeff() / w[1].cwiseAbs().maxCoeff();
  };
  const double d_small = difference(1e-3), d_ten = difference(1e-2), d_slip = difference(20.0);
  std::printf("frozen vs proportional k_T after one period: relative difference %.3e (1 mN), "
              "%.3e (10 mN), %.3e (20 N)\n", d_small, d_ten, d_slip);
  EXPECT_NEAR(d_ten / d_small, 10.0, 2.0);  // second order: ∝ amplitude
  EXPECT_LT(d_small, 1e-5);
  EXPECT_GT(d_slip, 100.0 * d_small);
}

namespace {

// Rigid-body modes of the mesh (translations, small rotations about the centroid), n × 6.
Eigen::MatrixXd rigid_body_modes(const fe::Mesh& mesh) {
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(mesh.num_dofs(), 6);
  const Eigen::Vector3d c = mesh.coordinates.rowwise().mean();
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Eigen::Vector3d x = mesh.coordinates.col(i) - c;
    for (int d = 0; d < 3; ++d) {
      r(3 * i + d, d) = 1.0;
      r.block<3, 1>(3 * i, 3 + d) = Eigen::Vector3d::Unit(d).cross(x);
    }
  }
  return r;
}

}  // namespace

// A suddenly applied, self-equilibrated static pair (±F along the line of its two nodes) on the
// free-free lap: the assembly vibrates but its rigid-body motion stays zero.
TEST(FeNewmark, SelfEquilibratedStaticLoadGivesNoRigidBodyDrift) {
  const NewmarkLap& l = newmark_lap();
  ASSERT_TRUE(l.preload.status().ok());
  const int n = l.c.mesh.num_dofs();
  const int a = node_at(l.c.mesh, 0.0, 0.0, 0.0), b = node_at(l.c.mesh, 0.1, 0.0, 0.0);
  ti::FeExcitation ex;
  ex.static_force = Eigen::VectorXd::Zero(n);
  ex.static_force[3 * a] = -50.0;
  ex.static_force[3 * b] = 50.0;
  const Eigen::MatrixXd rb = rigid_body_modes(l.c.mesh);
  const Eigen::MatrixXd mr = l.model.structure.mass * rb;
  const Eigen::LDLT<Eigen::MatrixXd> rmr(rb.transpose() * mr);
  for (const double alpha : {0.0, -0.1}) {  // trapezoidal and HHT-α
    ti::FeNewmarkOptions o;
    o.time_step = 2.0 * std::numbers::pi / l.omega1 / 20.0;
    o.stiffness_damping = 2.0 * 0.01 / l.omega1;
    o.alpha = alpha;
    double w_max = 0.0, rigid_max = 0.0, v_rigid_max = 0.0, v_max = 0.0;
    const auto r = ti::integrate_fe(
        l.model, l.preload, ex, 0.0, ti::preloaded_state(l.model, l.preload), 400, o,
        [&](const ti::FeState& s) {
          w_max = std::max(w_max, s.displacement.cwiseAbs().maxCoeff());
          v_max = std::max(v_max, s.velocity.cwiseAbs().maxCoeff());
          const Eigen::VectorXd q = rmr.solve(mr.transpose() * s.displacement);
          const Eigen::VectorXd qv = rmr.solve(mr.transpose() * s.velocity);
          rigid_max = std::max(rigid_max, (rb * q).cwiseAbs().maxCoeff());
          v_rigid_max = std::max(v_rigid_max, (rb * qv).cwiseAbs().maxCoeff());
        });
    ASSERT_EQ(r.termination, jointhb::Termination::reached_end) << r.message;
    std::printf("alpha %g: max |w| %.3e m, rigid part %.3e m; max |v| %.3e m/s, rigid part %.3e "
                "m/s; %.2f Newton it/step, %d factorisations\n",
                alpha, w_max, rigid_max, v_max, v_rigid_max,
                static_cast<double>(r.newton_iterations) / static_cast<double>(r.steps),
                r.factorizations);
    EXPECT_GT(w_max, 0.0);
    EXPECT_LT(rigid_max, 1e-6 * w_max);  // round-off and the Newton tolerance, no drift
    EXPECT_LT(v_rigid_max, 1e-6 * v_max);
  }
}

TEST(FeNewmark, BadInputThrowsNamingTheField) {
  const NewmarkLap& l = newmark_lap();
  const int n = l.c.mesh.num_dofs();
  const auto throws_with = [](const auto& call, const std::string& field) {
    try {
      call();
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "no std::invalid_argument for " << field;
  };
  ti::FeExcitation bad_dof;
  bad_dof.forces.push_back({n, 1.0});
  ti::FeNewmarkOptions good;
  good.time_step = 1e-5;
  throws_with([&] {
    (void)ti::integrate_fe(l.model, l.preload, bad_dof, 1.0, ti::preloaded_state(l.model, l.preload),
                           1, good);
  }, "forces[0].dof");
  ti::FeNewmarkOptions zero_step;
  throws_with([&] {
    (void)ti::integrate_fe(l.model, l.preload, {}, 1.0, ti::preloaded_state(l.model, l.preload), 1,
                           zero_step);
  }, "time_step");
  ti::FeNewmarkOptions negative_step = good;
  negative_step.time_step = -1e-5;
  throws_with([&] {
    (void)ti::integrate_fe(l.model, l.preload, {}, 1.0, ti::preloaded_state(l.model, l.preload), 1,
                           negative_step);
  }, "time_step");
  ti::FeSteadyStateOptions so;
  so.output_dofs = {-1};
  throws_with([&] { (void)ti::fe_forced_steady_state(l.model, l.preload, {}, 1.0, so); },
              "output_dofs[0]");
  so.output_dofs = {0};
  so.integrator.refactor_ratio = 1.5;
  throws_with([&] { (void)ti::fe_forced_steady_state(l.model, l.preload, {}, 1.0, so); },
              "integrator.refactor_ratio");
}

// Cost on the coarse lap of the HB validation (5 mm elements, 2646 DOFs): run with
// --gtest_also_run_disabled_tests --gtest_filter='*FeNewmark*Timing*'. Prints, asserts nothing
// on time.
TEST(FeNewmark, DISABLED_TimingCoarseLap) {
  const auto l = make_lap("[20, 6, 2]");
  ASSERT_TRUE(l->preload.status().ok());
  const int dof = 3 * node_at(l->c.mesh, 0.0, 0.0, 0.0) + 2;
  std::printf("%d DOFs, %d interface points, f1 = %.2f Hz\n", l->c.mesh.num_dofs(),
              l->model.interfaces[0].geometry.num_points(), l->omega1 / (2.0 * std::numbers::pi));
  {
    // One factorisation of a J̃-like matrix (K_t + M/(βΔt²)): CHOLMOD LLᵀ (what is used) against
    // Eigen's SparseLU (what the exact, non-symmetric tangent would need in every iteration).
    const double dt = 2.0 * std::numbers::pi / (0.9 * l->omega1) / 128.0;
    Eigen::SparseMatrix<double> j = l->preload.dynamic_stiffness +
                                    (4.0 / (dt * dt)) * l->model.structure.mass;
    j.makeCompressed();
    fe::SparseCholesky chol;
    chol.analyze(j);
    auto t0 = std::chrono::steady_clock::now();
    chol.factorize(j);
    const double t_chol = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    t0 = std::chrono::steady_clock::now();
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(j);
    const double t_lu = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("one factorisation: CHOLMOD %.2f ms (numeric only), SparseLU %.2f ms (with "
                "analysis)\n", 1e3 * t_chol, 1e3 * t_lu);
  }
  struct Run {
    double force, refactor_ratio;
  };
  for (const Run run : {Run{1e-3, 0.2}, Run{20.0, 0.2}, Run{20.0, 0.5}, Run{20.0, 0.05},
                        Run{20.0, 1e-6}}) {
    const double force = run.force;
    ti::FeExcitation ex;
    ex.forces.push_back({dof, force});
    ti::FeSteadyStateOptions o;
    o.steps_per_period = 128;
    o.harmonics = 3;
    o.tolerance = 1e-5;
    o.max_periods = 20;
    o.output_dofs = {dof};
    o.integrator.stiffness_damping = 2.0 * 0.01 / l->omega1;
    o.integrator.refactor_ratio = run.refactor_ratio;
    const auto r = ti::fe_forced_steady_state(l->model, l->preload, ex, 0.9 * l->omega1, o);
    std::printf("F = %g N, refactor_ratio %g: %s; |a1| %.4e m; %ld steps, %.3f ms/step, %.2f Newton it/step (max "
                "%d), %d factorisations, %ld halvings; friction %.4e J of W_ext %.4e J\n",
                force, run.refactor_ratio, r.message.c_str(), std::abs(r.coefficients(0, 1)), r.steps,
                1e3 * r.seconds_per_step,
                static_cast<double>(r.newton_iterations) / static_cast<double>(r.steps),
                r.max_step_iterations, r.factorizations, r.line_search_cuts,
                r.contact_dissipation.at(0), r.external_work);
  }
}
