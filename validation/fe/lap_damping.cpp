// Description: the damping curve of the first elastic mode of the preloaded, free-free bolted lap
// (case 05's geometry, validation/fe/lap_case.hpp) by harmonic balance in modal/interface form
// (hb/interface_mode.hpp, continuation/interface_response.hpp), from the stuck linear limit
// through microslip to macroslip, scored against what is known independently:
//
//   linear limit    Ω(q → 0) = ω_1 of the ARPACK modes of K_t (the model's own kept mode) and
//                   ζ(q → 0) = the Rayleigh ratio (a/ω + bω)/2;
//   energy          ζ = ξ/(2Ω) against ζ_E = (W_D + W_viscous)/(2π Ω² q²), W_D from the sampled
//                   hysteresis loops of every point (not from the Fourier coefficients): bound 5 %
//                   at H = 1 and 2 % above, on the premise that the gap is the harmonic truncation
//                   of the contact forces and shrinks with H. Measured (full run 2026-11-25) it
//                   does not: 3.2 % at H = 1, 4.2-4.3 % at H = 3, 5, 7, while loop and Fourier W_D
//                   agree to < 1 % in macroslip; the gap follows `energy_error` (the unformed
//                   residual-mode share, below), so the H > 1 bound is not met (open, README).
//                   The exact balance of injected, viscous and Fourier contact work is a
//                   unit test with every mode kept (tests/unit/continuation); here the residual
//                   modes' share of the viscous and EPMC work is not formed, so `energy_error`
//                   (kept modes only) is reported, not bounded;
//   macroslip       the curve reaches the amplitude where the frequency has dropped by
//                   `drop` (the joint is slipping over much of its area) without stopping;
//   FRF peaks       forced responses (a vertical force F cos Ωt at the free end of the upper
//                   plate) at several F peak where the backbone says: at the peak's modal
//                   amplitude q (mode 1's fundamental in the HB unknowns) the backbone frequency,
//                   interpolated in log q, equals the peak frequency (EPMC's premise: near
//                   resonance the forcing balances the damping, single-mode response).
//
// The tangential stiffness of each contact point is frozen at its preloaded value (eq. T-30,
// docs/theory.md §11); with k_T following p_N(t) the curve stops in microslip (the T-21 ratchet
// of low-pressure points: no periodic state), which this study also records.
//
//   lap_damping [--ci] OUTPUT_PREFIX
// The 192 nodal contact points of the coarse mesh are merged into their 63 node pairs (exact,
// eq. T-31); the patch runs measure the interface reduction's error against them.
// --ci: 20 × 6 × 1 C3D8I per plate, H = 1, node pairs and 10 mm patches, one FRF; full: also all
// 192 points, 5 and 20 mm patches, k_T following p_N(t), H = 3, 5 and 7, cutoffs 10 and 40 × f_1,
// and the 40 × 12 × 1 mesh. Tables: PREFIX_backbone_<label>.csv (one row per point),
// PREFIX_summary.csv (one row per run), PREFIX_frf_peaks.csv (one row per force level),
// PREFIX_deviation.csv (each run on the coarse mesh against the first, and each H > 1 also against
// the next lower H, column `against`: the largest deviation of the frequency drop, relative to the
// compared-to curve's total drop, and of ζ, relative).

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/fe_case.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/contact_patches.hpp"
#include "jointhb/reduction/modal_interface.hpp"
#include "lap_case.hpp"
#include "lap_interface.hpp"
#include "study_arguments.hpp"

