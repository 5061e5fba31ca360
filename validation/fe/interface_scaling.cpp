// Description: cost of harmonic balance of the preloaded bolted lap (validation/fe/lap_case.hpp)
// in modal/interface form at ≈100, 400 and 1600 contact points and H = 1, 3, 7: time per Newton
// iteration split into AFT, Jacobian (dense assembly or matrix-free products) and linear solve,
// time per damping curve (the first elastic mode from its linear limit to a `drop` frequency
// drop, as validation/fe/lap_damping), memory, and the error reached:
//
//   agreement     the Newton–Krylov solves of the bordered systems — GMRES on the dense
//                 Jacobian preconditioned by a lagged LU ("dense Krylov"), and GMRES on
//                 matrix-free products preconditioned by the harmonic block-Jacobi inverse
//                 (T-32c, "matrix-free") — against the dense LU per iteration (dense_lu) where
//                 that is run, else matrix-free against dense Krylov: largest relative
//                 difference of the unknowns over the leading points the curves share;
//   product       the matrix-free Jacobian-vector product (InterfaceBalance::apply_jacobian)
//                 against the dense Jacobian times the same vector, where the matrix fits;
//   residual      ‖R‖_∞ of the last point (EPMC residual, rows in units of the modal amplitude).
//
// Per-iteration figures are measured at one state of the curve (the linear mode shape at
// q = 10^probe_log10_q, in microslip), each call repeated until ≥ 0.2 s: AFT = evaluate without
// the Jacobian; AFT+blocks = with the point blocks B_p only; dense assembly = evaluate with the
// dense matrix minus AFT+blocks; product = one apply_jacobian; LU = one LAPACK dgetrf of the
// U × U Jacobian (only up to `lu_limit` unknowns). A configuration whose damping curve is not run
// (the dense matrix above `dense_limit` unknowns, or the predicted time above `budget`) is
// reported with the measured per-iteration costs and the reason, never with an invented time.
//
//   interface_scaling [--ci] [--only LABEL] [--budget SECONDS] [--matrix-free-only]
//                     [--preconditioner point_local|harmonic_blocks] [--refresh every_jacobian|on_failure]
//                     [--double-products] OUTPUT_PREFIX
// The last three choose the matrix-free curve's solver (defaults: the library's), to pair the
// solver before issue 16 (harmonic_blocks, on_failure, double products) with today's.
// --ci: the ≈100-point mesh at H = 1 only, all three solvers (ctest, ~10–20 s), bounds:
// agreement < 1e-8, product < 1e-12 of Σ|J||v|, the curves reach the drop. --only: one configuration (label
// P<points>_H<h>, one per process for the peak memory: interface_scaling.sh). --matrix-free-only:
// only the matrix-free curve and its per-iteration figures (no dense Jacobian, LU or dense
// curves; e.g. to re-measure a curve after a change outside the linear solvers). Tables:
// PREFIX_table.csv (one row per configuration), PREFIX_backbone_<label>.csv.

#include <fmt/format.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "../../src/support/lapack_lu.hpp"
#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/modal_interface.hpp"
#include "lap_case.hpp"
#include "lap_interface.hpp"

