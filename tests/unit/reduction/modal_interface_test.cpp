// The modal interface model (reduction/modal_interface.hpp) of a preloaded, free-free bolted lap
// (case 05's geometry, validation/fe/lap_case.hpp, coarsened to 20 × 6 × 1 C3D8I per plate: 1764
// DOFs, 192 contact points). Checked against a direct complex sparse solve of the stuck, Rayleigh-
// damped full model (K_t − Ω²M + iΩC) u = f: the modal sum over the kept modes plus the residual
// terms of eq. (T-23/T-24) must reproduce its gaps and output DOFs, with an error that falls fast
// as the cutoff rises, and clearly worse without the first-order (R1) terms.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseLU>
#include <cmath>
#include <complex>
#include <cstdio>
#include <memory>

#include "../../../validation/fe/lap_case.hpp"
#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/contact_patches.hpp"
#include "jointhb/reduction/modal_interface.hpp"
#include "unit/test_constants.hpp"

namespace {

using namespace jointhb;
namespace rd = jointhb::reduction;
using SpMat = Eigen::SparseMatrix<double>;
using Complex = std::complex<double>;
using CVec = Eigen::VectorXcd;
using test_constants::kTwoPi;

int nearest_node(const fe::Mesh& mesh, const Eigen::Vector3d& x) {
  int best = 0;
  for (int i = 1; i < mesh.num_nodes(); ++i)
    if ((mesh.coordinates.col(i) - x).norm() < (mesh.coordinates.col(best) - x).norm()) best = i;
  return best;
}

// The preloaded lap, built once for every test of the suite.
struct ModalLap {
  io::FeCase c;
  preload::PreloadModel model;
  preload::PreloadResult preload;
  rd::ModalLoad load;
  std::vector<rd::ModalOutputSpec> outputs;
  SpMat K, M, G;  // all DOFs (free-free), G stacked over the interfaces
};

const ModalLap& modal_lap() {
  static const std::unique_ptr<ModalLap> instance = [] {
    auto l = std::make_unique<ModalLap>();
    validation::LapCaseOptions o;
    o.nx = 20;
    o.ny = 6;
    o.nz = 1;
    l->c = io::parse_fe_case(validation::lap_case_yaml(o), "lap.yaml");
    l->model.mesh = &l->c.mesh;
    l->model.structure = fe::assemble(l->c.mesh, l->c.material_per_part);
    l->model.interfaces = l->c.interfaces;
    l->model.bolts = l->c.bolts;
    l->model.constraints = l->c.constraints;
    l->preload = preload::solve_preload(l->model, l->c.preload);
    const int n = l->c.mesh.num_dofs();
    // A vertical force at the free end of the upper plate; outputs: that DOF and the free end of
    // the lower plate, vertical.
    const int drive = nearest_node(l->c.mesh, {0.160, 0.015, 0.008});
    const int far = nearest_node(l->c.mesh, {0.0, 0.015, 0.0});
    l->load = {"end force", Eigen::VectorXd::Unit(n, 3 * drive + 2)};
    l->outputs = {{"drive z", Eigen::VectorXd::Unit(n, 3 * drive + 2)}, {"far end z", Eigen::VectorXd::Unit(n, 3 * far + 2)}};
    l->K = preload::dynamic_stiffness(l->model, l->preload.displacement);
    l->M = l->model.structure.mass;
    std::vector<Eigen::Triplet<double>> t;
    int offset = 0;
    for (const auto& ci : l->model.interfaces) {
      for (int j = 0; j < ci.geometry.gap_operator.outerSize(); ++j)
        for (SpMat::InnerIterator it(ci.geometry.gap_operator, j); it; ++it)
          t.emplace_back(offset + static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
      offset += static_cast<int>(ci.geometry.gap_operator.rows());
    }
    l->G.resize(offset, n);
    l->G.setFromTriplets(t.begin(), t.end());
    return l;
  }();
  return *instance;
}

rd::ModalInterfaceOptions options(double cutoff_hz) {
  rd::ModalInterfaceOptions o;
  o.cutoff_hz = cutoff_hz;
  o.modal.shift = -std::pow(kTwoPi * 10.0, 2);  // free-free: below the rigid-body modes
  return o;
}

rd::ModalInterfaceResult build(double cutoff_hz, double a = 0.0, double b = 0.0) {
  rd::ModalInterfaceOptions o = options(cutoff_hz);
  o.rayleigh_mass = a;
  o.rayleigh_stiffness = b;
  return rd::build_modal_interface(modal_lap().model, modal_lap().preload, modal_lap().load, modal_lap().outputs, o);
}

// The first elastic mode [Hz] of the lap (from a cheap build).
double first_elastic_hz() {
  static const double f = [] {
    const rd::ModalInterfaceResult r = build(1.0);
    return r.modes.frequencies_hz[6];
  }();
  return f;
}

// (K_t − Ω²M + iΩ(aM + bK_t)) u = f on the DOFs not held by the model's constraints (all DOFs for
// the free-free lap), complex sparse LU; u returned on the full DOFs (zeros where held).
CVec direct_solve(const preload::PreloadModel& model, const preload::PreloadResult& preload, double Omega, double a,
                  double b, const Eigen::VectorXd& f) {
  const fe::DofMap dofs = fe::DofMap::from_fixed_nodes(model.mesh->num_nodes(), model.constraints);
  const SpMat K = dofs.restrict(preload::dynamic_stiffness(model, preload.displacement));
  const SpMat M = dofs.restrict(model.structure.mass);
  const Complex beta(1.0, Omega * b);
  const Eigen::SparseMatrix<Complex> A =
      K.cast<Complex>() * beta + M.cast<Complex>() * Complex(-Omega * Omega, Omega * a);
  Eigen::SparseLU<Eigen::SparseMatrix<Complex>> lu;
  lu.compute(A);
  EXPECT_EQ(lu.info(), Eigen::Success);
  const CVec u_free = lu.solve(dofs.restrict(f).cast<Complex>());
  CVec u = CVec::Zero(dofs.num_full());
  for (int i = 0; i < dofs.num_free(); ++i) u[dofs.full_of_free[static_cast<std::size_t>(i)]] = u_free[i];
  return u;
}

CVec direct_solve(double Omega, double a, double b, const Eigen::VectorXd& f) {
  return direct_solve(modal_lap().model, modal_lap().preload, Omega, a, b, f);
}

struct Prediction {
  CVec gaps;     // 3P
  CVec outputs;  // per output
};

// The model's prediction for the load shape (first_order = false drops the R1-type terms).
Prediction predict_load(const hb::InterfaceModel& m, double Omega, bool first_order = true) {
  const double a = m.rayleigh_mass, b = m.rayleigh_stiffness, s = m.residual_shift;
  const Complex beta(1.0, Omega * b);
  const Complex w = s * beta - Omega * Omega + Complex(0.0, Omega * a);
  const Complex c1 = first_order ? w / (beta * beta) : Complex(0.0);
  CVec h(m.num_modes());
  for (int j = 0; j < m.num_modes(); ++j)
    h[j] = 1.0 / Complex(m.omega2[j] - Omega * Omega, Omega * (a + b * m.omega2[j]));
  const CVec eta = h.cwiseProduct(m.load_modal.cast<Complex>());
  Prediction p;
  p.gaps = m.gap_shapes.cast<Complex>() * eta + m.load_residual0.cast<Complex>() / beta -
           c1 * m.load_residual1.cast<Complex>();
  p.outputs.resize(static_cast<Eigen::Index>(m.outputs.size()));
  for (std::size_t k = 0; k < m.outputs.size(); ++k) {
    const hb::InterfaceOutput& o = m.outputs[k];
    p.outputs[static_cast<Eigen::Index>(k)] =
        o.modal.cast<Complex>().dot(eta) + o.load_residual0 / beta - c1 * o.load_residual1;
  }
  return p;
}

// The prediction for interface forces f = Gᵀ q (exercises R0, R1 and the outputs' residual0/1).
Prediction predict_interface_force(const hb::InterfaceModel& m, double Omega, const Eigen::VectorXd& q,
                                   bool first_order = true) {
  const double a = m.rayleigh_mass, b = m.rayleigh_stiffness, s = m.residual_shift;
  const Complex beta(1.0, Omega * b);
  const Complex w = s * beta - Omega * Omega + Complex(0.0, Omega * a);
  const Complex c1 = first_order ? w / (beta * beta) : Complex(0.0);
  CVec h(m.num_modes());
  for (int j = 0; j < m.num_modes(); ++j)
    h[j] = 1.0 / Complex(m.omega2[j] - Omega * Omega, Omega * (a + b * m.omega2[j]));
  const CVec eta = h.cwiseProduct((m.gap_shapes.transpose() * q).cast<Complex>());
  Prediction p;
  p.gaps = m.gap_shapes.cast<Complex>() * eta + (m.residual_flexibility * q).cast<Complex>() / beta -
           c1 * (m.residual_inertia * q).cast<Complex>();
  p.outputs.resize(static_cast<Eigen::Index>(m.outputs.size()));
  for (std::size_t k = 0; k < m.outputs.size(); ++k) {
    const hb::InterfaceOutput& o = m.outputs[k];
    p.outputs[static_cast<Eigen::Index>(k)] =
        o.modal.cast<Complex>().dot(eta) + o.residual0.dot(q) / beta - c1 * o.residual1.dot(q);
  }
  return p;
}

struct Errors {
  double gaps = 0.0, outputs = 0.0;
  [[nodiscard]] double max() const { return std::max(gaps, outputs); }
};

Errors errors(const Prediction& p, const CVec& u) {
  const CVec g = modal_lap().G.cast<Complex>() * u;
  Errors e;
  e.gaps = (p.gaps - g).norm() / g.norm();
  for (std::size_t k = 0; k < modal_lap().outputs.size(); ++k) {
    const Complex exact = modal_lap().outputs[k].functional.cast<Complex>().dot(u);
    e.outputs = std::max(e.outputs, std::abs(p.outputs[static_cast<Eigen::Index>(k)] - exact) / std::abs(exact));
  }
  return e;
}

}  // namespace

TEST(ModalInterface, PreloadConverges) {
  ASSERT_TRUE(modal_lap().preload.status().ok()) << modal_lap().preload.message;
  EXPECT_TRUE(modal_lap().model.constraints.empty());  // free-free: the dynamics keep every DOF
}

TEST(ModalInterface, ValidateAcceptsTheBuiltModelAndNamesCorruptedFields) {
  const rd::ModalInterfaceResult r = build(4.0 * first_elastic_hz());
  const hb::InterfaceModel& m = r.model;
  std::printf("[          ] %s\n", r.brief().c_str());
  EXPECT_EQ(m.validate(), "");
  EXPECT_EQ(m.num_points(), modal_lap().model.interfaces[0].geometry.num_points());
  EXPECT_EQ(m.num_modes(), r.kept_modes);

  auto rejects = [&](const char* field, auto corrupt) {
    hb::InterfaceModel bad = m;
    corrupt(bad);
    const std::string message = bad.validate();
    EXPECT_NE(message.find(field), std::string::npos) << "expected '" << field << "' in: " << message;
  };
  rejects("gap_shapes", [](hb::InterfaceModel& x) { x.gap_shapes.conservativeResize(x.gap_shapes.rows(), x.gap_shapes.cols() - 1); });
  rejects("residual_flexibility", [](hb::InterfaceModel& x) { x.residual_flexibility(0, 1) += 1.0; });
  rejects("residual_inertia", [](hb::InterfaceModel& x) { x.residual_inertia.resize(3, 3); });
  rejects("groups", [](hb::InterfaceModel& x) { x.groups[0].count -= 1; });
  rejects("groups", [](hb::InterfaceModel& x) { x.groups[0].first = 1; });
  rejects("areas", [](hb::InterfaceModel& x) { x.areas[3] = 0.0; });
  rejects("omega2", [](hb::InterfaceModel& x) { x.omega2[0] = 1e-3; });  // a rigid mode not exactly 0
  ASSERT_GE(m.omega2.size(), 9);  // 6 rigid modes and at least 3 elastic ones (indices below)
  const Eigen::Index last = m.omega2.size() - 1;
  rejects("omega2", [last](hb::InterfaceModel& x) { x.omega2[last - 2] = x.omega2[last] * 2.0; });  // not ascending
  rejects("omega2", [last](hb::InterfaceModel& x) { x.omega2[last - 1] = std::nan(""); });
  rejects("load_residual1", [](hb::InterfaceModel& x) { x.load_residual1.resize(2); });
  rejects("outputs[1]", [](hb::InterfaceModel& x) { x.outputs[1].residual0[5] = INFINITY; });
  rejects("references", [](hb::InterfaceModel& x) { x.references.pop_back(); });
  rejects("stuck_tangents", [](hb::InterfaceModel& x) { x.stuck_tangents.pop_back(); });
  rejects("rigid_modes", [](hb::InterfaceModel& x) { x.rigid_modes = x.num_modes() + 1; });
}

TEST(ModalInterface, RejectsInvalidOptionsAndSizesNamingTheField) {
  rd::ModalInterfaceOptions o = options(0.0);
  EXPECT_NE(o.validate().find("cutoff_hz"), std::string::npos);
  o = options(1000.0);
  o.rayleigh_mass = -1.0;
  EXPECT_NE(o.validate().find("rayleigh_mass"), std::string::npos);
  o = options(1000.0);
  o.initial_count = 0;
  try {
    (void)rd::build_modal_interface(modal_lap().model, modal_lap().preload, modal_lap().load, modal_lap().outputs, o);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("initial_count"), std::string::npos) << e.what();
  }
  rd::ModalLoad short_load{"short", Eigen::VectorXd::Zero(5)};
  try {
    (void)rd::build_modal_interface(modal_lap().model, modal_lap().preload, short_load, modal_lap().outputs, options(1000.0));
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("load.force"), std::string::npos) << e.what();
  }
  // A shift above the rigid-body modes of a free-free model: K_t − sM is not positive definite.
  o = options(1000.0);
  o.modal.shift = 1.0e4;
  EXPECT_THROW((void)rd::build_modal_interface(modal_lap().model, modal_lap().preload, modal_lap().load, modal_lap().outputs, o),
               std::runtime_error);
}

