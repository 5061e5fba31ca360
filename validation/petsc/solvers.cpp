// The PETSc path's solvers (fe/petsc_solvers.hpp) against the serial ones on the same matrices:
//   jointhb_validate_petsc_solvers [--ci] OUTPUT_PREFIX          (one process)
//   mpirun -np R jointhb_validate_petsc solvers [--ci] OUTPUT_PREFIX
// The matrices: K of a structured grid of 8-node brick elements (unit cube, E = 1, ν = 0.3, the
// library's own assembly of C3D8 on a box mesh) with its bottom face clamped, and its lumped-free
// consistent M. Checked, each against CHOLMOD / ARPACK on the same matrix:
//   1. SparseCholesky with the mumps backend, SPD mode, from the lower, the upper and both
//      triangles: X = K⁻¹B for 6 right-hand sides, relative difference and residual ‖KX − B‖/‖B‖;
//      then refactored with new values on the same pattern (K + M), again;
//   2. the general symmetric mode on K − σM with σ between eigenvalues: the inertia (negative
//      pivots) equals CHOLMOD LDLᵀ's count (Sylvester), and the solution agrees;
//   3. SPD mode on an indefinite matrix: factorize() throws one line (no NaN solution);
//   4. modal::compute_modes with eigen_solver = slepc vs arpack: 10 eigenvalues, relative;
//   5. the cg backend (no factor) with GAMG and with hypre: the residual reaches the tolerance, the
//      solution agrees with CHOLMOD's to the condition number times it, and GAMG with the
//      rigid-body modes as near-null space needs fewer iterations than without;
//   6. cg on the indefinite matrix: solve() throws one line;
//   7. SLEPc with CG/GAMG inner solves vs ARPACK, on the clamped brick and on the free-free one
//      (whose six rigid-body modes are deflated: fe/petsc_solvers.cpp, rigid_subspace).
// Writes OUTPUT_PREFIX_solvers.csv (check, value, bound); exits 1 when a bound is exceeded.
#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/fe/petsc_solvers.hpp"
#include "jointhb/fe/rigid_body_modes.hpp"
#include "jointhb/fe/sparse_cholesky.hpp"
#include "jointhb/modal/modes.hpp"
#include "study_arguments.hpp"

namespace jointhb_study_petsc_solvers {
namespace {

using namespace jointhb;
using SpMat = Eigen::SparseMatrix<double>;

struct Check {
  std::string name;
  double value = 0.0;
  double bound = 0.0;
  [[nodiscard]] bool ok() const { return std::isfinite(value) && value <= bound; }
};

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).norm() / b.norm(); }

}  // namespace

