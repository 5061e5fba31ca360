// Description: stability of finite-element FRF points of the bolted lap (lap_interface.hpp,
// Gaul–Mayer microslip) by Hill's method (hb/interface_hill_stability.hpp, T-36a) against the
// monodromy of the reduced model along the orbit (hb/interface_orbit_monodromy.hpp, T-39a/T-40a:
// the contact laws followed in time — the reference of docs/stability.md §2), and what each costs
// per point as the joint grows (docs/stability.md §7).
//
// Per mesh (P contact points, nodal integration, no merging): the FRF at 2 N on "drive z" across
// the first resonance, Ω from 0.97 to 1.0 times the stuck f_1, H = 3, N_t = 64 (matrix-free, the
// default of FE FRFs), without stability; then at every `stride`-th accepted point Hill's method and
// the monodromy with N_f = 1024 (and 4096 on the smallest mesh, the monodromy's own time-step
// error), each timed (one thread). Reported per point: the slipping points, max |ρ| of each, the
// verdicts, and each of Hill's multipliers against the nearest of the monodromy's (the largest
// distance, and the largest modulus among those nearest: the monodromy also has the force states of
// slipping points, for Gaul–Mayer one neutral at 1 — the creep of the traction — that Hill's method
// has not); per mesh: the median time per point, the largest of those and the verdicts' agreement.
//
//   interface_stability [--ci] OUTPUT_PREFIX
// --ci: the 24-point mesh, every 8th point (ctest, ~10 s): both methods ok at every sampled
// point, the verdicts equal. Tables: PREFIX_points.csv, PREFIX_meshes.csv (written
// row by row: a long run keeps what it measured).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "../../src/support/stopwatch.hpp"
#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/hb/interface_hill_stability.hpp"
#include "jointhb/hb/interface_orbit_monodromy.hpp"
#include "lap_interface.hpp"
#include "study_arguments.hpp"