// Nodal integration: the 192 points are 63 node pairs with identical gap rows; only those are
// solved for, and the residual terms of coincident points are exact copies.
TEST(ModalInterface, CoincidentPointsShareTheirResidualTerms) {
  const rd::ModalInterfaceResult r = build(2000.0);
  EXPECT_EQ(r.model.num_points(), 192);
  EXPECT_EQ(r.distinct_gap_rows, 3 * 63);
  const Eigen::MatrixXd G = Eigen::MatrixXd(modal_lap().G);
  int pairs = 0;
  for (int p = 0; p < 192; ++p)
    for (int q = p + 1; q < 192; ++q)
      if ((G.middleRows(3 * p, 3) - G.middleRows(3 * q, 3)).cwiseAbs().maxCoeff() == 0.0) {
        ++pairs;
        EXPECT_EQ((r.model.residual_flexibility.middleRows(3 * p, 3) - r.model.residual_flexibility.middleRows(3 * q, 3))
                      .cwiseAbs().maxCoeff(), 0.0);
        EXPECT_EQ((r.model.residual_inertia.middleRows(3 * p, 3) - r.model.residual_inertia.middleRows(3 * q, 3))
                      .cwiseAbs().maxCoeff(), 0.0);
        EXPECT_EQ((r.model.load_residual1.segment<3>(3 * p) - r.model.load_residual1.segment<3>(3 * q)).cwiseAbs().maxCoeff(), 0.0);
      }
  EXPECT_GT(pairs, 100);
}

