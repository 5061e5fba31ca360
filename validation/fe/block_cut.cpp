// A monolithic block against the same block cut in two and joined by a very stiff interface.
//
// Description:
//   Aluminium block (E = 70 GPa, ν = 0.33, ρ = 2700 kg/m³), L × b × t = 0.1 × 0.02 × 0.02 m,
//   C3D8I elements, 5n × n × n divisions (element size h = t/n). Meshes:
//     (a) "mono": one box (fe::box_mesh);
//     (b) "cut": two boxes appended with fe::append (the nodes of the cut plane are duplicated,
//         not merged), joined by a zero-thickness interface (fe::build_interface) of constant
//         diagonal stiffness C = diag(k_t, k_t, k_n) per unit area, k_t = k_n = k, at every point:
//         K_cut = K_s + Gᵀ A C G (fe::add_interface_stiffness); nodal or Gauss (2×2) integration.
//         Two cuts: "length" (two L/2 halves side by side, plane x = L/2, interface a.xmax/b.xmin)
//         and "thickness" (two t/2 layers stacked, neutral plane z = t/2, a.zmax/b.zmin).
//   The node positions of (b) are those of (a), so (b) → (a) as k → ∞ (a penalty tie). The
//   interface is a compliance 1/k in series with the solid: every error should fall as 1/k until
//   round-off (‖K‖ and K's condition number grow with k) stops it.
//   Sweep: k = κ E/h with κ = 1e-2 … 1e10 (decades); for each cut, integration and k:
//     * free-free modes (modal::compute_modes, 12 modes, shift −(2π·100 Hz)², tolerance 1e-13):
//       the 6 rigid-body modes and the first 6 elastic modes; max relative frequency difference
//       cut/mono of the elastic modes, residuals and backward errors from the ModalResult;
//     * static cantilever (face x = 0 clamped, DofMap::from_fixed_nodes, fe::SparseCholesky):
//       uniform traction on the face x = L, axial (P = 1 kN along x) and bending (P = 100 N along
//       z); the work-conjugate tip displacement w = fᵀu / P, relative difference cut/mono, and a
//       first-order prediction of it (see below).
//   Observed rate: least-squares slope of log|error| against log k over κ = 1 … 1e4. Round-off
//   onset: the first κ > 1e4 where the error is more than 10 % off the 1/k line through κ = 1e4.
//
// Bounds (exit code 1 when one is exceeded; measured values of the full run, n = 8, in brackets):
//   * −slope in [0.9, 1.1] for the frequencies, the axial and the bending displacement, both cuts
//     and integrations [0.973 … 1.000];
//   * |error| < 1e-5 at κ = 1e5 (before round-off for both cuts) [≤ 2.8e-7; --ci ≤ 1.2e-6], and
//     for the length cut also < 1e-6 at κ = 1e6 [≤ 2.8e-8; --ci ≤ 1.2e-7];
//   * static error / first-order prediction at κ = 1e3: length cut within 1e-3 (axial) and 2e-2
//     (bending) of 1 [1.00000; 1.0013 nodal, 0.9999 Gauss]; thickness cut, bending, within 3e-2
//     (--ci: 0.15, the 3D shear distribution across the width is poorly resolved by 2 elements)
//     [0.990 nodal, 0.998 Gauss; --ci 1.019, 1.096];
//   * κ ≤ 1e6: rigid-body modes |f| < 5 Hz [≤ 1.4 Hz], elastic backward errors < 1e-11
//     [≤ 2.6e-12];
//   * κ ≤ 1e4 (below the round-off onset): the cut block is not stiffer than the monolithic one
//     (frequency and displacement ratios, to 1e-9).
// --ci: n = 2 (n_x = 10; 297 / 324 / 396 DOFs) and κ ≤ 1e8, the same bounds; under a second.
//
// Sample runs:
//   build/validation/fe/jointhb_validate_fe_block_cut validation/fe/results/block_cut   (~60 s)

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/fe/interface.hpp"
#include "jointhb/fe/sparse_cholesky.hpp"
#include "jointhb/modal/modes.hpp"
#include "study_arguments.hpp"

