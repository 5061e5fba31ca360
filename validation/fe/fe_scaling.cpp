// Description: wall time and peak memory of the FE pipeline of `jointhb run` (assembly →
// preload Newton with CHOLMOD → 20 modes by ARPACK shift-invert) on the bolted lap joint of
// cases/05-bolted-lap scaled by mesh refinement, with the accuracy reached.
//
//   Geometry, material, contact law, bolts, load steps (4), tolerance (1e-9) and modes (20,
//   shift −(2π·10 Hz)²) are those of case 05; only the divisions change. Each plate has
//   10m × 3m × n_z C3D8I elements (element size 10/m mm in plane, 4/n_z mm through the
//   thickness; the overlap x ∈ [60, 100] mm always falls on element boundaries). DOFs =
//   2 · 3 (10m + 1)(3m + 1)(n_z + 1). --dofs N picks the refinement (m, n_z ≈ 0.4 m, i.e. nearly
//   cubic elements) whose DOF count is nearest N:
//     --dofs 10000  → m = 4,  n_z = 2:   9 594 DOFs (case 05 itself)
//     --dofs 100000 → m = 10, n_z = 4:  93 930 DOFs
//     --dofs 300000 → m = 15, n_z = 6: 291 732 DOFs
//   One size per process, so that the peak resident set (getrusage RUSAGE_SELF, ru_maxrss) is
//   that size's own; validation/fe/run_fe_scaling.sh runs the three sizes.
//
// What is timed (steady clock, wall time):
//   build    : parsing the case text, meshing, interfaces and bolt footprints (io::parse_fe_case)
//              plus fe::assemble (K_s, M);
//   preload  : preload::solve_preload, split into contact evaluation (residual and tangents of
//              every point, line-search trials included), Newton-matrix assembly and restriction,
//              and CHOLMOD (analyse once, one numeric factorisation + one solve per iteration);
//   modes    : restricting K_t and M to the free DOFs + modal::compute_modes (forming and
//              factoring K − σM, then ARPACK's Lanczos with its solves).
// Peak RSS is sampled after each stage (it is monotone, so the stage that raises it is visible).
// Also recorded: the BLAS library actually mapped into the process (/proc/self/maps), the
// thread-count variables and the 1-minute load average at start.
//
// Bounds (exit code 1 when one is exceeded), for every size and --ci:
//   * preload converged at every load step, final relative residual ≤ 1e-9 (the case tolerance);
//   * clamping force = Σ bolt preloads to 1e-8 relative; support reaction ≤ 1e-10 of the preload;
//   * 20 modes converged; the 6 rigid-body modes |f| < 1 Hz and the first elastic one > 100 Hz;
//   * normwise backward error of every mode ≤ 1e-10 (the ARPACK tolerance; measured ≤ 5e-12).
// --ci: m = 2, n_z = 2 (2 646 DOFs), a smoke run of the whole pipeline with the same bounds
// (ctest: validation.fe.fe_scaling); its times mean nothing.
//
// Tables: PREFIX_<dofs>.csv (one row: sizes, times, peak RSS, accuracy) and
// PREFIX_<dofs>_modes.csv (the 20 frequencies to 17 digits, residuals, backward errors: compare
// runs with different BLAS thread counts with them).
//
// Sample runs (see docs/performance.md §"Finite-element preload and modes" for the figures):
//   build/validation/fe/jointhb_validate_fe_fe_scaling /tmp/fe_scaling --dofs 100000
//   validation/fe/run_fe_scaling.sh build validation/fe/results/fe_scaling

#include <fmt/format.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "lap_case.hpp"
#include "study_arguments.hpp"