TEST(ModalInterface, FreeFreeLapHasSixRigidModesThatOpenNoGap) {
  const rd::ModalInterfaceResult r = build(4.0 * first_elastic_hz());
  const hb::InterfaceModel& m = r.model;
  ASSERT_EQ(m.rigid_modes, 6);
  for (int j = 0; j < 6; ++j) EXPECT_EQ(m.omega2[j], 0.0);
  EXPECT_GT(m.omega2[6], 0.0);
  double rigid = 0.0, elastic = 0.0;
  for (int j = 0; j < m.num_modes(); ++j)
    (j < 6 ? rigid : elastic) = std::max(j < 6 ? rigid : elastic, m.gap_shapes.col(j).norm());
  std::printf("[          ] max |G phi| rigid %.3e, elastic %.3e (ratio %.2e); f7 = %.1f Hz\n", rigid, elastic,
              rigid / elastic, r.modes.frequencies_hz[6]);
  EXPECT_LT(rigid, 1e-6 * elastic);
}

TEST(ModalInterface, ResidualMatricesAreSymmetricPositiveSemiDefinite) {
  const hb::InterfaceModel m = build(4.0 * first_elastic_hz()).model;
  for (const Eigen::MatrixXd* R : {&m.residual_flexibility, &m.residual_inertia}) {
    EXPECT_EQ((*R - R->transpose()).cwiseAbs().maxCoeff(), 0.0);
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(*R, Eigen::EigenvaluesOnly).eigenvalues();
    EXPECT_GE(eig.minCoeff(), -1e-10 * eig.maxCoeff()) << "min " << eig.minCoeff() << " max " << eig.maxCoeff();
    EXPECT_GT(eig.maxCoeff(), 0.0);
  }
}