// The study is one function of the multi-call program jointhb_validate_fe (CMakeLists.txt).
namespace jointhb_study_fe_block_cut {

namespace {

using namespace jointhb::fe;
using jointhb::modal::ModalOptions;
using jointhb::modal::ModalResult;

constexpr double kLength = 0.1, kWidth = 0.02, kThickness = 0.02;
constexpr double kAxialLoad = 1000.0, kBendingLoad = 100.0;
constexpr int kRigid = 6, kElastic = 6;
const Material kAluminium{"aluminium", 70e9, 0.33, 2700.0};

struct Model {
  Mesh mesh;
  StructuralMatrices matrices;
  std::vector<std::string> tip;   // surfaces x = L
  std::vector<std::string> root;  // node sets x = 0
};

// Where the block is cut: at mid-length (plane x = L/2, interface a.xmax / b.xmin) or at
// mid-thickness (plane z = t/2, interface a.zmax / b.zmin).
enum class Cut { length, thickness };
const char* cut_name(Cut c) { return c == Cut::length ? "length" : "thickness"; }
std::string label(Cut c, InterfaceIntegration i) {
  return fmt::format("{}/{}", cut_name(c), to_string(i));
}

Model monolithic(int n) {
  BoxOptions o;
  o.part = "mono";
  o.size = Eigen::Vector3d(kLength, kWidth, kThickness);
  o.divisions = {5 * n, n, n};
  Model m{box_mesh(o), {}, {"mono.xmax"}, {"mono.xmin"}};
  m.matrices = assemble(m.mesh, {kAluminium});
  return m;
}

Model cut(int n, Cut c) {
  BoxOptions a;
  a.part = "a";
  BoxOptions b = a;
  b.part = "b";
  Model m;
  if (c == Cut::length) {
    a.size = Eigen::Vector3d(0.5 * kLength, kWidth, kThickness);
    a.divisions = {5 * n / 2, n, n};
    b.origin = Eigen::Vector3d(0.5 * kLength, 0.0, 0.0);
    m.tip = {"b.xmax"};
    m.root = {"a.xmin"};
  } else {
    a.size = Eigen::Vector3d(kLength, kWidth, 0.5 * kThickness);
    a.divisions = {5 * n, n, n / 2};
    b.origin = Eigen::Vector3d(0.0, 0.0, 0.5 * kThickness);
    m.tip = {"a.xmax", "b.xmax"};
    m.root = {"a.xmin", "b.xmin"};
  }
  b.size = a.size;
  b.divisions = a.divisions;
  m.mesh = box_mesh(a);
  append(m.mesh, box_mesh(b));
  m.matrices = assemble(m.mesh, {kAluminium, kAluminium});
  return m;
}

// Uniform traction on the tip surface, resultant P along `axis` (consistent for bilinear faces of
// a rectangle: a quarter of each face's force at each corner).
Eigen::VectorXd tip_load(const Mesh& mesh, const std::vector<std::string>& surfaces, int axis,
                         double load) {
  const double area = kWidth * kThickness;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(mesh.num_dofs());
  for (const std::string& surface : surfaces)
    for (const Face& face : mesh.surfaces.at(surface)) {
      const std::vector<int> nodes = face_nodes(mesh, face);
      const Eigen::Vector3d d1 = mesh.coordinates.col(nodes[1]) - mesh.coordinates.col(nodes[0]);
      const Eigen::Vector3d d3 = mesh.coordinates.col(nodes[3]) - mesh.coordinates.col(nodes[0]);
      const double face_area = d1.cross(d3).norm();
      for (int k = 0; k < 4; ++k)
        f(3 * nodes[static_cast<std::size_t>(k)] + axis) += 0.25 * load * face_area / area;
    }
  return f;
}

struct Response {
  ModalResult modes;
  double axial = 0.0, bending = 0.0;  // work-conjugate tip displacements [m]
};

Response respond(const Model& model, const Eigen::SparseMatrix<double>& stiffness) {
  Response r;
  ModalOptions options;
  options.count = kRigid + kElastic;
  options.shift = -std::pow(2.0 * std::numbers::pi * 100.0, 2);
  options.tolerance = 1e-13;
  r.modes = jointhb::modal::compute_modes(stiffness, model.matrices.mass, options);
  if (r.modes.termination != jointhb::Termination::converged)
    throw std::runtime_error("compute_modes: " + r.modes.message);
  std::vector<FixedNodes> fixed;
  for (const std::string& set : model.root) fixed.push_back({model.mesh.node_sets.at(set)});
  const DofMap dofs = DofMap::from_fixed_nodes(model.mesh.num_nodes(), fixed);
  SparseCholesky solver;
  solver.compute(dofs.restrict(stiffness));
  const Eigen::VectorXd fa = tip_load(model.mesh, model.tip, 0, kAxialLoad);
  const Eigen::VectorXd fb = tip_load(model.mesh, model.tip, 2, kBendingLoad);
  Eigen::MatrixXd rhs(dofs.num_free(), 2);
  rhs.col(0) = dofs.restrict(fa);
  rhs.col(1) = dofs.restrict(fb);
  const Eigen::MatrixXd u = solver.solve(rhs);
  r.axial = rhs.col(0).dot(u.col(0)) / kAxialLoad;
  r.bending = rhs.col(1).dot(u.col(1)) / kBendingLoad;
  return r;
}

struct Run {
  Cut cut{};
  InterfaceIntegration integration{};
  double kappa = 0.0, k = 0.0;
  int points = 0;
  Response response;
  double freq_error = 0.0;       // max_j |f_j^cut / f_j^mono − 1| over the elastic modes
  double freq_signed_min = 0.0;  // min_j (f_j^mono / f_j^cut − 1): < 0 when a cut mode is stiffer
  double axial_error = 0.0, bending_error = 0.0;  // w^cut / w^mono − 1
  double max_rigid_hz = 0.0, max_residual = 0.0, max_backward = 0.0;
};

double slope(const std::vector<const Run*>& runs, double Run::*error) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const Run* r : runs) {
    const double x = std::log10(r->kappa), y = std::log10(std::abs(r->*error));
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double n = static_cast<double>(runs.size());
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

int run(int argc, char** argv) {
  const validation_study::Arguments args = validation_study::parse_arguments(argc, argv);
  if (!args.ok) return 2;
  const int n = args.ci ? 2 : 8;
  const double h = kThickness / n;
  const int max_decade = args.ci ? 8 : 10;

  const Model mono = monolithic(n);
  const Response reference = respond(mono, mono.matrices.stiffness);
  std::printf("block %.3g x %.3g x %.3g m, C3D8I %d x %d x %d (h = %.4g m), %d DOFs\n", kLength,
              kWidth, kThickness, 5 * n, n, n, h, mono.mesh.num_dofs());
  std::printf("monolithic: %s\n  elastic modes [Hz]:", reference.modes.brief().c_str());
  for (int j = kRigid; j < kRigid + kElastic; ++j)
    std::printf(" %.4f", reference.modes.frequencies_hz(j));
  std::printf("\n  tip displacement: axial %.9e m, bending %.9e m\n", reference.axial,
              reference.bending);

  std::vector<Run> runs;
  const std::vector<Cut> cuts = {Cut::length, Cut::thickness};
  const std::vector<InterfaceIntegration> integrations = {InterfaceIntegration::nodal,
                                                          InterfaceIntegration::gauss};
  for (Cut cut_at : cuts) {
    const Model split = cut(n, cut_at);
    std::printf("cut at mid-%s: %d DOFs\n", cut_name(cut_at), split.mesh.num_dofs());
    for (InterfaceIntegration integration : integrations) {
      const Interface interface =
          cut_at == Cut::length
              ? build_interface(split.mesh, {"cut", "a.xmax", "b.xmin", integration})
              : build_interface(split.mesh, {"cut", "a.zmax", "b.zmin", integration});
      for (int decade = -2; decade <= max_decade; ++decade) {
        Run run;
        run.cut = cut_at;
        run.integration = integration;
        run.kappa = std::pow(10.0, decade);
        run.k = run.kappa * kAluminium.youngs_modulus / h;
        run.points = interface.num_points();
        const Eigen::Matrix3d c = Eigen::Vector3d(run.k, run.k, run.k).asDiagonal();
        const std::vector<Eigen::Matrix3d> tangents(interface.points.size(), c);
        std::vector<Eigen::Triplet<double>> triplets;
        add_interface_stiffness(interface, tangents, triplets);
        Eigen::SparseMatrix<double> k_interface(split.mesh.num_dofs(), split.mesh.num_dofs());
        k_interface.setFromTriplets(triplets.begin(), triplets.end());
        const Eigen::SparseMatrix<double> stiffness = split.matrices.stiffness + k_interface;
        run.response = respond(split, stiffness);
        const ModalResult& m = run.response.modes;
        run.freq_signed_min = INFINITY;
        for (int j = 0; j < kRigid; ++j)
          run.max_rigid_hz = std::max(run.max_rigid_hz, std::abs(m.frequencies_hz(j)));
        for (int j = kRigid; j < kRigid + kElastic; ++j) {
          const double fm = reference.modes.frequencies_hz(j), fc = m.frequencies_hz(j);
          run.freq_error = std::max(run.freq_error, std::abs(fc / fm - 1.0));
          run.freq_signed_min = std::min(run.freq_signed_min, fm / fc - 1.0);
          run.max_residual = std::max(run.max_residual, m.residuals(j));
          run.max_backward = std::max(run.max_backward, m.backward_errors(j));
        }
        run.axial_error = run.response.axial / reference.axial - 1.0;
        run.bending_error = run.response.bending / reference.bending - 1.0;
        std::printf(
            "%-15s kh/E=%7.0e  df/f=%9.3e  dw/w axial %10.3e bending %10.3e  rigid<%7.1e Hz  "
            "res %8.1e  berr %8.1e\n",
            label(cut_at, integration).c_str(), run.kappa, run.freq_error, run.axial_error,
            run.bending_error, run.max_rigid_hz, run.max_residual, run.max_backward);
        std::fflush(stdout);
        runs.push_back(std::move(run));
      }
    }
  }

  bool ok = true;
  auto check = [&](bool condition, const std::string& what) {
    if (!condition) {
      std::printf("BOUND EXCEEDED: %s\n", what.c_str());
      ok = false;
    }
  };

  std::ofstream rates(args.prefix + "_rates.csv");
  rates << "cut,integration,quantity,slope_kappa_1_to_1e4,error_at_kappa_1e5,error_at_kappa_1e6,"
           "error_at_onset,"
           "roundoff_onset_kappa\n";
  for (Cut cut_at : cuts)
    for (InterfaceIntegration integration : integrations) {
      const std::string name = label(cut_at, integration);
      std::vector<const Run*> fit, all;
      for (const Run& r : runs) {
        if (r.cut != cut_at || r.integration != integration) continue;
        all.push_back(&r);
        if (r.kappa >= 1.0 && r.kappa <= 1e4) fit.push_back(&r);
      }
      const Run *at_1e5 = nullptr, *at_1e6 = nullptr;
      for (const Run* r : all) {
        if (r->kappa == 1e5) at_1e5 = r;
        if (r->kappa == 1e6) at_1e6 = r;
      }
      struct Quantity {
        const char* name;
        double Run::*error;
      };
      for (const Quantity q :
           {Quantity{"frequency", &Run::freq_error}, Quantity{"axial", &Run::axial_error},
            Quantity{"bending", &Run::bending_error}}) {
        const double s = slope(fit, q.error);
        // Round-off onset: the first κ > 1e4 at which the error departs by more than 10 % from the
        // 1/k line through the κ = 1e4 point.
        const Run* at_1e4 = nullptr;
        for (const Run* r : all)
          if (r->kappa == 1e4) at_1e4 = r;
        double onset = INFINITY, onset_error = std::nan("");
        for (const Run* r : all)
          if (r->kappa > 1e4 && !std::isfinite(onset) &&
              std::abs((r->*q.error) / (at_1e4->*q.error * 1e4 / r->kappa) - 1.0) > 0.1) {
            onset = r->kappa;
            onset_error = r->*q.error;
          }
        const double e5 = std::abs(at_1e5->*q.error), e6 = std::abs(at_1e6->*q.error);
        std::printf(
            "%-15s %-9s: slope %.4f over kh/E = 1..1e4; |error| %.2e / %.2e at kh/E = "
            "1e5 / 1e6; round-off onset (>10 %% off 1/k) at kh/E = %.0e (error %.2e)\n",
            name.c_str(), q.name, s, e5, e6, onset, onset_error);
        rates << fmt::format("{},{},{},{:.5f},{:.3e},{:.3e},{:.3e},{:.0e}\n", cut_name(cut_at),
                             to_string(integration), q.name, s, e5, e6, onset_error, onset);
        check(-s >= 0.9 && -s <= 1.1,
              fmt::format("{} {}: slope {:.4f} not in [-1.1, -0.9]", name, q.name, s));
        check(e5 < 1e-5,
              fmt::format("{} {}: |error| {:.3e} at kh/E = 1e5 not below 1e-5", name, q.name, e5));
        if (cut_at == Cut::length)
          check(e6 < 1e-6, fmt::format("{} {}: |error| {:.3e} at kh/E = 1e6 not below 1e-6", name,
                                       q.name, e6));
      }
      // First-order prediction of the static errors (the interface's complementary energy
      // ∫ t·t/k dA / P under the monolithic block's tractions t on the cut plane, from beam
      // theory):
      //   length cut (x = L/2): axial Δw = P/(k A); bending Δw = P/k ((L/2)²/(c_q I) + (6/5)/A),
      //     c_q = 1 for Gauss (exact for the linear σ_xx), 1 + 2/n² for nodal integration (the
      //     trapezoidal rule on n intervals overestimates ∫z² dA by that factor: the nodal
      //     interface is stiffer in bending);
      //   thickness cut (neutral plane z = t/2): bending Δw = (3P/(2A))² b L / (k P) (the peak of
      //   the
      //     parabolic shear stress over the whole plane); axial: none (no traction in beam theory,
      //     only the end effects of the clamp), not checked.
      // Checked at kh/E = 1e3.
      {
        const Run* r3 = nullptr;
        for (const Run* r : all)
          if (r->kappa == 1e3) r3 = r;
        const double area = kWidth * kThickness, inertia = kWidth * std::pow(kThickness, 3) / 12.0;
        const double c_q = integration == InterfaceIntegration::gauss
                               ? 1.0
                               : 1.0 + 2.0 / static_cast<double>(n * n);
        const bool length = cut_at == Cut::length;
        const double axial = length ? kAxialLoad / (r3->k * area) / reference.axial : std::nan("");
        const double bending = length
                                   ? kBendingLoad / r3->k *
                                         (0.25 * kLength * kLength / (c_q * inertia) + 1.2 / area) /
                                         reference.bending
                                   : std::pow(1.5 * kBendingLoad / area, 2) * kWidth * kLength /
                                         (r3->k * kBendingLoad) / reference.bending;
        std::printf("%-15s kh/E = 1e3: axial error / prediction = %.5f, bending = %.5f\n",
                    name.c_str(), r3->axial_error / axial, r3->bending_error / bending);
        rates << fmt::format("{},{},axial_error_over_prediction_at_1e3,{:.5f},,,,\n",
                             cut_name(cut_at), to_string(integration), r3->axial_error / axial);
        rates << fmt::format("{},{},bending_error_over_prediction_at_1e3,{:.5f},,,,\n",
                             cut_name(cut_at), to_string(integration), r3->bending_error / bending);
        check((!length || std::abs(r3->axial_error / axial - 1.0) < 1e-3) &&
                  std::abs(r3->bending_error / bending - 1.0) <
                      (length ? 0.02 : (args.ci ? 0.15 : 0.03)),
              fmt::format("{}: static errors / first-order prediction = {:.4f}, {:.4f}", name,
                          r3->axial_error / axial, r3->bending_error / bending));
      }
      for (const Run* r : all) {
        if (r->kappa > 1e6) continue;
        const std::string where = fmt::format("{} kh/E = {:.0e}", name, r->kappa);
        check(r->max_rigid_hz < 5.0,
              fmt::format("{}: rigid-body mode at {:.3e} Hz", where, r->max_rigid_hz));
        check(r->max_backward < 1e-11,
              fmt::format("{}: elastic backward error {:.3e}", where, r->max_backward));
        check(r->kappa > 1e4 || (r->freq_signed_min > -1e-9 && r->axial_error > -1e-9 &&
                                 r->bending_error > -1e-9),
              fmt::format("{}: cut block stiffer than the monolithic one ({:.2e}, {:.2e}, {:.2e})",
                          where, r->freq_signed_min, r->axial_error, r->bending_error));
      }
    }

  std::ofstream table(args.prefix + "_sweep.csv");
  table << "cut,integration,interface_points,k_h_over_E,k_Pa_per_m,max_rel_freq_error";
  for (int j = 1; j <= kElastic; ++j) table << ",f" << j << "_cut_hz";
  table << ",axial_rel_error,bending_rel_error,max_rigid_hz,max_elastic_residual,"
           "max_elastic_backward_error\n";
  table << fmt::format("none,monolithic,0,inf,inf,0");
  for (int j = kRigid; j < kRigid + kElastic; ++j)
    table << fmt::format(",{:.10e}", reference.modes.frequencies_hz(j));
  table << fmt::format(",0,0,{:.3e},{:.3e},{:.3e}\n",
                       reference.modes.frequencies_hz.head(kRigid).cwiseAbs().maxCoeff(),
                       reference.modes.residuals.segment(kRigid, kElastic).maxCoeff(),
                       reference.modes.backward_errors.segment(kRigid, kElastic).maxCoeff());
  for (const Run& r : runs) {
    table << fmt::format("{},{},{},{:.0e},{:.6e},{:.6e}", cut_name(r.cut), to_string(r.integration),
                         r.points, r.kappa, r.k, r.freq_error);
    for (int j = kRigid; j < kRigid + kElastic; ++j)
      table << fmt::format(",{:.10e}", r.response.modes.frequencies_hz(j));
    table << fmt::format(",{:.6e},{:.6e},{:.3e},{:.3e},{:.3e}\n", r.axial_error, r.bending_error,
                         r.max_rigid_hz, r.max_residual, r.max_backward);
  }

  std::printf("%s\n", ok ? "all bounds met" : "BOUNDS EXCEEDED");
  return ok ? 0 : 1;
}

}  // namespace jointhb_study_fe_block_cut