// The study is one function of the multi-call program jointhb_validate_fe (CMakeLists.txt).
namespace jointhb_study_fe_fe_scaling {

namespace {

using namespace jointhb;
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Peak resident set size of this process so far [MiB] (Linux reports ru_maxrss in KiB).
double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// The shared objects mapped into this process whose file name contains "blas" or "lapack"
// (e.g. .../blas/libblas.so.3.11.0 + .../lapack/liblapack.so.3.11.0, or
// .../openblas-pthread/libopenblasp-r0.3.21.so), i.e. the BLAS and LAPACK CHOLMOD actually calls;
// separated by '+'.
std::string loaded_blas() {
  std::ifstream maps("/proc/self/maps");
  std::string line, found;
  while (std::getline(maps, line)) {
    const auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    const std::string name = path.substr(path.rfind('/') + 1);
    if (name.find("blas") == std::string::npos && name.find("lapack") == std::string::npos) continue;
    if (found.find(path) == std::string::npos) found += (found.empty() ? "" : "+") + path;
  }
  return found.empty() ? "?" : found;
}

std::string environment(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr ? v : "unset";
}

double load_average() {
  std::ifstream f("/proc/loadavg");
  double one_minute = -1.0;
  f >> one_minute;
  return one_minute;
}

// The mesh refinement: each plate 10m × 3m × nz elements.
struct Refinement {
  int m = 4, nz = 2;
  [[nodiscard]] int nx() const { return 10 * m; }
  [[nodiscard]] int ny() const { return 3 * m; }
  [[nodiscard]] long dofs() const { return 2L * 3 * (nx() + 1) * (ny() + 1) * (nz + 1); }
};

Refinement nearest_refinement(long target) {
  Refinement best;
  for (int m = 1; m <= 60; ++m) {
    const Refinement r{m, std::max(1, static_cast<int>(std::lround(0.4 * m)))};
    if (std::labs(r.dofs() - target) < std::labs(best.dofs() - target)) best = r;
  }
  return best;
}

// cases/05-bolted-lap/case.yaml (lap_case.hpp) with the divisions of both plates replaced.
std::string lap_case(const Refinement& r) {
  validation::LapCaseOptions o;
  o.nx = r.nx(), o.ny = r.ny(), o.nz = r.nz;
  return validation::lap_case_yaml(o);
}

// Everything measured on one size; one CSV row.
struct Measurement {
  Refinement refinement;
  long dofs = 0, nodes = 0, elements = 0, interface_points = 0;
  double build_seconds = 0.0, rss_after_build = 0.0;
  preload::PreloadResult preload;
  std::vector<std::vector<double>> history;  // relative residual per load step and iteration
  double rss_after_preload = 0.0;
  modal::ModalResult modes;
  double modes_seconds = 0.0, rss_after_modes = 0.0;
  double total_seconds = 0.0;
  double clamping_error = 0.0;  // |Σ clamping force − Σ preloads| / Σ preloads
};

Measurement run(const Refinement& r, double reuse_ratio) {
  Measurement s;
  s.refinement = r;
  const auto start = Clock::now();
  // build: the case (mesh, interface, bolts) and the structural matrices
  const io::FeCase c = io::parse_fe_case(lap_case(r), "fe_scaling.yaml");
  const preload::PreloadModel model = io::preload_model(c);
  s.build_seconds = seconds_since(start);
  s.rss_after_build = peak_rss_mib();
  s.dofs = c.mesh.num_dofs();
  s.nodes = c.mesh.num_nodes();
  s.elements = c.mesh.num_elements();
  for (const auto& ci : c.interfaces) s.interface_points += ci.geometry.num_points();

  // preload: as `jointhb run` (src/cli/fe_run.cpp), recording the residual of every iteration
  preload::PreloadOptions options = c.preload;
  options.reuse_factor_ratio = reuse_ratio;
  // and printing it with the elapsed time to stderr (a long run shows its pace as it goes)
  const auto preload_start = Clock::now();
  options.progress = [&s, preload_start](int step, int iteration, double residual) {
    if (static_cast<int>(s.history.size()) < step) s.history.resize(static_cast<std::size_t>(step));
    s.history[static_cast<std::size_t>(step - 1)].push_back(residual);
    std::fprintf(stderr, "preload step %d iteration %d residual %.2e at %.1f s\n", step, iteration,
                 residual, seconds_since(preload_start));
  };
  s.preload = preload::solve_preload(model, options);
  s.rss_after_preload = peak_rss_mib();
  double preload_sum = 0.0, clamping = 0.0;
  for (const auto& b : c.bolts) preload_sum += b.preload;
  for (const auto& i : s.preload.interfaces) clamping += i.clamping_force;
  s.clamping_error = std::abs(clamping - preload_sum) / preload_sum;

  // modes about the preloaded state, free-free (no user constraints: every DOF is free)
  if (s.preload.status().ok()) {
    const auto t0 = Clock::now();
    const fe::DofMap dofs = fe::DofMap::from_fixed_nodes(c.mesh.num_nodes(), c.constraints);
    const Eigen::SparseMatrix<double> K = dofs.restrict(s.preload.dynamic_stiffness);
    const Eigen::SparseMatrix<double> M = dofs.restrict(model.structure.mass);
    s.modes = modal::compute_modes(K, M, *c.modes);
    s.modes_seconds = seconds_since(t0);
  }
  s.rss_after_modes = peak_rss_mib();
  s.total_seconds = seconds_since(start);
  return s;
}

constexpr int kRigid = 6;

double max_rigid_hz(const modal::ModalResult& m) {
  double worst = 0.0;
  for (Eigen::Index j = 0; j < std::min<Eigen::Index>(kRigid, m.frequencies_hz.size()); ++j)
    worst = std::max(worst, std::abs(m.frequencies_hz[j]));
  return worst;
}
double max_elastic_residual(const modal::ModalResult& m) {
  double worst = 0.0;
  for (Eigen::Index j = kRigid; j < m.residuals.size(); ++j) worst = std::max(worst, m.residuals[j]);
  return worst;
}
double max_of(const Eigen::VectorXd& v) { return v.size() ? v.maxCoeff() : 0.0; }

void write_row(const std::string& file, const Measurement& s, double reuse_ratio, double load) {
  const preload::PreloadResult& p = s.preload;
  const modal::ModalResult& m = s.modes;
  int cuts = 0, chords = 0;
  for (const auto& step : p.steps) cuts += step.line_search_cuts, chords += step.chord_iterations;
  const int factorizations = p.factor.factorizations;
  std::ofstream out(file);
  out << "dofs,nodes,elements,interface_points,nx,ny,nz,load_steps,newton_iterations,"
         "line_search_cuts,chord_iterations,factorizations,reuse_factor_ratio,preload_n,preload_nnz_A,preload_nnz_L,preload_gflop,"
         "preload_ordering,analyze_s,factorize_last_s,factor_solve_per_iteration_s,build_s,"
         "preload_contact_s,preload_assembly_s,preload_factor_solve_s,preload_s,modal_nnz_L,"
         "modal_gflop,modal_factor_s,lanczos_s,operator_applications,modes_s,total_s,"
         "rss_build_mib,rss_preload_mib,rss_peak_mib,final_residual,support_reaction,"
         "clamping_error,max_rigid_hz,first_elastic_hz,max_elastic_residual,max_backward_error,"
         "blas,openblas_num_threads,omp_num_threads,load_average\n";
  out << fmt::format(
      "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.0f},{:.4g},{},{:.4g},{:.4g},{:.4g},{:.4g},{:.4g},"
      "{:.4g},{:.4g},{:.4g},{:.0f},{:.4g},{:.4g},{:.4g},{},{:.4g},{:.4g},{:.1f},{:.1f},{:.1f},"
      "{:.3e},{:.3e},{:.3e},{:.3e},{:.10g},{:.3e},{:.3e},{},{},{},{:.2f}\n",
      s.dofs, s.nodes, s.elements, s.interface_points, s.refinement.nx(), s.refinement.ny(),
      s.refinement.nz, p.steps.size(), p.total_iterations, cuts, chords, factorizations,
      reuse_ratio, p.factor.rows,
      p.factor.matrix_nonzeros, p.factor.factor_nonzeros, p.factor.factor_flops * 1e-9,
      p.factor.ordering, p.factor.analyze_seconds, p.factor.factorize_seconds,
      factorizations > 0 ? p.factor_seconds / factorizations : 0.0, s.build_seconds,
      p.contact_seconds, p.assembly_seconds, p.factor_seconds, p.seconds, m.factor.factor_nonzeros,
      m.factor.factor_flops * 1e-9, m.factor_seconds, m.lanczos_seconds, m.operator_applications,
      s.modes_seconds, s.total_seconds, s.rss_after_build, s.rss_after_preload, s.rss_after_modes,
      p.steps.empty() ? NAN : p.steps.back().residual, p.support_reaction, s.clamping_error,
      max_rigid_hz(m), m.frequencies_hz.size() > kRigid ? m.frequencies_hz[kRigid] : NAN,
      max_elastic_residual(m), max_of(m.backward_errors), loaded_blas(),
      environment("OPENBLAS_NUM_THREADS"), environment("OMP_NUM_THREADS"), load);
}

void write_modes(const std::string& file, const modal::ModalResult& m) {
  std::ofstream out(file);
  out << "mode,frequency_hz,eigenvalue,residual,backward_error\n";
  for (Eigen::Index j = 0; j < m.eigenvalues.size(); ++j)
    out << fmt::format("{},{:.17g},{:.17g},{:.3e},{:.3e}\n", j + 1, m.frequencies_hz[j],
                       m.eigenvalues[j], m.residuals[j], m.backward_errors[j]);
}

void print_summary(const Measurement& s) {
  const preload::PreloadResult& p = s.preload;
  const modal::ModalResult& m = s.modes;
  std::printf("mesh %d x %d x %d per plate: %ld DOFs, %ld nodes, %ld elements, %ld interface points\n",
              s.refinement.nx(), s.refinement.ny(), s.refinement.nz, s.dofs, s.nodes, s.elements,
              s.interface_points);
  std::printf("BLAS %s, OPENBLAS_NUM_THREADS=%s, OMP_NUM_THREADS=%s\n", loaded_blas().c_str(),
              environment("OPENBLAS_NUM_THREADS").c_str(), environment("OMP_NUM_THREADS").c_str());
  std::printf("build   %8.2f s  (peak RSS %.0f MiB)\n", s.build_seconds, s.rss_after_build);
  std::printf("preload %8.2f s  %s; contact %.2f s, Newton matrix %.2f s, factor+solve %.2f s "
              "(peak RSS %.0f MiB)\n",
              p.seconds, p.status().brief().c_str(), p.contact_seconds, p.assembly_seconds, p.factor_seconds,
              s.rss_after_preload);
  std::printf("        factor: %s, %d factorisations\n", p.factor.brief().c_str(),
              p.factor.factorizations);
  for (std::size_t k = 0; k < p.steps.size(); ++k) {
    std::printf("        step %zu: %d iterations (%d chord), %d factorisations, %d line-search "
                "cuts; residuals",
                k + 1, p.steps[k].iterations, p.steps[k].chord_iterations,
                p.steps[k].factorizations, p.steps[k].line_search_cuts);
    if (k < s.history.size())
      for (double r : s.history[k]) std::printf(" %.1e", r);
    std::printf("\n");
  }
  std::printf("modes   %8.2f s  %s (peak RSS %.0f MiB)\n", s.modes_seconds, m.brief().c_str(),
              s.rss_after_modes);
  std::printf("        factor: %s; factor %.2f s, Lanczos %.2f s, %d solves\n",
              m.factor.brief().c_str(), m.factor_seconds, m.lanczos_seconds,
              m.operator_applications);
  for (Eigen::Index j = 0; j < m.eigenvalues.size(); ++j)
    std::printf("        %2ld  %14.6f Hz  residual %.2e  backward error %.2e\n",
                static_cast<long>(j + 1), m.frequencies_hz[j], m.residuals[j], m.backward_errors[j]);
  std::printf("total   %8.2f s, peak RSS %.0f MiB\n", s.total_seconds, s.rss_after_modes);
}

// The bounds of the header; prints each failure, returns the number failed.
int check(const Measurement& s, double tolerance) {
  int failed = 0;
  const auto bound = [&](bool ok, const std::string& what) {
    if (!ok) {
      std::printf("FAILED: %s\n", what.c_str());
      ++failed;
    }
  };
  const preload::PreloadResult& p = s.preload;
  const modal::ModalResult& m = s.modes;
  const double residual = p.steps.empty() ? NAN : p.steps.back().residual;
  bound(p.status().ok(), "preload converged (" + p.message + ")");
  bound(residual <= tolerance, fmt::format("final relative residual {:.3e} <= {:.1e}", residual, tolerance));
  bound(s.clamping_error <= 1e-8, fmt::format("clamping force error {:.3e} <= 1e-8", s.clamping_error));
  bound(p.support_reaction <= 1e-10, fmt::format("support reaction {:.3e} <= 1e-10", p.support_reaction));
  bound(m.termination == jointhb::Termination::converged && m.eigenvalues.size() == 20,
        "20 modes converged (" + m.message + ")");
  if (m.eigenvalues.size() > kRigid) {
    bound(max_rigid_hz(m) < 1.0, fmt::format("rigid-body modes |f| {:.3e} < 1 Hz", max_rigid_hz(m)));
    bound(m.frequencies_hz[kRigid] > 100.0,
          fmt::format("first elastic mode {:.2f} Hz > 100 Hz", m.frequencies_hz[kRigid]));
  }
  bound(max_of(m.backward_errors) <= 1e-10,
        fmt::format("max backward error {:.3e} <= 1e-10", max_of(m.backward_errors)));
  return failed;
}

}  // namespace

int run(int argc, char** argv) {
  // [--ci] OUTPUT_PREFIX [--dofs N]: take --dofs N out, the rest is the shared study command line.
  long target = 10000;
  double reuse_ratio = preload::PreloadOptions{}.reuse_factor_ratio;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (std::string(argv[i]) == "--dofs" && i + 1 < argc) {
      target = std::atol(argv[++i]);
    } else if (std::string(argv[i]) == "--plain-newton") {
      reuse_ratio = 0.0;  // a factorisation every Newton iteration (before the factor reuse)
    } else {
      rest.push_back(argv[i]);
    }
  }
  const validation_study::Arguments args = validation_study::parse_arguments(static_cast<int>(rest.size()), rest.data());
  if (!args.ok || target <= 0) {
    std::fprintf(stderr, "usage: %s [--ci] OUTPUT_PREFIX [--dofs N] [--plain-newton]\n", argv[0]);
    return 2;
  }
  const double load = load_average();
  const Refinement r = args.ci ? Refinement{2, 2} : nearest_refinement(target);
  const Measurement s = run(r, reuse_ratio);
  print_summary(s);
  write_row(fmt::format("{}_{}.csv", args.prefix, s.dofs), s, reuse_ratio, load);
  write_modes(fmt::format("{}_{}_modes.csv", args.prefix, s.dofs), s.modes);
  const int failed = check(s, 1e-9);
  std::printf("%s: %d bound(s) failed\n", failed == 0 ? "PASS" : "FAIL", failed);
  return failed == 0 ? 0 : 1;
}

}  // namespace jointhb_study_fe_fe_scaling