// The key test: receptances of the model against the direct solve of the full damped system.
TEST(ModalInterface, ReceptanceMatchesDirectSolveAndConvergesWithTheCutoff) {
  const double f1 = first_elastic_hz(), w1 = kTwoPi * f1;
  const double zeta = 0.01, a = zeta * w1, b = zeta / w1;  // ζ = 1 % at the first elastic mode
  const std::vector<double> ratios{0.3, 0.9, 1.1, 2.0};
  // Five cutoffs for the table below; the decrease is asserted over every other one (a factor 4 in
  // frequency): one quantity's error need not fall at every step, since the neglected terms of
  // different residual modes partly cancel (e.g. the far-end output at 2 ω1 rises from 1.1e-4 at
  // 8 f1 to 1.9e-4 at 16 f1) while the worst error over all quantities falls by 4 orders.
  const std::vector<double> cutoffs{4.0 * f1, 8.0 * f1, 16.0 * f1, 32.0 * f1, 64.0 * f1};
  std::vector<CVec> u_load, u_force;
  Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(modal_lap().G.rows(), -1.0, 2.0).array().sin();  // interface forces
  q *= 1e3;
  const Eigen::VectorXd f_interface = modal_lap().G.transpose() * q;
  for (double ratio : ratios) {
    u_load.push_back(direct_solve(ratio * w1, a, b, modal_lap().load.force));
    u_force.push_back(direct_solve(ratio * w1, a, b, f_interface));
  }
  std::vector<double> worst, worst_zeroth;
  for (double cutoff : cutoffs) {
    const rd::ModalInterfaceResult r = build(cutoff, a, b);
    std::printf("[          ] cutoff %.0f Hz (%.0f x f1): %s\n", cutoff, cutoff / f1, r.brief().c_str());
    double e_max = 0.0, e0_max = 0.0;
    for (std::size_t k = 0; k < ratios.size(); ++k) {
      const double Omega = ratios[k] * w1;
      const Errors e_load = errors(predict_load(r.model, Omega), u_load[k]);
      const Errors e_force = errors(predict_interface_force(r.model, Omega, q), u_force[k]);
      const Errors z_load = errors(predict_load(r.model, Omega, false), u_load[k]);
      const Errors z_force = errors(predict_interface_force(r.model, Omega, q, false), u_force[k]);
      std::printf("[          ]   Omega = %.1f w1: load gaps %.2e outputs %.2e | interface force gaps %.2e outputs "
                  "%.2e | without R1: %.2e %.2e %.2e %.2e\n",
                  ratios[k], e_load.gaps, e_load.outputs, e_force.gaps, e_force.outputs, z_load.gaps, z_load.outputs,
                  z_force.gaps, z_force.outputs);
      e_max = std::max({e_max, e_load.max(), e_force.max()});
      e0_max = std::max({e0_max, z_load.max(), z_force.max()});
    }
    worst.push_back(e_max);
    worst_zeroth.push_back(e0_max);
  }
  for (std::size_t i = 0; i < cutoffs.size(); ++i)
    EXPECT_LT(worst[i], 0.2 * worst_zeroth[i]) << "the first-order terms must help clearly, cutoff " << cutoffs[i];
  EXPECT_LT(worst.back(), 0.01 * worst_zeroth.back());
  for (std::size_t i = 2; i < cutoffs.size(); i += 2)
    EXPECT_LT(worst[i], 0.1 * worst[i - 2]) << "error must fall fast with the cutoff, " << cutoffs[i] << " Hz";
  EXPECT_LT(worst.back(), 1e-6);
}