int run(int argc, char** argv) {
  fe::petsc::Session session(&argc, &argv);
  if (session.rank() > 0) {
    session.serve();
    return 0;
  }
  const auto args = validation_study::parse_arguments(argc, argv);
  if (!args.ok) return 2;
  // ---- the matrices: a clamped brick of C3D8I elements (SI units of steel) ----------------------
  fe::BoxOptions box;
  box.size = Eigen::Vector3d(0.1, 0.04, 0.02);
  box.divisions = args.ci ? std::array<int, 3>{10, 4, 3} : std::array<int, 3>{30, 12, 8};
  const fe::Mesh mesh = fe::box_mesh(box);
  fe::Material steel;
  steel.youngs_modulus = 210e9;
  steel.poissons_ratio = 0.3;
  steel.density = 7800.0;
  const fe::StructuralMatrices full = fe::assemble(mesh, {steel});
  fe::FixedNodes bottom;
  for (int i = 0; i < mesh.num_nodes(); ++i)
    if (mesh.coordinates(2, i) == 0.0) bottom.nodes.push_back(i);
  const fe::DofMap dofs = fe::DofMap::from_fixed_nodes(mesh.num_nodes(), {bottom});
  const SpMat K = dofs.restrict(full.stiffness);
  const SpMat M = dofs.restrict(full.mass);
  const Eigen::Index n = K.rows();
  Eigen::MatrixXd B(n, 6);
  for (Eigen::Index j = 0; j < B.cols(); ++j)
    for (Eigen::Index i = 0; i < n; ++i) B(i, j) = std::sin(0.37 * static_cast<double>(i + 1) * static_cast<double>(j + 1));
  std::printf("petsc solvers: n = %ld free DOFs, nnz(K) = %ld, %d rank(s)\n", static_cast<long>(n),
              static_cast<long>(K.nonZeros()), session.size());

  std::vector<Check> checks;
  const auto cholmod = [](const SpMat& A, fe::SparseCholesky::Options o) {
    fe::SparseCholesky f(o);
    f.compute(A);
    return f;
  };
  // ---- 1. SPD mode from each triangle, then new values on the same pattern ----------------------
  using Tri = fe::SparseCholesky::Options::Triangle;
  const fe::SparseCholesky reference = cholmod(K, {});
  const Eigen::MatrixXd x_ref = reference.solve(B);
  const SpMat lower = K.triangularView<Eigen::Lower>(), upper = K.triangularView<Eigen::Upper>();
  const struct { const char* name; const SpMat* a; Tri triangle; } inputs[] = {
      {"lower", &lower, Tri::lower}, {"upper", &upper, Tri::upper}, {"full", &K, Tri::lower}};
  for (const auto& in : inputs) {
    fe::SparseCholesky::Options o;
    o.triangle = in.triangle;
    o.backend = fe::LinearSolver::mumps;
    fe::SparseCholesky f(o);
    f.compute(*in.a);
    const Eigen::MatrixXd x = f.solve(B);
    checks.push_back({fmt::format("spd {} triangle: |X - X_cholmod| / |X_cholmod|", in.name), relative(x, x_ref), 1e-10});
    checks.push_back({fmt::format("spd {} triangle: |K X - B| / |B|", in.name), (K * x - B).norm() / B.norm(), 1e-12});
    if (in.triangle == Tri::lower && in.a == &K) {
      const SpMat shifted = K + M * 1e9;  // same pattern (the element blocks), new values
      f.factorize(shifted);
      const Eigen::MatrixXd y = f.solve(B);
      const Eigen::MatrixXd y_ref = cholmod(shifted, {}).solve(B);
      checks.push_back({"spd refactorised with new values: |X - X_cholmod| / |X_cholmod|", relative(y, y_ref), 1e-10});
      Eigen::VectorXd single(n);
      f.solve_into(B.col(2), single);
      checks.push_back({"spd solve_into one column: |x - X_col| / |X_col|", relative(single, y.col(2)), 1e-14});
    }
  }
  // ---- 2. general symmetric mode: inertia of K − σM with σ between eigenvalues ------------------
  modal::ModalOptions mo;
  mo.count = 10;
  mo.shift = -1.0;
  const modal::ModalResult arpack = modal::compute_modes(K, M, mo);
  if (arpack.eigenvalues.size() < 10) {
    std::fprintf(stderr, "ARPACK reference failed: %s\n", arpack.message.c_str());
    return 1;
  }
  const double sigma = 0.5 * (arpack.eigenvalues(4) + arpack.eigenvalues(5));
  const SpMat indefinite = K - sigma * M;
  fe::SparseCholesky::Options ldlt;
  ldlt.method = fe::SparseCholesky::Options::Method::simplicial_ldlt;
  const fe::SparseCholesky ldlt_ref = cholmod(indefinite, ldlt);
  ldlt.backend = fe::LinearSolver::mumps;
  const fe::SparseCholesky ldlt_mumps = cholmod(indefinite, ldlt);
  checks.push_back({fmt::format("indefinite: |negative pivots - 5| (MUMPS {}, CHOLMOD {})", ldlt_mumps.negative_pivots(),
                                ldlt_ref.negative_pivots()),
                    std::abs(static_cast<double>(ldlt_mumps.negative_pivots()) - 5.0) +
                        std::abs(static_cast<double>(ldlt_ref.negative_pivots()) - 5.0),
                    0.0});
  checks.push_back({"indefinite: |X - X_cholmod| / |X_cholmod|", relative(ldlt_mumps.solve(B), ldlt_ref.solve(B)), 1e-8});
  // ---- 3. SPD mode on the indefinite matrix: one line, no solution ------------------------------
  {
    fe::SparseCholesky::Options o;
    o.backend = fe::LinearSolver::mumps;
    fe::SparseCholesky f(o);
    std::string message;
    try {
      f.compute(indefinite);
    } catch (const std::runtime_error& e) {
      message = e.what();
    }
    std::printf("spd mode on K - sigma M: %s\n", message.c_str());
    checks.push_back({"spd mode on an indefinite matrix throws one line (0 = yes)",
                      message.empty() || message.find('\n') != std::string::npos || f.factorized() ? 1.0 : 0.0, 0.0});
  }
  // ---- 4. SLEPc Krylov–Schur vs ARPACK --------------------------------------------------------
  mo.eigen_solver = modal::ModalOptions::EigenSolver::slepc;
  const modal::ModalResult slepc = modal::compute_modes(K, M, mo);
  double worst = slepc.eigenvalues.size() == 10 ? 0.0 : 1.0;
  for (Eigen::Index j = 0; j < std::min<Eigen::Index>(10, slepc.eigenvalues.size()); ++j)
    worst = std::max(worst, std::abs(slepc.eigenvalues(j) / arpack.eigenvalues(j) - 1.0));
  checks.push_back({fmt::format("slepc: 10 eigenvalues vs ARPACK, max relative ({})", slepc.message.empty() ? "converged" : slepc.message), worst, 1e-10});
  double mac = 1.0;  // |φ_sᵀ M φ_a| of mass-normalised shapes: 1 for the same (simple) mode
  for (Eigen::Index j = 0; j < std::min<Eigen::Index>(10, slepc.shapes.cols()); ++j)
    mac = std::min(mac, std::abs(slepc.shapes.col(j).dot(M * arpack.shapes.col(j))));
  checks.push_back({"slepc: 1 - min |phi_slepc^T M phi_arpack|", 1.0 - mac, 1e-8});
  checks.push_back({"slepc: max backward error", slepc.backward_errors.size() ? slepc.backward_errors.maxCoeff() : 1.0, 1e-12});

  // ---- 5. the cg backend ---------------------------------------------------------------------------
  const Eigen::MatrixXd rigid = fe::rigid_body_modes(mesh, dofs);
  long gamg_iterations[2] = {0, 0};
  for (const bool hypre : {false, true}) {
    for (const bool near_null : {true, false}) {
      if (hypre && !near_null) continue;
      fe::SparseCholesky::Options o;
      o.backend = fe::LinearSolver::cg;
      o.iterative.preconditioner = hypre ? fe::IterativeSettings::Preconditioner::hypre
                                         : fe::IterativeSettings::Preconditioner::gamg;
      if (near_null) o.iterative.near_null_space = rigid;
      fe::SparseCholesky f(o);
      f.compute(K);
      const Eigen::MatrixXd x = f.solve(B);
      const std::string name = hypre ? "cg/hypre" : near_null ? "cg/gamg" : "cg/gamg without near-null space";
      std::printf("%s: %s\n", name.c_str(), f.statistics().brief().c_str());
      double worst_residual = 0.0;
      for (Eigen::Index j = 0; j < B.cols(); ++j)
        worst_residual = std::max(worst_residual, (K * x.col(j) - B.col(j)).norm() / B.col(j).norm());
      checks.push_back({fmt::format("{}: max_j |K x_j - b_j| / |b_j| (tolerance 1e-10)", name), worst_residual, 1e-10});
      checks.push_back({fmt::format("{}: |X - X_cholmod| / |X_cholmod|", name), relative(x, x_ref), 1e-6});
      if (!hypre) gamg_iterations[near_null ? 0 : 1] = f.statistics().iterations;
    }
  }
  checks.push_back({fmt::format("cg/gamg: iterations with the rigid-body modes / without ({} / {})", gamg_iterations[0],
                                gamg_iterations[1]),
                    static_cast<double>(gamg_iterations[0]) / static_cast<double>(std::max(1L, gamg_iterations[1])), 0.9});
  // ---- 6. cg on the indefinite matrix: one line, no solution -------------------------------------
  {
    fe::SparseCholesky::Options o;
    o.backend = fe::LinearSolver::cg;
    o.iterative.near_null_space = rigid;
    fe::SparseCholesky f(o);
    std::string message;
    try {
      f.compute(indefinite);
      (void)f.solve(B);
    } catch (const std::runtime_error& e) {
      message = e.what();
    }
    std::printf("cg on K - sigma M: %s\n", message.c_str());
    checks.push_back({"cg on an indefinite matrix throws one line (0 = yes)",
                      message.empty() || message.find('\n') != std::string::npos ? 1.0 : 0.0, 0.0});
  }
  // ---- 7. SLEPc with CG/GAMG inner solves, clamped and free-free ------------------------------------
  const auto iterative_modes = [&](const SpMat& k, const SpMat& m, const Eigen::MatrixXd& near_null, int count,
                                   double reference_shift, const char* name) {
    modal::ModalOptions o;
    o.count = count;
    o.shift = reference_shift;
    const modal::ModalResult a = modal::compute_modes(k, m, o);
    o.shift = -1.0;
    o.eigen_solver = modal::ModalOptions::EigenSolver::slepc;
    o.linear_solver = fe::LinearSolver::cg;
    o.iterative.near_null_space = near_null;
    const modal::ModalResult c = modal::compute_modes(k, m, o);
    std::printf("%s: %s; %s\n", name, c.message.empty() ? "converged" : c.message.c_str(), c.factor.brief().c_str());
    double worst_value = c.eigenvalues.size() == count ? 0.0 : 1.0;
    const Eigen::Index first_elastic = a.eigenvalues(0) < 1.0 ? 6 : 0;  // rigid: at round-off, compared below
    for (Eigen::Index j = first_elastic; j < std::min<Eigen::Index>(count, c.eigenvalues.size()); ++j)
      worst_value = std::max(worst_value, std::abs(c.eigenvalues(j) / a.eigenvalues(j) - 1.0));
    checks.push_back({fmt::format("{}: elastic eigenvalues vs ARPACK, max relative", name), worst_value, 1e-9});
    checks.push_back({fmt::format("{}: max backward error", name), c.backward_errors.size() ? c.backward_errors.maxCoeff() : 1.0, 1e-11});
    if (first_elastic > 0) {
      // |λ| of the rigid modes against the first elastic one: ARPACK's and ours both at round-off.
      const double rigid_scale = c.eigenvalues.head(6).cwiseAbs().maxCoeff() / a.eigenvalues(6);
      checks.push_back({fmt::format("{}: max |lambda_rigid| / lambda_7", name), rigid_scale, 1e-8});
    }
  };
  iterative_modes(K, M, rigid, 10, -1.0, "slepc + cg/gamg, clamped");
  // The free-free reference at σ = −1e6 (λ₇ ≈ 3e9): ARPACK at σ = −1 has backward errors of ~1e-7 on
  // the elastic pairs here (inverse iteration dominated by the rigid modes' 1/|σ|), 2e-6 in λ.
  iterative_modes(full.stiffness, full.mass, fe::rigid_body_modes(mesh), 12, -1e6, "slepc + cg/gamg, free-free (6 deflated)");

  // ---- report -----------------------------------------------------------------------------------
  std::ofstream csv(args.prefix + "_solvers.csv");
  csv << "check,value,bound,ok\n";
  int failed = 0;
  for (const Check& c : checks) {
    csv << '"' << c.name << "\"," << fmt::format("{:.3e},{:g},{}", c.value, c.bound, c.ok() ? 1 : 0) << '\n';
    std::printf("%s %-80s %.3e (bound %g)\n", c.ok() ? "ok  " : "FAIL", c.name.c_str(), c.value, c.bound);
    failed += c.ok() ? 0 : 1;
  }
  return failed == 0 ? 0 : 1;
}

}  // namespace jointhb_study_petsc_solvers
