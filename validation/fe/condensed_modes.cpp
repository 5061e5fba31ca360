// Description: the Craig–Bampton-condensed bolted lap (reduction/condensed_interface.hpp) against
// the full finite-element model: linear modes about the preloaded state, stuck tangent (P-2),
// for several cutoffs of the fixed-interface modes.
//
//   full:      compute_modes(K_t, M) on every DOF (free-free), K_t = dynamic_stiffness(P-2)
//   condensed: the dense generalized eigenproblem (K_r + G_rᵀ A C_pre G_r, M_r), boundary = every
//              DOF of the 2 × 221 interface nodes (1326), plus the fixed-interface modes ≤ cutoff
//
// The first kElastic elastic modes are compared (the 6 rigid-body modes skipped; both sorted by
// frequency); the cutoffs are multiples of the highest compared full frequency. By Rayleigh–Ritz
// the condensed frequencies lie above the full ones and fall towards them as the cutoff rises.
// Bounds (exit 1): every condensed frequency ≥ full·(1 − 1e-9); the worst error decreases with the
// cutoff; below 1e-3 (0.1 %) over the whole band with a cutoff of 5× the band.
// Measured (40 × 12 × 2, 9594 DOFs, 1326 boundary DOFs; band = elastic mode 10 = 12.0 kHz): worst
// error 6.4e-3, 4.4e-3, 1.4e-3, 2.8e-4 for cutoffs 1.5, 2, 3, 5 × band (12, 18, 24, 40 modes);
// modes 1–6 (≤ 5.2 kHz) within 2.2e-4 from 2 × band. --ci: 6.0e-3, 3.6e-3, 1.2e-3, 2.3e-4.
//
//   condensed_modes [--ci] OUTPUT_PREFIX     (--ci: 20 × 6 × 2 per plate instead of 40 × 12 × 2)
// Tables: PREFIX_errors.csv (cutoff factor, modes kept, mode, full Hz, condensed Hz, relative
// error), PREFIX_timing.csv (cutoff factor, size, CB stages [s], dense eigensolution [s]).

#include <fmt/format.h>

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <vector>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/condensed_interface.hpp"
#include "lap_case.hpp"
#include "study_arguments.hpp"

// The study is one function of the multi-call program jointhb_validate_fe (CMakeLists.txt).
namespace jointhb_study_fe_condensed_modes {

namespace {

using namespace jointhb;
constexpr int kRigid = 6, kElastic = 10;

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

Eigen::VectorXd dense_frequencies_hz(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M) {
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(K, M, Eigen::EigenvaluesOnly);
  Eigen::VectorXd f = solver.eigenvalues();
  for (Eigen::Index k = 0; k < f.size(); ++k)
    f[k] = std::copysign(std::sqrt(std::abs(f[k])), f[k]) / (2.0 * std::numbers::pi);
  return f;
}

}  // namespace

int run(int argc, char** argv) {
  const validation_study::Arguments args = validation_study::parse_arguments(argc, argv);
  if (!args.ok) return 2;
  validation::LapCaseOptions lap;
  if (args.ci) lap.nx = 20, lap.ny = 6;
  lap.modes = kRigid + kElastic;
  const io::FeCase c = io::parse_fe_case(validation::lap_case_yaml(lap), "condensed_modes.yaml");
  // Structure, preload and the full model's modes through the pipeline object (as `jointhb run`).
  pipeline::FePipeline pipe(c, c);
  const preload::PreloadModel& model = pipe.structure();
  const preload::PreloadResult& p = pipe.preload();
  if (!p.status().ok()) {
    std::printf("preload failed: %s\n", p.message.c_str());
    return 1;
  }
  auto t = std::chrono::steady_clock::now();
  const modal::ModalResult& full = pipe.modes();  // of K_t on every DOF (free-free: no constraints)
  const double full_seconds = seconds_since(t);
  if (full.termination != jointhb::Termination::converged) {
    std::printf("full modes failed: %s\n", full.message.c_str());
    return 1;
  }
  const double band = full.frequencies_hz[kRigid + kElastic - 1];
  std::printf("model %d DOFs, %ld interface points; full modes %.2f s; band %.1f Hz (elastic modes 1..%d)\n",
              c.mesh.num_dofs(), static_cast<long>(c.interfaces[0].geometry.num_points()), full_seconds, band,
              kElastic);

  std::ofstream errors(args.prefix + "_errors.csv"), timing(args.prefix + "_timing.csv");
  errors << "cutoff_factor,fixed_interface_modes,mode,full_hz,condensed_hz,relative_error\n";
  timing << "cutoff_factor,boundary_dofs,fixed_interface_modes,size,condense_s,factor_s,constraint_modes_s,"
            "fixed_interface_modes_s,projection_s,dense_eigen_s\n";
  bool ok = true;
  double previous = 1.0;
  for (double factor : {1.5, 2.0, 3.0, 5.0}) {
    reduction::CraigBamptonOptions o;
    o.cutoff_hz = factor * band;
    o.modal.shift = -std::pow(2.0 * std::numbers::pi * 10.0, 2);
    const reduction::CondensedModel r = reduction::condense(model, p, o);
    t = std::chrono::steady_clock::now();
    const Eigen::VectorXd f = dense_frequencies_hz(r.stuck_stiffness, r.cb.mass);
    const double eigen_seconds = seconds_since(t);
    double worst = 0.0;
    for (int k = kRigid; k < kRigid + kElastic; ++k) {
      const double e = f[k] / full.frequencies_hz[k] - 1.0;
      worst = std::max(worst, std::abs(e));
      if (e < -1e-9) ok = false;  // Rayleigh–Ritz: never below the full model
      errors << fmt::format("{},{},{},{:.10g},{:.10g},{:.3e}\n", factor, r.cb.num_modes(), k - kRigid + 1,
                            full.frequencies_hz[k], f[k], e);
    }
    timing << fmt::format("{},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f}\n", factor, r.cb.num_boundary(),
                          r.cb.num_modes(), r.size(), r.seconds, r.cb.factor_seconds, r.cb.constraint_seconds,
                          r.cb.modes_seconds, r.cb.projection_seconds, eigen_seconds);
    std::printf("cutoff %.1f x band (%.0f Hz): %s; rigid |f| <= %.2g Hz; worst error %.3e; dense eigen %.2f s\n",
                factor, o.cutoff_hz, r.cb.brief().c_str(), f.head(kRigid).cwiseAbs().maxCoeff(), worst,
                eigen_seconds);
    if (!(worst < previous)) ok = false;
    if (factor >= 5.0 && !(worst < 1e-3)) ok = false;
    previous = worst;
  }
  std::printf("%s\n", ok ? "all bounds met" : "BOUND VIOLATED");
  return ok ? 0 : 1;
}

}  // namespace jointhb_study_fe_condensed_modes