// The study is one function of the multi-call program jointhb_validate_fe (CMakeLists.txt).
namespace jointhb_study_fe_lap_damping {

namespace {

using namespace jointhb;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

using validation::nearest_node;

struct Run {
  std::string label;
  int nx = 20, ny = 6, nz = 1, harmonics = 1;
  bool frozen = true;
  double cutoff_factor = 20.0;  // cutoff = factor × f_1
  std::vector<double> forces;   // FRF force levels [N] whose peaks are checked against the backbone
  double frf_range[2] = {0.95, 1.003};  // × f_1
  double patch = 0.0;           // contact patches [m] (T-31); 0: node pairs (exact); < 0: all points
};

struct PeakCheck {
  double force = 0, q = 0, peak_hz = 0, backbone_hz = 0, error = 0, seconds = 0;
  int points = 0;
  std::string reason;
};

// Backbone frequency [Hz] at modal amplitude q, linear in log q between accepted points.
double backbone_frequency(const continuation::InterfaceBackbone& b, double q) {
  const auto& pts = b.points;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    const double q0 = pts[i - 1].state.amplitude, q1 = pts[i].state.amplitude;
    if (q >= q0 && q <= q1) {
      const double t = std::log(q / q0) / std::log(q1 / q0);
      return ((1.0 - t) * pts[i - 1].state.omega + t * pts[i].state.omega) / kTwoPi;
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// The forced response at `force` over [lo, hi]·f_1; its peak against the backbone.
PeakCheck frf_peak(const hb::InterfaceModel& model, const continuation::InterfaceBackbone& b, double force,
                   double f1, double lo, double hi, int harmonics) {
  PeakCheck c;
  c.force = force;
  continuation::InterfaceFrfOptions o;
  o.omega_start = lo * kTwoPi * f1;
  o.omega_end = hi * kTwoPi * f1;
  o.load_amplitude = force;
  o.balance.harmonics = harmonics;
  o.balance.time_samples = harmonics == 1 ? 32 : 64;
  const hb::InterfaceBalance balance(model, o.balance);
  const auto start = std::chrono::steady_clock::now();
  const continuation::InterfaceFrf r = continuation::trace_interface_frf(model, o);
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  c.points = static_cast<int>(r.points.size());
  c.reason = r.message;
  const continuation::InterfaceFrfPoint* peak = nullptr;
  for (const auto& p : r.points)
    if (!peak || p.amplitude_h1 > peak->amplitude_h1) peak = &p;
  if (!peak || peak == &r.points.front() || peak == &r.points.back()) return c;  // no interior peak
  const int a1 = balance.basis().cosine_index(1);
  const Eigen::Index i = balance.modal_index(model.rigid_modes, a1);
  c.q = std::hypot(peak->unknowns[i], peak->unknowns[i + 1]);
  c.peak_hz = peak->omega / kTwoPi;
  c.backbone_hz = backbone_frequency(b, c.q);
  c.error = std::abs(c.peak_hz / c.backbone_hz - 1.0);
  return c;
}

struct CurvePoint {
  double q, f, zeta;
};

// Largest relative deviation of `curve` from `reference` in frequency shift f_lin − f and in ζ,
// over the points of `curve` inside the reference's amplitude range (log-linear interpolation).
std::pair<double, double> curve_deviation(const std::vector<CurvePoint>& curve, const std::vector<CurvePoint>& reference) {
  double df = 0.0, dz = 0.0;
  const double f_lin = reference.front().f;
  double shift_max = 0.0;
  for (const auto& c : reference) shift_max = std::max(shift_max, f_lin - c.f);
  for (const auto& c : curve) {
    for (std::size_t i = 1; i < reference.size(); ++i) {
      const auto& a = reference[i - 1];
      const auto& b = reference[i];
      if (c.q < a.q || c.q > b.q) continue;
      const double t = std::log(c.q / a.q) / std::log(b.q / a.q);
      const double f = (1 - t) * a.f + t * b.f, z = (1 - t) * a.zeta + t * b.zeta;
      df = std::max(df, std::abs(c.f - f) / shift_max);  // relative to the largest frequency drop
      dz = std::max(dz, std::abs(c.zeta / z - 1.0));
      break;
    }
  }
  return {df, dz};
}

struct Outcome {
  std::string label, reason;
  std::vector<PeakCheck> peaks;
  std::vector<CurvePoint> curve;
  int fine_points = 0;
  int points = 0, contact_points = 0, kept_modes = 0, unknowns = 0, newton = 0;
  double f1 = 0, zeta_linear = 0, linear_f_error = 0, linear_zeta_error = 0, energy_error = 0,
         truncation = 0,
         final_drop = 0, q_end = 0, zeta_max = 0, seconds = 0, build_seconds = 0, lu_seconds = 0,
         aft_seconds = 0;
};

Outcome run(const Run& r, const std::string& prefix, double drop_target) {
  Outcome out;
  out.label = r.label;
  validation::LapCaseOptions lo;
  lo.nx = r.nx;
  lo.ny = r.ny;
  lo.nz = r.nz;
  const io::FeCase c = io::parse_fe_case(validation::lap_case_yaml(lo), "lap.yaml");
  // Structure and preload through the pipeline object (as `jointhb run`); the condensation below
  // keeps this study's own cutoff and damping rule (a probe model for f_1).
  pipeline::FePipeline pipe(c, c);
  const preload::PreloadModel& model = pipe.structure();
  const auto t0 = std::chrono::steady_clock::now();
  const preload::PreloadResult& p = pipe.preload();
  const int n = c.mesh.num_dofs();
  const int drive = nearest_node(c.mesh, {0.160, 0.015, 0.008});
  const reduction::ModalLoad load{"end force", Eigen::VectorXd::Unit(n, 3 * drive + 2)};
  const std::vector<reduction::ModalOutputSpec> outputs{{"drive z", Eigen::VectorXd::Unit(n, 3 * drive + 2)}};
  // The first elastic mode, then the model with the cutoff at cutoff_factor × f_1.
  reduction::ModalInterfaceOptions mo;
  mo.modal.shift = -std::pow(kTwoPi * 10.0, 2);
  mo.cutoff_hz = 1000.0;
  const reduction::ModalInterfaceResult probe = reduction::build_modal_interface(model, p, load, outputs, mo);
  const double f1 = std::sqrt(probe.model.omega2[probe.model.rigid_modes]) / kTwoPi;
  mo.cutoff_hz = r.cutoff_factor * f1;
  // Rayleigh damping: 0.5 % at f_1 from the stiffness term alone.
  const double zeta_target = 0.005;
  mo.rayleigh_stiffness = 2.0 * zeta_target / (kTwoPi * f1);
  reduction::ModalInterfaceResult mi = reduction::build_modal_interface(model, p, load, outputs, mo);
  out.fine_points = mi.model.num_points();
  if (r.patch >= 0.0) mi.model = reduction::merge_contact_patches(mi.model, model, {.size = r.patch}).model;
  out.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.contact_points = mi.model.num_points();
  out.kept_modes = mi.kept_modes;
  out.f1 = std::sqrt(mi.model.omega2[mi.model.rigid_modes]) / kTwoPi;
  out.zeta_linear = 0.5 * mo.rayleigh_stiffness * kTwoPi * out.f1;

  continuation::InterfaceBackboneOptions bo;
  bo.mode.mode = 1;
  bo.mode.balance.harmonics = r.harmonics;
  bo.mode.balance.time_samples = r.harmonics == 1 ? 32 : 64;
  bo.mode.balance.preloaded_tangential_stiffness = r.frozen;
  bo.log10_amplitude_start = -9.0;
  bo.log10_amplitude_end = -4.0;
  bo.continuation.max_points = 200;
  bo.continuation.max_step = 0.15;  // dense enough to interpolate the FRF peaks' frequencies
  std::FILE* csv = std::fopen(fmt::format("{}_backbone_{}.csv", prefix, r.label).c_str(), "w");
  if (csv) std::fprintf(csv, "q,frequency_hz,damping_ratio,damping_ratio_energy,dissipation_J,fourier_dissipation_J,open_points,slipping_points,iterations\n");
  double worst_energy = 0.0, worst_truncation = 0.0;
  const auto start = std::chrono::steady_clock::now();
  const continuation::InterfaceBackbone b = continuation::trace_interface_backbone(
      mi.model, bo, [&](const continuation::InterfaceBackbonePoint& pt) {
        const auto& s = pt.state;
        const double f = s.omega / kTwoPi;
        if (csv) {
          std::fprintf(csv, "%.10e,%.12g,%.10e,%.10e,%.6e,%.6e,%d,%d,%d\n", s.amplitude, f, s.damping_ratio,
                       s.damping_ratio_energy, s.dissipation, s.fourier_dissipation, s.open_points,
                       s.slipping_points, pt.iterations);
          std::fflush(csv);
        }
        out.curve.push_back({s.amplitude, f, s.damping_ratio});
        worst_energy = std::max(worst_energy, std::abs(s.viscous_dissipation + s.fourier_dissipation -
                                                       s.injected_energy) / s.injected_energy);
        worst_truncation = std::max(worst_truncation, std::abs(s.damping_ratio_energy / s.damping_ratio - 1.0));
        std::fprintf(stderr, "\r  %s: q %.3e  f %.3f Hz  zeta %.4e  slipping %d   ", r.label.c_str(),
                     s.amplitude, f, s.damping_ratio, s.slipping_points);
        return f < (1.0 - drop_target) * out.f1 ? false : true;
      });
  std::fprintf(stderr, "\n");
  if (csv) std::fclose(csv);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.points = static_cast<int>(b.points.size());
  out.unknowns = static_cast<int>(b.unknowns);
  out.newton = b.newton_iterations;
  out.reason = b.message;
  out.lu_seconds = b.timings.linear_solve;
  out.aft_seconds = b.timings.aft;
  if (!b.points.empty()) {
    const auto& first = b.points.front().state;
    const auto& last = b.points.back().state;
    out.linear_f_error = std::abs(first.omega / kTwoPi / out.f1 - 1.0);
    out.linear_zeta_error = std::abs(first.damping_ratio / out.zeta_linear - 1.0);
    out.final_drop = 1.0 - last.omega / kTwoPi / out.f1;
    out.q_end = last.amplitude;
    for (const auto& pt : b.points) out.zeta_max = std::max(out.zeta_max, pt.state.damping_ratio);
  }
  out.energy_error = worst_energy;
  out.truncation = worst_truncation;
  for (double force : r.forces) {
    out.peaks.push_back(frf_peak(mi.model, b, force, out.f1, r.frf_range[0], r.frf_range[1], r.harmonics));
    const PeakCheck& k = out.peaks.back();
    std::printf("  FRF F = %.3g N: peak %.4f Hz at q = %.3e, backbone %.4f Hz there: error %.2e (%d points, %.1f s)%s%s\n",
                k.force, k.peak_hz, k.q, k.backbone_hz, k.error, k.points, k.seconds,
                k.q > 0 ? "" : " -- no interior peak: ", k.q > 0 ? "" : k.reason.c_str());
  }
  return out;
}

}  // namespace

int run(int argc, char** argv) {
  const validation_study::Arguments args = validation_study::parse_arguments(argc, argv);
  if (!args.ok) return 2;
  const double drop = 0.03;
  // The first run is the reference of the curve comparisons (node pairs, H = 1).
  std::vector<Run> runs{{"20x6x1_H1", 20, 6, 1, 1, true, 20.0, {0.5}, {0.99, 0.999}, 0.0},
                        {"20x6x1_H1_patch5mm", 20, 6, 1, 1, true, 20.0, {}, {0.95, 1.003}, 0.005}};
  if (!args.ci) {
    runs.front().forces = {0.2, 0.5, 1.0};
    runs.push_back({"20x6x1_H1_all_points", 20, 6, 1, 1, true, 20.0, {}, {0.95, 1.003}, -1.0});
    runs.push_back({"20x6x1_H1_patch10mm", 20, 6, 1, 1, true, 20.0, {}, {0.95, 1.003}, 0.01});
    runs.push_back({"20x6x1_H1_patch20mm", 20, 6, 1, 1, true, 20.0, {}, {0.95, 1.003}, 0.02});
    runs.push_back({"20x6x1_H1_instantaneous_kT", 20, 6, 1, 1, false, 20.0, {}, {0.95, 1.003}, 0.0});
    runs.push_back({"20x6x1_H3", 20, 6, 1, 3, true, 20.0, {}, {0.95, 1.003}, 0.0});
    runs.push_back({"20x6x1_H5", 20, 6, 1, 5, true, 20.0, {}, {0.95, 1.003}, 0.0});
    runs.push_back({"20x6x1_H7", 20, 6, 1, 7, true, 20.0, {}, {0.95, 1.003}, 0.0});
    runs.push_back({"20x6x1_H1_cutoff10", 20, 6, 1, 1, true, 10.0, {}, {0.95, 1.003}, 0.0});
    runs.push_back({"20x6x1_H1_cutoff40", 20, 6, 1, 1, true, 40.0, {}, {0.95, 1.003}, 0.0});
    runs.push_back({"40x12x1_H1", 40, 12, 1, 1, true, 20.0, {}, {0.95, 1.003}, 0.0});
  }
  std::FILE* summary = std::fopen((args.prefix + "_summary.csv").c_str(), "w");
  if (summary)
    std::fprintf(summary, "run,contact_points,kept_modes,unknowns,f1_hz,zeta_linear,points,newton,linear_f_error,"
                          "linear_zeta_error,energy_error,zeta_vs_loop_energy,final_drop,q_end,zeta_max,build_s,backbone_s,lu_s,aft_s,stop\n");
  std::FILE* peaks = std::fopen((args.prefix + "_frf_peaks.csv").c_str(), "w");
  if (peaks) std::fprintf(peaks, "run,force_N,q,peak_hz,backbone_hz,relative_error,frf_points,frf_s\n");
  std::FILE* deviations = std::fopen((args.prefix + "_deviation.csv").c_str(), "w");
  if (deviations)
    std::fprintf(deviations, "run,contact_points,unknowns,frequency_shift_deviation,damping_deviation,backbone_s,against\n");
  bool ok = true;
  std::vector<CurvePoint> reference;
  // The harmonic ladder (node pairs, frozen k_T, cutoff 20 f_1 on the coarse mesh): each H > 1
  // also against the next lower H that ran.
  std::vector<CurvePoint> lower_h;
  std::string lower_h_label;
  for (const Run& r : runs) {
    const Outcome o = run(r, args.prefix, drop);
    const bool ladder = r.nx == runs.front().nx && r.frozen && r.patch == 0.0 && r.cutoff_factor == 20.0;
    if (reference.empty()) {
      reference = o.curve;
    } else if (r.nx == runs.front().nx && !o.curve.empty()) {  // same mesh: against the reference curve
      const auto [df, dz] = curve_deviation(o.curve, reference);
      std::printf("  vs %s: frequency shift %.2e, damping %.2e\n", runs.front().label.c_str(), df, dz);
      if (deviations)
        std::fprintf(deviations, "%s,%d,%d,%.3e,%.3e,%.2f,%s\n", o.label.c_str(), o.contact_points, o.unknowns, df, dz,
                     o.seconds, runs.front().label.c_str());
      if (ladder && r.harmonics > 1 && !lower_h.empty() && lower_h_label != runs.front().label) {
        const auto [dfh, dzh] = curve_deviation(o.curve, lower_h);
        std::printf("  vs %s: frequency shift %.2e, damping %.2e\n", lower_h_label.c_str(), dfh, dzh);
        if (deviations)
          std::fprintf(deviations, "%s,%d,%d,%.3e,%.3e,%.2f,%s\n", o.label.c_str(), o.contact_points, o.unknowns, dfh,
                       dzh, o.seconds, lower_h_label.c_str());
      }
      // All points vs node pairs: exact (unit test: 5e-12 at equal q); here the comparison
      // interpolates between the two curves' own points, which limits it to ~1e-2.
      if (r.patch < 0.0) ok = ok && df < 0.05 && dz < 0.1;
      // Patches approximate the slip (reported, not bounded); their linear limit is exact (below).
    }
    if (ladder && !o.curve.empty()) lower_h = o.curve, lower_h_label = o.label;
    std::printf("%-28s P=%d (of %d) modes=%d U=%d f1=%.3f Hz: %d points (%d Newton), linear f %.1e zeta %.1e, energy %.1e "
                "(zeta vs loop W_D %.1e), "
                "drop %.3f at q=%.2e, zeta_max %.4f; build %.1f s, backbone %.1f s (LU %.1f, AFT %.1f)\n  stop: %s\n",
                o.label.c_str(), o.contact_points, o.fine_points, o.kept_modes, o.unknowns, o.f1, o.points, o.newton,
                o.linear_f_error, o.linear_zeta_error, o.energy_error, o.truncation, o.final_drop, o.q_end,
                o.zeta_max, o.build_seconds, o.seconds, o.lu_seconds, o.aft_seconds, o.reason.c_str());
    if (summary)
      std::fprintf(summary, "%s,%d,%d,%d,%.10g,%.6e,%d,%d,%.3e,%.3e,%.3e,%.3e,%.5f,%.4e,%.5e,%.2f,%.2f,%.2f,%.2f,\"%s\"\n",
                   o.label.c_str(), o.contact_points, o.kept_modes, o.unknowns, o.f1, o.zeta_linear, o.points,
                   o.newton, o.linear_f_error, o.linear_zeta_error, o.energy_error, o.truncation, o.final_drop, o.q_end,
                   o.zeta_max, o.build_seconds, o.seconds, o.lu_seconds, o.aft_seconds, o.reason.c_str());
    if (r.frozen) {
      ok = ok && o.linear_f_error < 1e-6 && o.linear_zeta_error < 2e-4;
      if (r.patch <= 0.0) ok = ok && o.truncation < (r.harmonics == 1 ? 0.05 : 0.02) && o.final_drop >= drop;
      int found = 0;  // a level whose FRF stops before its peak is reported, not scored
      for (const PeakCheck& k : o.peaks)
        if (k.q > 0.0) ok = ok && k.error < 1e-3, ++found;
      ok = ok && (o.peaks.empty() || found > 0);
    }
    if (peaks)
      for (const PeakCheck& k : o.peaks)
        std::fprintf(peaks, "%s,%.6g,%.6e,%.10g,%.10g,%.3e,%d,%.2f\n", o.label.c_str(), k.force, k.q, k.peak_hz,
                     k.backbone_hz, k.error, k.points, k.seconds);
  }
  if (summary) std::fclose(summary);
  if (peaks) std::fclose(peaks);
  if (deviations) std::fclose(deviations);
  std::printf("%s\n", ok ? "lap_damping: all bounds met" : "lap_damping: a bound was exceeded");
  return ok ? 0 : 1;
}

}  // namespace jointhb_study_fe_lap_damping