// With user constraints (the lower plate clamped at x = 0) the dynamics use the free DOFs only:
// no rigid-body modes, and the output at a clamped DOF is exactly 0.
TEST(ModalInterface, ClampedLapUsesTheFreeDofsAndMatchesTheDirectSolve) {
  const ModalLap& l = modal_lap();
  preload::PreloadModel clamped = l.model;
  fe::FixedNodes end;
  for (int i = 0; i < l.c.mesh.num_nodes(); ++i)
    if (l.c.mesh.coordinates(0, i) < 1e-9) end.nodes.push_back(i);
  clamped.constraints = {end};
  const preload::PreloadResult p = preload::solve_preload(clamped, l.c.preload);
  ASSERT_TRUE(p.status().ok()) << p.message;
  EXPECT_TRUE(p.support_dofs.empty());
  const double f1 = first_elastic_hz(), w1 = kTwoPi * f1, a = 0.01 * w1, b = 0.01 / w1;
  rd::ModalInterfaceOptions o = options(32.0 * f1);
  o.rayleigh_mass = a;
  o.rayleigh_stiffness = b;
  const rd::ModalInterfaceResult r = rd::build_modal_interface(clamped, p, l.load, l.outputs, o);
  std::printf("[          ] clamped: %s\n", r.brief().c_str());
  const hb::InterfaceModel& m = r.model;
  EXPECT_EQ(m.validate(), "");
  EXPECT_EQ(m.rigid_modes, 0);
  EXPECT_GT(r.modes.frequencies_hz[0], 10.0);
  // The far-end output sits on a clamped DOF.
  EXPECT_EQ(m.outputs[1].modal.norm(), 0.0);
  EXPECT_EQ(m.outputs[1].load_residual0, 0.0);
  for (double ratio : {0.3, 1.1}) {
    const double Omega = ratio * w1;
    const CVec u = direct_solve(clamped, p, Omega, a, b, l.load.force);
    const Prediction pr = predict_load(m, Omega);
    const CVec g = l.G.cast<Complex>() * u;
    const Complex drive = l.outputs[0].functional.cast<Complex>().dot(u);
    const double e_gaps = (pr.gaps - g).norm() / g.norm(), e_drive = std::abs(pr.outputs[0] - drive) / std::abs(drive);
    std::printf("[          ]   Omega = %.1f w1: gaps %.2e, drive %.2e\n", ratio, e_gaps, e_drive);
    EXPECT_LT(e_gaps, 1e-5);
    EXPECT_LT(e_drive, 1e-5);
  }
}

