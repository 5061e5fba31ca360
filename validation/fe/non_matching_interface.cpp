// A block cut in two, meshed independently on each side of the cut and joined by a stiff
// non-matching interface (segment-to-segment / mortar integration), against the same block with
// matching meshes and the monolithic block.
//
// Description:
//   Aluminium block (E = 70 GPa, ν = 0.33, ρ = 2700 kg/m³), L × b × t = 0.1 × 0.02 × 0.02 m, C3D8I.
//   Two cuts, each joining part a (bottom surface) to part b (top surface) by a zero-thickness
//   interface of constant stiffness C = diag(k, k, k) per unit area, k = κ E / h_a with κ = 1e6
//   (block_cut: the penalty's own error is below 1e-6 there), K = K_s + Gᵀ A C G:
//     length:    plane x = L/2; a: (5n/2) × n × n, b: (5m/2) × m × m cells;
//     thickness: plane z = t/2; a: 5n × n × n/2,   b: 5m × m × m/2 cells;
//   with m = 3n/2 (non-matching: the interface nodes of b fall between those of a) and, as
//   references, m = n and n = m (matching meshes, the interface built as coincident node pairs).
//   Interface rules: nodal (dual mortar at a's nodes) and gauss (points on every overlap segment).
//   Quantities: the first 6 elastic free-free frequencies (modal::compute_modes), and the tip
//   compliances of the cantilever (x = 0 clamped) under a uniform axial and a uniform transverse
//   (z) traction on x = L. Reference: the monolithic block, Richardson-extrapolated from
//   5N × N × N and 10N × 2N × 2N cells with rate 2 (N = 8; --ci: N = 4).
//   Errors e = |q / q_ref − 1| (max over the 6 frequencies).
//
// Bounds (exit code 1 when one is exceeded), nodal rule (dual mortar):
//   * "within the discretisation error": for every cut, n and quantity, the non-matching
//     error is at most 1.1 × the larger of the two matching errors (sides both at n, both at m)
//     plus 1e-6 (reference and penalty error);
//   * observed rate log2(e(n)/e(2n)) of the non-matching frequency error in [1.6, 2.4] (C3D8I:
//     h² convergence, Strang & Fix §6.3);
//   * rigid-body frequencies below 5 Hz and elastic backward errors below 1e-11 (both rules).
// The gauss rule is reported, not bounded: with a stiff interface its constraints at every
// quadrature point of every segment outnumber the interface DOFs and over-constrain
// ("lock") the finer side — the ratio non-matching / larger matching error printed for it
// measures by how much. It is meant for compliant contact laws; ties and stiff joints between
// non-matching meshes take the nodal rule.
// --ci: n = 2, 4 (length) and n = 4 (thickness; no rate), N = 4.
//
// Sample runs:
//   build/validation/fe/jointhb_validate_fe_non_matching_interface validation/fe/results/non_matching_interface

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
namespace jointhb_study_fe_non_matching_interface {

namespace {

using namespace jointhb::fe;
using jointhb::modal::ModalOptions;
using jointhb::modal::ModalResult;

constexpr double kLength = 0.1, kWidth = 0.02, kThickness = 0.02;
constexpr double kKappa = 1e6;
constexpr int kRigid = 6, kElastic = 6;
const Material kAluminium{"aluminium", 70e9, 0.33, 2700.0};

enum class Cut { length, thickness };
const char* cut_name(Cut c) { return c == Cut::length ? "length" : "thickness"; }

struct Quantities {
  std::vector<double> frequencies;  // elastic [Hz]
  double axial = 0.0, bending = 0.0;  // work-conjugate tip displacements [m]
  double max_rigid_hz = 0.0, max_backward = 0.0;
  int dofs = 0, points = 0;
};

// Uniform traction on the faces of `surfaces` (rectangles), resultant `load` along `axis`.
Eigen::VectorXd tip_load(const Mesh& mesh, const std::vector<std::string>& surfaces, int axis, double load) {
  const double area = kWidth * kThickness;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(mesh.num_dofs());
  for (const std::string& surface : surfaces)
    for (const Face& face : mesh.surfaces.at(surface)) {
      const std::vector<int> nodes = face_nodes(mesh, face);
      const Eigen::Vector3d d1 = mesh.coordinates.col(nodes[1]) - mesh.coordinates.col(nodes[0]);
      const Eigen::Vector3d d3 = mesh.coordinates.col(nodes[3]) - mesh.coordinates.col(nodes[0]);
      const double face_area = d1.cross(d3).norm();
      for (int k = 0; k < 4; ++k) f(3 * nodes[static_cast<std::size_t>(k)] + axis) += 0.25 * load * face_area / area;
    }
  return f;
}

Quantities respond(const Mesh& mesh, const Eigen::SparseMatrix<double>& stiffness,
                   const Eigen::SparseMatrix<double>& mass, const std::vector<std::string>& root,
                   const std::vector<std::string>& tip) {
  Quantities q;
  q.dofs = mesh.num_dofs();
  ModalOptions options;
  options.count = kRigid + kElastic;
  options.shift = -std::pow(2.0 * std::numbers::pi * 100.0, 2);
  options.tolerance = 1e-13;
  const ModalResult modes = jointhb::modal::compute_modes(stiffness, mass, options);
  if (modes.termination != jointhb::Termination::converged) throw std::runtime_error("compute_modes: " + modes.message);
  for (int j = 0; j < kRigid; ++j) q.max_rigid_hz = std::max(q.max_rigid_hz, std::abs(modes.frequencies_hz(j)));
  for (int j = kRigid; j < kRigid + kElastic; ++j) {
    q.frequencies.push_back(modes.frequencies_hz(j));
    q.max_backward = std::max(q.max_backward, modes.backward_errors(j));
  }
  std::vector<FixedNodes> fixed;
  for (const std::string& set : root) fixed.push_back({mesh.node_sets.at(set)});
  const DofMap dofs = DofMap::from_fixed_nodes(mesh.num_nodes(), fixed);
  SparseCholesky solver;
  solver.compute(dofs.restrict(stiffness));
  Eigen::MatrixXd rhs(dofs.num_free(), 2);
  rhs.col(0) = dofs.restrict(tip_load(mesh, tip, 0, 1000.0));
  rhs.col(1) = dofs.restrict(tip_load(mesh, tip, 2, 100.0));
  const Eigen::MatrixXd u = solver.solve(rhs);
  q.axial = rhs.col(0).dot(u.col(0)) / 1000.0;
  q.bending = rhs.col(1).dot(u.col(1)) / 100.0;
  return q;
}

Quantities monolithic(int n) {
  BoxOptions o;
  o.part = "mono";
  o.size = Eigen::Vector3d(kLength, kWidth, kThickness);
  o.divisions = {5 * n, n, n};
  const Mesh mesh = box_mesh(o);
  const StructuralMatrices m = assemble(mesh, {kAluminium});
  return respond(mesh, m.stiffness, m.mass, {"mono.xmin"}, {"mono.xmax"});
}

// Part a with n cells across the cut, part b with m, joined by the interface.
Quantities split(Cut cut, int n, int m, InterfaceIntegration integration) {
  BoxOptions a, b;
  a.part = "a";
  b.part = "b";
  std::vector<std::string> root, tip;
  InterfaceOptions io;
  io.name = "cut";
  io.integration = integration;
  io.meshes = n == m ? InterfaceMeshes::matching : InterfaceMeshes::non_matching;
  if (cut == Cut::length) {
    a.size = b.size = Eigen::Vector3d(0.5 * kLength, kWidth, kThickness);
    a.divisions = {5 * n / 2, n, n};
    b.divisions = {(5 * m + 1) / 2, m, m};
    b.origin = Eigen::Vector3d(0.5 * kLength, 0.0, 0.0);
    root = {"a.xmin"};
    tip = {"b.xmax"};
    io.bottom_surface = "a.xmax";
    io.top_surface = "b.xmin";
  } else {
    a.size = b.size = Eigen::Vector3d(kLength, kWidth, 0.5 * kThickness);
    a.divisions = {5 * n, n, n / 2};
    b.divisions = {5 * m, m, m / 2};
    b.origin = Eigen::Vector3d(0.0, 0.0, 0.5 * kThickness);
    root = {"a.xmin", "b.xmin"};
    tip = {"a.xmax", "b.xmax"};
    io.bottom_surface = "a.zmax";
    io.top_surface = "b.zmin";
  }
  Mesh mesh = box_mesh(a);
  append(mesh, box_mesh(b));
  const StructuralMatrices matrices = assemble(mesh, {kAluminium, kAluminium});
  const Interface interface = build_interface(mesh, io);
  const double k = kKappa * kAluminium.youngs_modulus / (kThickness / n);
  const std::vector<Eigen::Matrix3d> tangents(interface.points.size(), Eigen::Matrix3d::Identity() * k);
  std::vector<Eigen::Triplet<double>> triplets;
  add_interface_stiffness(interface, tangents, triplets);
  Eigen::SparseMatrix<double> k_interface(mesh.num_dofs(), mesh.num_dofs());
  k_interface.setFromTriplets(triplets.begin(), triplets.end());
  Quantities q = respond(mesh, matrices.stiffness + k_interface, matrices.mass, root, tip);
  q.points = interface.num_points();
  return q;
}

struct Errors {
  double frequency = 0.0, axial = 0.0, bending = 0.0;
};

Errors errors(const Quantities& q, const Quantities& ref) {
  Errors e;
  for (std::size_t j = 0; j < q.frequencies.size(); ++j)
    e.frequency = std::max(e.frequency, std::abs(q.frequencies[j] / ref.frequencies[j] - 1.0));
  e.axial = std::abs(q.axial / ref.axial - 1.0);
  e.bending = std::abs(q.bending / ref.bending - 1.0);
  return e;
}

}  // namespace

int run(int argc, char** argv) {
  const validation_study::Arguments args = validation_study::parse_arguments(argc, argv);
  if (!args.ok) return 2;
  const int big_n = args.ci ? 4 : 8;

  // Reference: Richardson extrapolation (rate 2) of the monolithic block from N and 2N.
  const Quantities coarse = monolithic(big_n), fine = monolithic(2 * big_n);
  Quantities ref = fine;
  for (std::size_t j = 0; j < ref.frequencies.size(); ++j)
    ref.frequencies[j] = fine.frequencies[j] + (fine.frequencies[j] - coarse.frequencies[j]) / 3.0;
  ref.axial = fine.axial + (fine.axial - coarse.axial) / 3.0;
  ref.bending = fine.bending + (fine.bending - coarse.bending) / 3.0;
  std::printf("reference: monolithic C3D8I %d and %d cells across (%d DOFs), Richardson; f [Hz]:", big_n,
              2 * big_n, fine.dofs);
  for (double f : ref.frequencies) std::printf(" %.4f", f);
  std::printf("\n  change fine vs extrapolated: frequency %.2e, axial %.2e, bending %.2e\n",
              errors(fine, ref).frequency, errors(fine, ref).axial, errors(fine, ref).bending);

  bool ok = true;
  auto check = [&](bool condition, const std::string& what) {
    if (!condition) {
      std::printf("BOUND EXCEEDED: %s\n", what.c_str());
      ok = false;
    }
  };
  std::ofstream table(args.prefix + "_errors.csv");
  table << "cut,integration,n,m,variant,dofs,interface_points,max_rel_freq_error,axial_rel_error,"
           "bending_rel_error,max_rigid_hz,max_backward_error\n";
  for (Cut cut : {Cut::length, Cut::thickness}) {
    std::vector<int> ns = cut == Cut::length ? std::vector<int>{2, 4, 8} : std::vector<int>{4, 8};
    if (args.ci) ns = cut == Cut::length ? std::vector<int>{2, 4} : std::vector<int>{4};
    for (InterfaceIntegration rule : {InterfaceIntegration::nodal, InterfaceIntegration::gauss}) {
      double previous = NAN;
      for (int n : ns) {
        const int m = 3 * n / 2;
        struct Variant {
          const char* name;
          int a, b;
        };
        Errors e[3];
        int v = 0;
        for (const Variant var : {Variant{"matching_n", n, n}, Variant{"non_matching", n, m}, Variant{"matching_m", m, m}}) {
          const Quantities q = split(cut, var.a, var.b, rule);
          e[v] = errors(q, ref);
          table << fmt::format("{},{},{},{},{},{},{},{:.6e},{:.6e},{:.6e},{:.3e},{:.3e}\n", cut_name(cut),
                               to_string(rule), var.a, var.b, var.name, q.dofs, q.points, e[v].frequency,
                               e[v].axial, e[v].bending, q.max_rigid_hz, q.max_backward);
          table.flush();
          check(q.max_rigid_hz < 5.0, fmt::format("{} {} {}: rigid-body mode at {:.3e} Hz", cut_name(cut),
                                                  to_string(rule), var.name, q.max_rigid_hz));
          check(q.max_backward < 1e-11, fmt::format("{} {} {}: backward error {:.3e}", cut_name(cut),
                                                    to_string(rule), var.name, q.max_backward));
          ++v;
        }
        std::printf("%-9s %-5s n=%2d m=%2d  freq %.3e [%.3e %.3e]  axial %.3e [%.3e %.3e]  bending %.3e "
                    "[%.3e %.3e]\n",
                    cut_name(cut), to_string(rule), n, m, e[1].frequency, e[0].frequency, e[2].frequency,
                    e[1].axial, e[0].axial, e[2].axial, e[1].bending, e[0].bending, e[2].bending);
        std::fflush(stdout);
        const auto within = [&](double Errors::*q, const char* name) {
          const double bound = 1.1 * std::max(e[0].*q, e[2].*q) + 1e-6;
          check(e[1].*q <= bound, fmt::format("{} {} n={}: non-matching {} error {:.3e} above {:.3e}", cut_name(cut),
                                              to_string(rule), n, name, e[1].*q, bound));
        };
        const double over = std::max({e[1].frequency / std::max(e[0].frequency, e[2].frequency),
                                      e[1].axial / std::max(e[0].axial, e[2].axial),
                                      e[1].bending / std::max(e[0].bending, e[2].bending)});
        std::printf("          non-matching error / larger matching error: %.3f (worst quantity)\n", over);
        if (rule == InterfaceIntegration::nodal) {
          within(&Errors::frequency, "frequency");
          within(&Errors::axial, "axial");
          within(&Errors::bending, "bending");
        }
        if (std::isfinite(previous)) {
          const double rate = std::log2(previous / e[1].frequency);
          std::printf("          observed rate of the non-matching frequency error: %.3f\n", rate);
          if (rule == InterfaceIntegration::nodal)
            check(rate >= 1.6 && rate <= 2.4, fmt::format("{} {}: rate {:.3f} outside [1.6, 2.4]", cut_name(cut),
                                                          to_string(rule), rate));
        }
        previous = e[1].frequency;
      }
    }
  }
  std::printf("%s\n", ok ? "all bounds met" : "BOUNDS EXCEEDED");
  return ok ? 0 : 1;
}

}  // namespace jointhb_study_fe_non_matching_interface