// The study is one function of the multi-call program jointhb_validate_fe (CMakeLists.txt).
namespace jointhb_study_fe_interface_stability {

namespace {

using namespace jointhb;
using support::Clock;
constexpr double kTwoPi = 2.0 * std::numbers::pi;


double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Mesh {
  int nx, ny;  // points = 4 · (0.4 nx) · ny
  double footprint_radius;  // [m] (lap_interface)
  int stride;  // every stride-th accepted point
  bool fine_reference;  // also the monodromy at N_f = 4096
};

// Each of Hill's multipliers against the nearest of the monodromy's: the largest distance, and the
// largest modulus among those nearest (the monodromy also holds the force states of the slipping
// points — for Gaul–Mayer a neutral one at 1, the creep of the traction, docs/stability.md §7 —
// which Hill's method does not have).
struct Matched {
  double distance = 0.0, max_modulus = 0.0;
};

Matched match(const Eigen::VectorXcd& hill, const Eigen::VectorXcd& monodromy) {
  Matched m;
  for (const std::complex<double>& h : hill) {
    double best = 1e300;
    std::complex<double> at;
    for (const std::complex<double>& q : monodromy) {
      if (std::abs(h - q) < best) best = std::abs(h - q), at = q;
    }
    m.distance = std::max(m.distance, best);
    m.max_modulus = std::max(m.max_modulus, std::abs(at));
  }
  return m;
}

struct MeshSummary {
  int sampled = 0, agreed = 0, failed = 0;
  double distance = 0.0, modulus = 0.0, own_error = 0.0;  // largest over the sampled points
  std::vector<double> hill_s, monodromy_s, monodromy_fine_s;
};

}  // namespace

int run(int argc, char** argv) {
  const validation_study::Arguments args = validation_study::parse_arguments(argc, argv);
  if (!args.ok) return 2;
  std::vector<Mesh> meshes{{5, 3, 0.0045, 3, true},
                           {10, 3, 0.006, 3, false},
                           {15, 4, 0.0045, 4, false},
                           {20, 6, 0.0045, 25, false}};
  if (args.ci) meshes = {{5, 3, 0.0045, 8, false}};

  std::FILE* points = std::fopen((args.prefix + "_points.csv").c_str(), "w");
  std::FILE* table = std::fopen((args.prefix + "_meshes.csv").c_str(), "w");
  if (!points || !table) {
    std::fprintf(stderr, "cannot write %s_*.csv\n", args.prefix.c_str());
    return 1;
  }
  std::fprintf(points, "points,unknowns,frequency_hz,amplitude_h1,slipping_points,hill_max_multiplier,hill_stable,"
                       "hill_s,monodromy_max_multiplier,monodromy_stable,monodromy_s,matched_distance,"
                       "matched_max_multiplier,monodromy4096_matched_distance,monodromy4096_s\n");
  std::fprintf(table, "points,kept_modes,unknowns,frf_points,sampled,frf_s,hill_median_s,monodromy1024_median_s,"
                      "monodromy4096_median_s,max_matched_distance,max_modulus_difference,monodromy_own_error,"
                      "verdicts_agree,failed\n");
  bool ok = true;
  for (const Mesh& mesh : meshes) {
    const validation::LapInterface lap = validation::lap_interface(mesh.nx, mesh.ny, mesh.footprint_radius);
    const int P = lap.model.num_points();
    continuation::InterfaceFrfOptions o;
    o.omega_start = 0.97 * kTwoPi * lap.f1;
    o.omega_end = kTwoPi * lap.f1;
    o.load_amplitude = 2.0;
    o.balance.harmonics = 3;
    o.balance.time_samples = 64;
    o.stability = continuation::Stability::never;
    o.refine_extrema = false;
    const auto t0 = Clock::now();
    const continuation::InterfaceFrf frf = continuation::trace_interface_frf(lap.model, o);
    const double frf_seconds = support::seconds_since(t0);
    std::printf("P = %d (%d kept modes, %ld unknowns): FRF %zu points in %.2f s, %s\n", P, lap.kept_modes,
                static_cast<long>(frf.unknowns), frf.points.size(), frf_seconds, frf.message.c_str());
    std::fflush(stdout);  // progress also when not on a terminal
    if (frf.points.empty()) {
      ok = false;
      continue;
    }
    const hb::InterfaceBalance balance(lap.model, o.balance);
    MeshSummary s;
    hb::OrbitMonodromyOptions coarse, fine;
    coarse.samples = 1024;
    fine.samples = 4096;
    for (std::size_t k = 0; k < frf.points.size(); k += static_cast<std::size_t>(mesh.stride)) {
      const continuation::InterfaceFrfPoint& p = frf.points[k];
      auto t = Clock::now();
      const hb::FloquetResult hill = hb::interface_hill_floquet(balance, p.unknowns, p.omega);
      s.hill_s.push_back(support::seconds_since(t));
      t = Clock::now();
      const hb::FloquetResult mono = hb::interface_orbit_floquet(balance, p.unknowns, p.omega, coarse);
      s.monodromy_s.push_back(support::seconds_since(t));
      hb::FloquetResult mono_fine;
      if (mesh.fine_reference) {
        t = Clock::now();
        mono_fine = hb::interface_orbit_floquet(balance, p.unknowns, p.omega, fine);
        s.monodromy_fine_s.push_back(support::seconds_since(t));
      }
      ++s.sampled;
      if (!hill.ok || !mono.ok || (mesh.fine_reference && !mono_fine.ok)) {
        ++s.failed;
        std::printf("  %.4f Hz: failed: %s %s\n", p.omega / kTwoPi, hill.message.c_str(), mono.message.c_str());
        continue;
      }
      const Matched m = match(hill.multipliers, mono.multipliers);
      s.distance = std::max(s.distance, m.distance);
      s.modulus = std::max(s.modulus, std::abs(m.max_modulus - hill.max_multiplier));
      const Matched own = mesh.fine_reference ? match(hill.multipliers, mono_fine.multipliers) : Matched{};
      s.own_error = std::max(s.own_error, std::abs(own.distance - m.distance));
      if (hill.stable() == mono.stable()) ++s.agreed;
      std::fprintf(points, "%d,%ld,%.10g,%.10e,%d,%.10f,%d,%.4e,%.10f,%d,%.4e,%.4e,%.10f,%s,%s\n", P,
                   static_cast<long>(frf.unknowns), p.omega / kTwoPi, p.amplitude_h1, p.slipping_points,
                   hill.max_multiplier, hill.stable() ? 1 : 0, s.hill_s.back(), mono.max_multiplier,
                   mono.stable() ? 1 : 0, s.monodromy_s.back(), m.distance, m.max_modulus,
                   mesh.fine_reference ? fmt::format("{:.4e}", own.distance).c_str() : "",
                   mesh.fine_reference ? fmt::format("{:.4e}", s.monodromy_fine_s.back()).c_str() : "");
      std::fflush(points);
    }
    std::fprintf(table, "%d,%d,%ld,%zu,%d,%.3f,%.4e,%.4e,%s,%.3e,%.3e,%s,%d,%d\n", P, lap.kept_modes,
                 static_cast<long>(frf.unknowns), frf.points.size(), s.sampled, frf_seconds, median(s.hill_s),
                 median(s.monodromy_s),
                 mesh.fine_reference ? fmt::format("{:.4e}", median(s.monodromy_fine_s)).c_str() : "", s.distance,
                 s.modulus, mesh.fine_reference ? fmt::format("{:.3e}", s.own_error).c_str() : "", s.agreed,
                 s.failed);
    std::fflush(table);
    std::printf("  %d points sampled: Hill %.3g s per point, monodromy (N_f = 1024) %.3g s; Hill's multipliers within "
                "%.2e of the monodromy's (largest moduli within %.2e)%s; verdicts agree at %d; %d failed\n",
                s.sampled, median(s.hill_s), median(s.monodromy_s), s.distance, s.modulus,
                mesh.fine_reference ? fmt::format(" (N_f = 4096 changes that by {:.1e})", s.own_error).c_str() : "",
                s.agreed, s.failed);
    std::fflush(stdout);
    if (s.failed > 0 || s.agreed != s.sampled) ok = false;
  }
  std::fclose(points);
  std::fclose(table);
  std::printf("%s\n", ok ? "ok" : "FAILED: a method failed or the verdicts differ");
  return ok ? 0 : 1;
}

}  // namespace jointhb_study_fe_interface_stability