// Full-field recovery (eq. T-33): the displacement of every DOF from the modal coordinates and the
// contact forces, against the direct complex solve of the full model, for the load shape and for
// interface forces, converging with the cutoff; and a node-pair merge leaves it unchanged.
namespace {

// Harmonic-1 coefficients (cos, sin) of the phasor U (u = Re(U e^{iΩt}) = a cos + b sin: a = Re U, b = −Im U).
Eigen::MatrixXd coefficients(const CVec& u) {
  Eigen::MatrixXd c(u.size(), 3);
  c.col(0).setZero();
  c.col(1) = u.real();
  c.col(2) = -u.imag();
  return c;
}

// η (3 × n_s: mean, cos, sin) of the kept modes for the modal force φᵀf (complex receptance).
Eigen::MatrixXd modal_coefficients(const hb::InterfaceModel& m, double Omega, const Eigen::VectorXd& modal_force) {
  CVec eta(m.num_modes());
  for (int j = 0; j < m.num_modes(); ++j)
    eta[j] = modal_force[j] / Complex(m.omega2[j] - Omega * Omega,
                                      Omega * (m.rayleigh_mass + m.rayleigh_stiffness * m.omega2[j]));
  return coefficients(eta).transpose();
}

}  // namespace

TEST(ModalInterface, FieldRecoveryMatchesTheDirectSolveAndConvergesWithTheCutoff) {
  const double f1 = first_elastic_hz(), w1 = kTwoPi * f1, Omega = 0.9 * w1;
  const double zeta = 0.01, a = zeta * w1, b = zeta / w1;
  const hb::FourierBasis basis(1, 8);
  Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(modal_lap().G.rows(), -1.0, 2.0).array().sin();
  q *= 1e3;  // interface forces A N (cos part)
  const Eigen::MatrixXd u_load = coefficients(direct_solve(Omega, a, b, modal_lap().load.force));
  const Eigen::MatrixXd u_force = coefficients(direct_solve(Omega, a, b, -(modal_lap().G.transpose() * q).eval()));
  std::vector<double> worst;
  for (double cutoff : {4.0 * f1, 16.0 * f1, 64.0 * f1}) {
    rd::ModalInterfaceOptions o = options(cutoff);
    o.rayleigh_mass = a;
    o.rayleigh_stiffness = b;
    o.keep_field_recovery = true;
    const rd::ModalInterfaceResult r = rd::build_modal_interface(modal_lap().model, modal_lap().preload, modal_lap().load, modal_lap().outputs, o);
    const hb::InterfaceModel& m = r.model;
    ASSERT_FALSE(r.recovery.empty());
    ASSERT_EQ(r.recovery.points(), m.num_points());
    // the load F cos Ωt, no contact force
    const Eigen::MatrixXd u1 = r.recovery.displacement(basis, Omega, modal_coefficients(m, Omega, m.load_modal),
                                                       Eigen::MatrixXd::Zero(3, 3 * m.num_points()),
                                                       Eigen::Vector3d(0.0, 1.0, 0.0));
    // the interface force q cos Ωt (A N), no load
    Eigen::MatrixXd an = Eigen::MatrixXd::Zero(3, 3 * m.num_points());
    an.row(1) = q.transpose();
    const Eigen::MatrixXd u2 = r.recovery.displacement(basis, Omega, modal_coefficients(m, Omega, -(m.gap_shapes.transpose() * q).eval()),
                                                       an, {});
    const double e1 = (u1 - u_load).norm() / u_load.norm(), e2 = (u2 - u_force).norm() / u_force.norm();
    std::printf("[          ] cutoff %2.0f x f1 (%d kept modes): full field vs direct solve: load %.2e, interface "
                "forces %.2e\n", cutoff / f1, m.num_modes(), e1, e2);
    worst.push_back(std::max(e1, e2));
    // a merge of the coincident points (exact, T-31) gives the same field for the same forces
    const rd::ContactPatchResult merged = rd::merge_contact_patches(m, modal_lap().model, {.size = 0.0});
    const rd::FieldRecovery fm = r.recovery.merged(merged.patch_of_point, merged.point_weights, merged.patches);
    Eigen::MatrixXd an_c = Eigen::MatrixXd::Zero(3, 3 * merged.patches);
    for (int c = 0; c < merged.patches; ++c) an_c.row(1).segment(3 * c, 3) << 1e3 * std::sin(c), 2e3, -5e2 * c;
    Eigen::MatrixXd an_f = Eigen::MatrixXd::Zero(3, 3 * m.num_points());  // A_p N_p = ω_p A_c N_c
    for (int p = 0; p < m.num_points(); ++p)
      an_f.row(1).segment(3 * p, 3) =
          merged.point_weights[static_cast<std::size_t>(p)] * an_c.row(1).segment(3 * merged.patch_of_point[static_cast<std::size_t>(p)], 3);
    const Eigen::MatrixXd eta0 = Eigen::MatrixXd::Zero(3, m.num_modes());
    const Eigen::MatrixXd uf = r.recovery.displacement(basis, Omega, eta0, an_f, {});
    const Eigen::MatrixXd uc = fm.displacement(basis, Omega, eta0, an_c, {});
    EXPECT_LT((uf - uc).norm(), 1e-12 * uf.norm());
  }
  EXPECT_LT(worst[1], 0.1 * worst[0]);
  EXPECT_LT(worst[2], 0.1 * worst[1]);
  EXPECT_LT(worst[2], 1e-3);
}