// The study is one function of the multi-call program jointhb_validate_fe (CMakeLists.txt).
namespace jointhb_study_fe_interface_scaling {

namespace {

using namespace jointhb;
using Clock = std::chrono::steady_clock;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// Mean wall time of f() over ≥ min_seconds (at least one call).
template <class F>
double time_call(F&& f, double min_seconds = 0.2) {
  const auto t = Clock::now();
  int calls = 0;
  do {
    f();
    ++calls;
  } while (since(t) < min_seconds);
  return since(t) / calls;
}

struct Mesh {
  int nx, ny;  // nz = 1; points = 4 · (0.4 nx) · ny (nodal integration per overlap face corner)
};

using Built = validation::LapInterface;

Built build(const Mesh& mesh) { return validation::lap_interface(mesh.nx, mesh.ny); }

struct Limits {
  double dense_limit = 9000;     // unknowns: dense Jacobian and LU (8U² bytes each)
  double lu_limit = 9000;        // unknowns: time one LU
  double dense_run_limit = 4000; // unknowns: also run the dense_lu reference curve
  double budget = 400.0;         // s: predicted damping-curve time above which it is not run
  bool matrix_free_only = false; // --matrix-free-only: no dense Jacobian, dense Krylov or dense LU
  // --preconditioner point_local|harmonic_blocks, --refresh every_jacobian|on_failure (matrix-free curve)
  hb::InterfacePreconditioner preconditioner = hb::InterfacePreconditioner::point_local;
  continuation::PreconditionerRefresh refresh = continuation::PreconditionerRefresh::every_jacobian;
  bool mixed_precision = true;  // --double-products: GMRES products in double precision only
  double krylov_tolerance = 0.0;  // --krylov-tolerance T: GMRES relative residual (0: the library's)
};
Limits g_limits;  // the command line's solver choices, read by trace()

struct Row {
  std::string label;
  int points = 0, harmonics = 0, modes = 0;
  long unknowns = 0;
  double build_s = 0, aft_s = 0, blocks_s = 0, assembly_s = -1, product_s = 0, lu_s = -1,
         product_error = -1, dense_gib = 0;
  // damping curve (Newton–Krylov); -1: not run
  int curve_points = -1, newton = -1, factorisations = -1, gmres = -1;
  double curve_s = -1, curve_aft_s = -1, curve_assembly_s = -1, curve_solve_s = -1, drop = -1,
         residual = -1;
  // dense_lu reference curve
  double dense_curve_s = -1, agreement = -1;
  int dense_factorisations = -1;
  // matrix-free curve (harmonic block-Jacobi preconditioner)
  int mf_points = -1, mf_newton = -1, mf_preconditioners = -1, mf_gmres = -1;
  double mf_s = -1, mf_aft_s = -1, mf_products_s = -1, mf_preconditioner_s = -1, mf_solve_s = -1,
         mf_drop = -1, mf_residual = -1, mf_agreement = -1, harmonic_lu_s = -1;
  double rss_mib = 0;
  std::string note;
};

// Largest relative difference of the unknowns over the leading points of two curves with the
// same parameters (the paths are identical while the step sequence is); `common` counts them.
double agreement(const continuation::InterfaceBackbone& a, const continuation::InterfaceBackbone& b,
                 std::size_t& common) {
  double worst = 0.0;
  common = 0;
  for (; common < std::min(a.points.size(), b.points.size()); ++common) {
    const auto& p = a.points[common];
    const auto& q = b.points[common];
    if (std::abs(p.state.amplitude / q.state.amplitude - 1.0) > 1e-9) break;
    worst = std::max(worst, (p.unknowns - q.unknowns).lpNorm<Eigen::Infinity>() / p.unknowns.lpNorm<Eigen::Infinity>());
  }
  return worst;
}

struct Curve {
  continuation::InterfaceBackbone backbone;
  double seconds = 0, drop = 0, residual = 0;
};

Curve trace(const hb::InterfaceModel& model, int harmonics, double f1, double drop,
            continuation::LinearSolver solver, bool matrix_free, const std::string& csv_path) {
  continuation::InterfaceBackboneOptions bo;
  bo.mode.mode = 1;
  bo.mode.balance.harmonics = harmonics;
  bo.mode.balance.time_samples = harmonics == 1 ? 32 : 64;
  bo.log10_amplitude_start = -9.0;
  bo.log10_amplitude_end = -4.0;
  bo.continuation.max_points = 200;
  bo.continuation.linear_solver = solver;
  bo.matrix_free = matrix_free;
  bo.preconditioner = g_limits.preconditioner;
  bo.continuation.preconditioner_refresh = g_limits.refresh;
  bo.mixed_precision = g_limits.mixed_precision;
  if (g_limits.krylov_tolerance > 0.0) bo.continuation.krylov_tolerance = g_limits.krylov_tolerance;
  std::FILE* csv = csv_path.empty() ? nullptr : std::fopen(csv_path.c_str(), "w");
  if (csv) std::fprintf(csv, "q,frequency_hz,damping_ratio,slipping_points,iterations\n");
  Curve c;
  const auto t0 = Clock::now();
  c.backbone = continuation::trace_interface_backbone(model, bo, [&](const continuation::InterfaceBackbonePoint& pt) {
    const double f = pt.state.omega / kTwoPi;
    if (csv) std::fprintf(csv, "%.10e,%.12g,%.10e,%d,%d\n", pt.state.amplitude, f, pt.state.damping_ratio,
                          pt.state.slipping_points, pt.iterations);
    return f >= (1.0 - drop) * f1;
  });
  c.seconds = since(t0);
  if (csv) std::fclose(csv);
  if (!c.backbone.points.empty()) {
    const auto& last = c.backbone.points.back();
    c.drop = 1.0 - last.state.omega / kTwoPi / f1;
    hb::InterfaceModeOptions mode = bo.mode;
    mode.balance.dense_jacobian = false;
    const hb::InterfaceModeResidual epmc(model, mode);
    hb::InterfaceModeResidual::Evaluation e;
    epmc.evaluate(last.unknowns, std::log10(last.state.amplitude), false, e);
    c.residual = e.residual.lpNorm<Eigen::Infinity>();
  }
  return c;
}

Row run(const Mesh& mesh, const Built& built, int harmonics, const Limits& lim, double drop,
        const std::string& prefix, bool reference) {
  Row r;
  const hb::InterfaceModel& model = built.model;
  r.points = model.num_points();
  r.harmonics = harmonics;
  r.label = fmt::format("P{}_H{}", r.points, harmonics);
  r.modes = model.num_modes();
  r.build_s = built.seconds;
  (void)mesh;
  hb::InterfaceBalanceOptions bopt;
  bopt.harmonics = harmonics;
  bopt.time_samples = harmonics == 1 ? 32 : 64;
  bopt.dense_jacobian = false;
  const hb::InterfaceBalance free(model, bopt);
  const int m = free.basis().size();
  r.unknowns = free.unknowns();
  const double U = static_cast<double>(r.unknowns);
  r.dense_gib = 8.0 * U * U / (1024.0 * 1024.0 * 1024.0);

  // Probe state: the linear mode at q = 10^-6.5 (microslip on the coarse lap), Ω = ω_1, ξ = c_1.
  const hb::InterfaceModeResidual epmc(model, {.mode = 1, .balance = bopt});
  const Eigen::VectorXd start = epmc.linear_start();
  const double q = std::pow(10.0, -6.5);
  const Eigen::VectorXd y = q * start.head(free.unknowns());
  const double omega = start[free.unknowns()], xi = start[free.unknowns() + 1];
  hb::InterfaceBalanceEvaluation e;
  r.aft_s = time_call([&] { free.evaluate(y, omega, xi, Eigen::VectorXd(), false, e); });
  r.blocks_s = time_call([&] { free.evaluate(y, omega, xi, Eigen::VectorXd(), true, e); });
  Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(free.unknowns(), -1.0, 1.0);
  Eigen::VectorXd product;
  r.product_s = time_call([&] { product = free.apply_jacobian(e, omega, xi, v); });
  std::fprintf(stderr, "  %s: U = %ld (m = %d), AFT %.3g s, AFT+blocks %.3g s, product %.3g s\n", r.label.c_str(),
               r.unknowns, m, r.aft_s, r.blocks_s, r.product_s);
  if (U <= lim.dense_limit && !lim.matrix_free_only) {
    bopt.dense_jacobian = true;
    const hb::InterfaceBalance dense(model, bopt);
    hb::InterfaceBalanceEvaluation ed;
    const double with_matrix = time_call([&] { dense.evaluate(y, omega, xi, Eigen::VectorXd(), true, ed); });
    r.assembly_s = std::max(with_matrix - r.blocks_s, 0.0);
    const Eigen::VectorXd jv = ed.jacobian * v;
    const Eigen::VectorXd bound = ed.jacobian.cwiseAbs() * v.cwiseAbs();
    r.product_error = ((jv - product).cwiseAbs().array() / bound.array().max(1e-300)).maxCoeff();
    if (U <= lim.lu_limit) {
      const auto t = Clock::now();
      const support::LapackLu lu(ed.jacobian);
      r.lu_s = since(t);
      (void)lu;
    }
    std::fprintf(stderr, "  %s: dense assembly %.3g s, LU %.3g s, product error %.2e\n", r.label.c_str(),
                 r.assembly_s, r.lu_s, r.product_error);
  }

  // The preconditioner of the matrix-free curve (--preconditioner): one build.
  {
    const auto t = Clock::now();
    const auto pc = free.preconditioner(e, omega, xi, lim.preconditioner);
    r.harmonic_lu_s = since(t);
    std::fprintf(stderr, "  %s: %s preconditioner %.3g s\n", r.label.c_str(),
                 lim.preconditioner == hb::InterfacePreconditioner::point_local ? "point-local" : "harmonic",
                 r.harmonic_lu_s);
  }

  continuation::InterfaceBackbone reference_curve;  // dense_lu, else dense Krylov
  std::string reference_name;
  // Dense Jacobian, lagged LU: predicted with ~100 Newton iterations and ~10 factorisations.
  const double predicted_dense =
      100.0 * (r.blocks_s + std::max(r.assembly_s, 0.0) + 20.0 * r.product_s) + 10.0 * std::max(r.lu_s, 0.0);
  if (lim.matrix_free_only) {
    r.note += "dense Krylov not run: --matrix-free-only;";
  } else if (U > lim.dense_limit) {
    r.note += fmt::format("dense Krylov not run: {:.1f} GiB per copy of the {}x{} matrix;", r.dense_gib, r.unknowns,
                          r.unknowns);
  } else if (predicted_dense > lim.budget) {
    r.note += fmt::format("dense Krylov not run: predicted {:.0f} s (100 Newton x (AFT+Jacobian {:.2g} s + 20 "
                          "products) + 10 LU x {:.2g} s) > budget {:.0f} s;",
                          predicted_dense, r.blocks_s + r.assembly_s, r.lu_s, lim.budget);
  } else {
    const Curve k = trace(model, harmonics, built.f1, drop, continuation::LinearSolver::newton_krylov, false,
                          fmt::format("{}_backbone_{}.csv", prefix, r.label));
    const auto& b = k.backbone;
    r.curve_points = static_cast<int>(b.points.size());
    r.newton = b.newton_iterations;
    r.factorisations = b.timings.factorisations;
    r.gmres = b.timings.krylov_iterations;
    r.curve_s = k.seconds;
    r.curve_aft_s = b.timings.aft;
    r.curve_assembly_s = b.timings.assembly;
    r.curve_solve_s = b.timings.linear_solve;
    r.drop = k.drop;
    r.residual = k.residual;
    if (r.drop < drop) r.note += "dense Krylov stopped before the drop: " + b.message + ";";
    std::fprintf(stderr, "  %s: newton_krylov curve %.1f s, %d points, %d Newton, %d LU, %d GMRES, drop %.4f\n",
                 r.label.c_str(), r.curve_s, r.curve_points, r.newton, r.factorisations, r.gmres, r.drop);
    reference_curve = b;
    reference_name = "krylov";
    if (reference && U <= lim.dense_run_limit) {
      const Curve d = trace(model, harmonics, built.f1, drop, continuation::LinearSolver::dense_lu, false, "");
      r.dense_curve_s = d.seconds;
      r.dense_factorisations = d.backbone.timings.factorisations;
      std::size_t common = 0;
      r.agreement = agreement(d.backbone, b, common);
      if (common < std::max(d.backbone.points.size(), b.points.size()))
        r.note += fmt::format("dense/krylov paths part after {} of {}/{} points;", common, d.backbone.points.size(),
                              b.points.size());
      std::fprintf(stderr, "  %s: dense_lu curve %.1f s (%d LU), agreement %.2e over %zu points\n", r.label.c_str(),
                   r.dense_curve_s, r.dense_factorisations, r.agreement, common);
      reference_curve = d.backbone;
      reference_name = "dense";
    }
  }
  // Matrix-free: predicted with ~100 Newton iterations x 30 GMRES steps and 5 preconditioner builds.
  const double predicted_free = 100.0 * (r.blocks_s + 30.0 * r.product_s) + 5.0 * r.harmonic_lu_s;
  if (predicted_free > lim.budget) {
    r.note += fmt::format("matrix-free not run: predicted {:.0f} s (100 Newton x (AFT+blocks {:.2g} s + 30 products "
                          "x {:.2g} s) + 5 x preconditioner {:.2g} s) > budget {:.0f} s;",
                          predicted_free, r.blocks_s, r.product_s, r.harmonic_lu_s, lim.budget);
  } else {
    const Curve f = trace(model, harmonics, built.f1, drop, continuation::LinearSolver::newton_krylov, true,
                          fmt::format("{}_backbone_{}_matrix_free.csv", prefix, r.label));
    const auto& b = f.backbone;
    r.mf_points = static_cast<int>(b.points.size());
    r.mf_newton = b.newton_iterations;
    r.mf_preconditioners = b.timings.factorisations;
    r.mf_gmres = b.timings.krylov_iterations;
    r.mf_s = f.seconds;
    r.mf_aft_s = b.timings.aft;
    r.mf_products_s = b.timings.products;
    r.mf_preconditioner_s = b.timings.preconditioner;
    r.mf_solve_s = b.timings.linear_solve;
    r.mf_drop = f.drop;
    r.mf_residual = f.residual;
    if (r.mf_drop < drop) r.note += "matrix-free stopped before the drop: " + b.message + ";";
    std::fprintf(stderr, "  %s: matrix-free curve %.1f s, %d points, %d Newton, %d preconditioners, %d GMRES, drop %.4f\n",
                 r.label.c_str(), r.mf_s, r.mf_points, r.mf_newton, r.mf_preconditioners, r.mf_gmres, r.mf_drop);
    if (!reference_curve.points.empty()) {
      std::size_t common = 0;
      r.mf_agreement = agreement(reference_curve, b, common);
      if (common < std::max(reference_curve.points.size(), b.points.size()))
        r.note += fmt::format("{}/matrix-free paths part after {} of {}/{} points;", reference_name, common,
                              reference_curve.points.size(), b.points.size());
      std::fprintf(stderr, "  %s: matrix-free vs %s: %.2e over %zu points\n", r.label.c_str(), reference_name.c_str(),
                   r.mf_agreement, common);
    }
  }
  r.rss_mib = peak_rss_mib();
  return r;
}

}  // namespace

int run(int argc, char** argv) {
  bool ci = false;
  std::string only, prefix;
  Limits lim;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--ci") ci = true;
    else if (a == "--only" && i + 1 < argc) only = argv[++i];
    else if (a == "--budget" && i + 1 < argc) lim.budget = std::atof(argv[++i]);
    else if (a == "--matrix-free-only") lim.matrix_free_only = true;
    else if (a == "--double-products") lim.mixed_precision = false;
    else if (a == "--krylov-tolerance" && i + 1 < argc) lim.krylov_tolerance = std::atof(argv[++i]);
    else if (a == "--preconditioner" && i + 1 < argc) {
      const std::string v = argv[++i];
      if (v != "harmonic_blocks" && v != "point_local") prefix.clear(), i = argc;
      lim.preconditioner = v == "harmonic_blocks" ? hb::InterfacePreconditioner::harmonic_blocks
                                                  : hb::InterfacePreconditioner::point_local;
    } else if (a == "--refresh" && i + 1 < argc) {
      const std::string v = argv[++i];
      if (v != "on_failure" && v != "every_jacobian") prefix.clear(), i = argc;
      lim.refresh = v == "on_failure" ? continuation::PreconditionerRefresh::on_failure
                                      : continuation::PreconditionerRefresh::every_jacobian;
    }
    else if (prefix.empty() && !a.empty() && a[0] != '-') prefix = a;
    else prefix.clear(), i = argc;
  }
  g_limits = lim;
  if (prefix.empty()) {
    std::fprintf(stderr,
                 "usage: %s [--ci] [--only P<points>_H<h>] [--budget SECONDS] [--matrix-free-only] "
                 "[--preconditioner point_local|harmonic_blocks] [--refresh every_jacobian|on_failure] [--double-products] "
                 "OUTPUT_PREFIX\n",
                 argv[0]);
    return 2;
  }
  const double drop = 0.03;
  // P6400 (100 x 40 per plate: R0 and R1 5.9 GB in double, 2.9 GB more in single) only on request.
  const std::vector<Mesh> meshes =
      ci ? std::vector<Mesh>{{15, 4}} : std::vector<Mesh>{{15, 4}, {25, 10}, {50, 20}, {100, 40}};
  const std::vector<int> orders = ci ? std::vector<int>{1} : std::vector<int>{1, 3, 7};
  std::vector<Row> rows;
  bool ok = true;
  for (const Mesh& mesh : meshes) {
    const int points = 4 * (2 * mesh.nx / 5) * mesh.ny;
    bool wanted = only.empty() && points <= 1600;
    for (int h : orders) wanted = wanted || only == fmt::format("P{}_H{}", points, h);
    if (!wanted) continue;
    const Built built = build(mesh);
    std::fprintf(stderr, "mesh %dx%dx1: %d points, %d kept modes, f1 %.3f Hz, built in %.1f s\n", mesh.nx, mesh.ny,
                 built.model.num_points(), built.model.num_modes(), built.f1, built.seconds);
    for (int h : orders) {
      const std::string label = fmt::format("P{}_H{}", built.model.num_points(), h);
      if (!only.empty() && only != label) continue;
      rows.push_back(run(mesh, built, h, lim, drop, prefix, true));
      const Row& r = rows.back();
      if (r.product_error >= 0) ok = ok && r.product_error < 1e-12;
      if (r.agreement >= 0) ok = ok && r.agreement < 1e-8;
      if (r.mf_agreement >= 0) ok = ok && r.mf_agreement < 1e-8;
      if (ci) ok = ok && r.curve_points > 0 && r.drop >= drop && r.agreement >= 0 && r.mf_drop >= drop && r.mf_agreement >= 0;
    }
  }
  std::FILE* t = std::fopen((prefix + "_table.csv").c_str(), "w");
  if (t)
    std::fprintf(t, "label,points,harmonics,kept_modes,unknowns,dense_GiB,build_s,aft_s,aft_blocks_s,dense_assembly_s,"
                    "product_s,lu_s,product_error,curve_points,newton,factorisations,gmres,curve_s,curve_aft_s,"
                    "curve_assembly_s,curve_solve_s,drop,last_residual,dense_curve_s,dense_factorisations,"
                    "agreement,preconditioner_s,mf_points,mf_newton,mf_preconditioners,mf_gmres,mf_s,mf_aft_s,"
                    "mf_products_s,mf_preconditioner_s,mf_solve_s,mf_drop,mf_last_residual,mf_agreement,peak_rss_MiB,note\n");
  for (const Row& r : rows) {
    std::printf("%-10s U=%-6ld (%d modes) AFT %.3g s, AFT+B %.3g s, assembly %.3g s, product %.3g s, LU %.3g s | "
                "curve %.1f s: %d pts %d Newton %d LU %d GMRES (AFT %.1f, asm %.1f, solve %.1f) drop %.3f res %.1e | "
                "dense curve %.1f s %d LU, agreement %.1e | matrix-free %.1f s: %d Newton %d PC (%.2g s each) %d GMRES "
                "(AFT %.1f, products %.1f, PC %.1f, solve %.1f) drop %.3f res %.1e agreement %.1e | RSS %.0f MiB %s\n",
                r.label.c_str(), r.unknowns, r.modes, r.aft_s, r.blocks_s, r.assembly_s, r.product_s, r.lu_s, r.curve_s,
                r.curve_points, r.newton, r.factorisations, r.gmres, r.curve_aft_s, r.curve_assembly_s, r.curve_solve_s,
                r.drop, r.residual, r.dense_curve_s, r.dense_factorisations, r.agreement, r.mf_s, r.mf_newton,
                r.mf_preconditioners, r.harmonic_lu_s, r.mf_gmres, r.mf_aft_s, r.mf_products_s, r.mf_preconditioner_s,
                r.mf_solve_s, r.mf_drop, r.mf_residual, r.mf_agreement, r.rss_mib, r.note.c_str());
    if (t)
      std::fprintf(t, "%s,%d,%d,%d,%ld,%.4f,%.2f,%.5g,%.5g,%.5g,%.5g,%.5g,%.3e,%d,%d,%d,%d,%.3f,%.3f,%.3f,%.3f,%.5f,%.3e,"
                      "%.3f,%d,%.3e,%.5g,%d,%d,%d,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.5f,%.3e,%.3e,%.0f,\"%s\"\n",
                   r.label.c_str(), r.points, r.harmonics, r.modes, r.unknowns, r.dense_gib, r.build_s, r.aft_s,
                   r.blocks_s, r.assembly_s, r.product_s, r.lu_s, r.product_error, r.curve_points, r.newton,
                   r.factorisations, r.gmres, r.curve_s, r.curve_aft_s, r.curve_assembly_s, r.curve_solve_s, r.drop,
                   r.residual, r.dense_curve_s, r.dense_factorisations, r.agreement, r.harmonic_lu_s, r.mf_points,
                   r.mf_newton, r.mf_preconditioners, r.mf_gmres, r.mf_s, r.mf_aft_s, r.mf_products_s,
                   r.mf_preconditioner_s, r.mf_solve_s, r.mf_drop, r.mf_residual, r.mf_agreement, r.rss_mib,
                   r.note.c_str());
  }
  if (t) std::fclose(t);
  std::printf("%s\n", ok ? "interface_scaling: all bounds met" : "interface_scaling: a bound was exceeded");
  return ok ? 0 : 1;
}

}  // namespace jointhb_study_fe_interface_scaling
