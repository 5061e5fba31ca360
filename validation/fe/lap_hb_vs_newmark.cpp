// Description: harmonic balance of the modal/interface model (hb/interface_balance.hpp) against the
// steady state of the implicit Newmark integration of the FULL finite-element model
// (timeint/fe_newmark.hpp) for the preloaded, free-free bolted lap (lap_case.hpp) under a vertical
// force F cos Ωt at the free end of the upper plate, at a force that puts the joint in microslip.
// The two sides share the mesh, the contact law (Gaul–Mayer, tangential stiffness frozen at its
// preloaded value, eq. T-30, on both sides), the preload and the Rayleigh matrix C = b K_t, and
// nothing else: HB works on kept modes + residual flexibility (T-22..T-25) with Fourier series
// and AFT; Newmark on every DOF with the contact law's exact increments.
//
// Compared at frequencies around the first bending resonance: the drive point's fundamental
// amplitude |X_1| and phase (u = a_1 cos Ωt + b_1 sin Ωt, X_1 = a_1 − i b_1), the external work
// per cycle W_ext (HB: π F b_1; Newmark: Σ ½(f_n + f_{n+1})·Δw over the last period) and the
// friction dissipation per cycle W_D (HB: Σ_p A_p W_D,p on the sampled path; Newmark: Σ of the
// exact increments' dissipation).
//
// Error sources, each measured separately:
//   time step    Newmark at N and 2N steps per period; the scheme's error falls like Δt², so
//                e_N ≈ (x_N − x_2N)·4/3 and the Richardson value x_2N + (x_2N − x_N)/3 is the
//                time-exact reference;
//   harmonics    HB at H = 1, 3, 5(, 7) against that reference;
//   reduction    the stuck linear response of the modal/interface model (kept modes up to
//                cutoff × f_1 + residual terms) against a direct complex solve of the full model;
//   transient    the Newmark run stops when a period repeats to `tolerance`; the remaining
//                transient is estimated from the ratio ρ of successive changes, change·ρ/(1−ρ).
// The Newmark run starts from the HB solution at the largest H carried to the full model (the
// harmonics' full-field response W_k = Z_k⁻¹(f F_k − Gᵀ A N_k), Z_k the full dynamic stiffness,
// the contact state by replaying each point's law over two periods of that motion from the
// preload): a shorter transient, not a different steady state (the period-change criterion
// decides when it has settled).
//
// Force level: the backbone (EPMC, H = 1) is traced to a frequency drop `drop_target`; at that
// amplitude q* the phase-resonant force is F = ξ Ω q*/|φ_1ᵀf| = 2ζΩ²q*/|φ_1ᵀf| (the EPMC
// damping force supplied by the excitation), so the forced resonance sits near Ω_bb(q*) with the
// joint in microslip.
//
//   lap_hb_vs_newmark [--ci] OUTPUT_PREFIX
// --ci: 10 × 3 × 1 C3D8I per plate (48 contact points), H = 1, 3, the resonance frequency only,
// N = 64 / 128. Full: 10 × 3 × 1 with H = 1, 3, 5, 7 at five frequencies, N = 64 / 128 / 256
// (the observed order of the scheme), and 20 × 6 × 1 (192 points) with H = 1 at the resonance,
// N = 64 / 128 (reported, not scored). Tables: PREFIX_points.csv (one row per frequency and
// method), PREFIX_newmark_order.csv, PREFIX_summary.csv. Measured numbers:
// README_lap_hb_vs_newmark.md.

#include <fmt/format.h>

#include <Eigen/Dense>
#include <Eigen/SparseLU>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/hb/interface_balance.hpp"
#include "jointhb/timeint/fe_newmark.hpp"
#include "lap_hb_vs_newmark_fixture.hpp"
#include "study_arguments.hpp"

// The study is one function of the multi-call program jointhb_validate_fe (CMakeLists.txt).
namespace jointhb_study_fe_lap_hb_vs_newmark {

namespace {

using namespace jointhb;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * kPi;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// --- harmonic balance at fixed Ω ------------------------------------------------------------------

struct HbSolution {
  bool ok = false;
  std::string message;
  VectorXd y;
  hb::InterfaceBalanceEvaluation e;
  VectorXd output;  // drive-point coefficients [u0, a1, b1, ...]
  int iterations = 0;
  double residual = 0.0, seconds = 0.0;
};

// Newton with backtracking on ‖r‖∞ (dense LU), the load ramped from a tenth of F in `ramp` steps
// from the stuck linear solution, or in one step from `start`.
HbSolution solve_hb(const hb::InterfaceBalance& b, double omega, double force, const VectorXd* start,
                    int ramp = 6) {
  const auto t0 = std::chrono::steady_clock::now();
  HbSolution s;
  const VectorXd scale = b.unknown_scale();
  const int stages = start ? 1 : ramp;
  s.y = start ? *start : b.linear_solution(omega, b.cosine_load(0.1 * force));
  VectorXd load;
  for (int stage = 1; stage <= stages; ++stage) {
    const double f = start ? force : force * (0.1 + 0.9 * stage / stages);
    load = b.cosine_load(f);
    bool converged = false;
    for (int it = 0; it < 60; ++it) {
      b.evaluate(s.y, omega, 0.0, load, true, s.e);
      if (!s.e.ok) {
        s.message = s.e.message;
        s.seconds = seconds_since(t0);
        return s;
      }
      ++s.iterations;
      const double r = s.e.residual.lpNorm<Eigen::Infinity>();
      const double size = s.y.cwiseQuotient(scale).lpNorm<Eigen::Infinity>();
      s.residual = r / size;
      if (r <= 1e-11 * size) {
        converged = true;
        break;
      }
      const VectorXd dy = s.e.jacobian.partialPivLu().solve(-s.e.residual);
      double t = 1.0;
      hb::InterfaceBalanceEvaluation trial;
      for (int k = 0; k < 12; ++k, t *= 0.5) {
        b.evaluate(s.y + t * dy, omega, 0.0, load, false, trial);
        if (trial.ok && trial.residual.lpNorm<Eigen::Infinity>() < r) break;
      }
      s.y += t * dy;
    }
    if (!converged) {
      s.message = fmt::format("Newton did not converge at F = {:.4g} N (relative residual {:.2e})", f,
                              s.residual);
      s.seconds = seconds_since(t0);
      return s;
    }
  }
  s.output = b.output_coefficients(0, s.y, omega, 0.0, load, s.e.contact_force);
  s.ok = true;
  s.seconds = seconds_since(t0);
  return s;
}

// --- the full model's complex response ------------------------------------------------------------

// (K_t − (kΩ)²M + ikΩ b K_t)⁻¹ rhs on every DOF (free-free: the rigid-body modes are carried by the
// inertia term, so the matrix is regular for Ω > 0).
Eigen::VectorXcd full_response(const validation::LapFixture& f, double omega_k, double b,
                               const Eigen::VectorXcd& rhs) {
  const Eigen::SparseMatrix<double>& kt = f.preload.dynamic_stiffness;
  Eigen::SparseMatrix<Complex> z = (kt - omega_k * omega_k * f.model.structure.mass).cast<Complex>() +
                                   Complex(0.0, omega_k * b) * kt.cast<Complex>();
  z.makeCompressed();
  Eigen::SparseLU<Eigen::SparseMatrix<Complex>> lu(z);
  return lu.solve(rhs);
}

// The HB solution carried to the full model as a Newmark start at t = 0 (see the header).
timeint::FeState newmark_start(const validation::LapFixture& f, const hb::InterfaceBalance& b,
                               const HbSolution& s, double omega, double force, double rayleigh_b,
                               int steps_per_period, const timeint::FeNewmarkOptions& options) {
  const int n = f.c.mesh.num_dofs();
  const auto& geometry = f.model.interfaces.at(0).geometry;
  const hb::FourierBasis& basis = b.basis();
  const int P = b.points();
  std::vector<Eigen::VectorXcd> w;  // W_k per harmonic
  std::vector<int> orders;
  for (int k : basis.orders()) {
    const int ia = basis.cosine_index(k);
    // N_k per unit area (A N / A_p), complex X = a − i b, then Gᵀ A N_k.
    VectorXd re(3 * P), im(3 * P);
    for (int c = 0; c < 3 * P; ++c) {
      const double area = b.model().areas[c / 3];
      re[c] = s.e.contact_force(ia, c) / area;
      im[c] = -s.e.contact_force(ia + 1, c) / area;
    }
    Eigen::VectorXcd rhs = -(fe::interface_force(geometry, re).cast<Complex>() +
                             Complex(0.0, 1.0) * fe::interface_force(geometry, im).cast<Complex>());
    if (k == 1) rhs[f.drive_dof()] += force;
    w.push_back(full_response(f, k * omega, rayleigh_b, rhs));
    orders.push_back(k);
  }
  const auto at = [&](double t, bool velocity) {
    VectorXd u = VectorXd::Zero(n);
    for (std::size_t j = 0; j < w.size(); ++j) {
      const double kw = orders[j] * omega;
      const Complex e = std::polar(1.0, kw * t);
      u += velocity ? VectorXd((Complex(0.0, kw) * e * w[j]).real()) : VectorXd((e * w[j]).real());
    }
    return u;
  };
  timeint::FeState start = timeint::preloaded_state(f.model, f.preload, 0.0);
  start.displacement = at(0.0, false);
  start.velocity = at(0.0, true);
  // Contact state: each point's law replayed over two periods of the motion from the preload.
  const auto laws = timeint::fe_point_laws(f.model, f.preload, options);
  const VectorXd& g_pre = f.preload.interfaces[0].state.gap;
  VectorXd t_now = f.preload.interfaces[0].state.traction, g_now = g_pre;
  const double dt = kTwoPi / omega / steps_per_period;
  for (int j = 0; j <= 2 * steps_per_period; ++j) {
    const VectorXd g = g_pre + fe::gaps(geometry, at(j * dt, false));
    for (int p = 0; p < P; ++p)
      t_now.segment<3>(3 * p) = laws[0][static_cast<std::size_t>(p)]
                                    .step(t_now.segment<2>(3 * p), g_now.segment<3>(3 * p), g.segment<3>(3 * p))
                                    .traction;
    g_now = g;
  }
  start.traction[0] = t_now;
  start.gap[0] = g_now;
  return start;
}

// --- one frequency --------------------------------------------------------------------------------

struct Measure {
  std::string method;  // "HB H=3", "NM N=64", "NM extrapolated"
  double amplitude = 0, phase = 0, external_work = 0, dissipation = 0;
  double seconds = 0;
  int iterations = 0;          // HB Newton iterations / Newmark periods
  double change = 0, transient = 0;  // Newmark: last period change, estimated remaining transient
  bool ok = true;
  std::string message;
};

Measure from_coefficients(std::string method, double a1, double b1) {
  Measure m;
  m.method = std::move(method);
  m.amplitude = std::hypot(a1, b1);
  m.phase = std::atan2(b1, a1);  // lag of u behind F cos Ωt
  return m;
}

double relative(double x, double ref) { return std::abs(x - ref) / std::abs(ref); }

struct Config {
  std::string label;
  int nx = 10, ny = 3, nz = 1;
  double radius = 0.006;
  std::vector<int> harmonics{1, 3};
  std::vector<double> ratios{1.0};  // Ω / Ω_bb(q*)
  int steps = 64;                   // N; levels N, 2N(, 4N)
  int levels = 2;
  int max_periods = 150;
  double tolerance = 1e-5;
};

struct Summary {
  bool ok = true;
  double worst_hb_amp = 0, worst_hb_phase = 0, worst_hb_wext = 0, worst_hb_wd = 0;  // best H vs ref
  double worst_dt_amp = 0, worst_transient = 0, worst_reduction = 0;
  double best_h1_amp = 1e300;  // smallest H = 1 amplitude error over the frequencies
};

Summary run(const Config& cfg, std::FILE* points_csv, std::FILE* order_csv) {
  Summary sum;
  const auto t_start = std::chrono::steady_clock::now();
  const auto lap = validation::make_lap_fixture(cfg.nx, cfg.ny, cfg.nz, cfg.radius);
  if (!lap->preload.status().ok()) {
    std::printf("%s: preload failed: %s\n", cfg.label.c_str(), lap->preload.message.c_str());
    sum.ok = false;
    return sum;
  }
  const double f1 = validation::first_elastic_hz(*lap);
  const double zeta = 0.005;  // Rayleigh, at f_1, from the stiffness term
  const double rayleigh_b = 2.0 * zeta / (kTwoPi * f1);
  const auto mi = validation::lap_modal_model(*lap, f1, 20.0, rayleigh_b);
  std::printf("%s: %d DOFs, %d contact points, f1 = %.3f Hz, %d kept modes (%.1f s)\n", cfg.label.c_str(),
              lap->c.mesh.num_dofs(), mi.model.num_points(), f1, mi.kept_modes, seconds_since(t_start));
  // The HB model's points are the interface's points in order (one interface).
  const auto& geometry = lap->model.interfaces.at(0).geometry;
  for (int p = 0; p < geometry.num_points(); ++p)
    if (std::abs(geometry.points[static_cast<std::size_t>(p)].area - mi.model.areas[p]) >
        1e-12 * mi.model.areas[p]) {
      std::printf("point %d: HB and FE areas differ\n", p);
      sum.ok = false;
      return sum;
    }

  // Backbone to the target drop: q*, Ω_bb, ζ(q*); the phase-resonant force.
  const double drop_target = 0.02;
  continuation::InterfaceBackboneOptions bo;
  bo.mode.mode = 1;
  bo.mode.balance.harmonics = 1;
  bo.mode.balance.time_samples = 32;
  bo.log10_amplitude_start = -9.0;
  bo.log10_amplitude_end = -3.0;
  bo.continuation.max_points = 200;
  hb::InterfaceModeState star;
  const auto bb = continuation::trace_interface_backbone(mi.model, bo, [&](const continuation::InterfaceBackbonePoint& pt) {
    star = pt.state;
    return pt.state.omega / kTwoPi > (1.0 - drop_target) * f1;
  });
  const int followed = mi.model.rigid_modes;
  const double phi_f = std::abs(mi.model.load_modal[followed]);
  const double force = 2.0 * star.damping_ratio * star.omega * star.omega * star.amplitude / phi_f;
  std::printf("  backbone (H = 1): %zu points; at q* = %.4e: f = %.3f Hz (drop %.2f %%), zeta = %.4f, "
              "%d of %d points slipping -> F = %.4g N\n",
              bb.points.size(), star.amplitude, star.omega / kTwoPi, 100.0 * (1.0 - star.omega / kTwoPi / f1),
              star.damping_ratio, star.slipping_points, mi.model.num_points(), force);

  timeint::FeNewmarkOptions nm;
  nm.stiffness_damping = rayleigh_b;
  nm.preloaded_tangential_stiffness = true;

  for (double ratio : cfg.ratios) {
    const double omega = ratio * star.omega;
    std::vector<Measure> rows;
    // Reduction error: stuck linear response of the modal/interface model vs the full model.
    double reduction_error = 0.0;
    {
      hb::InterfaceBalance b1(mi.model, {.harmonics = 1, .time_samples = 16});
      const VectorXd load = b1.cosine_load(1.0);
      const VectorXd y = b1.linear_solution(omega, load);
      const VectorXd uo = b1.output_coefficients(0, y, omega, 0.0, load, MatrixXd::Zero(3, 3 * b1.points()));
      Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(lap->c.mesh.num_dofs());
      rhs[lap->drive_dof()] = 1.0;
      const Complex x_full = full_response(*lap, omega, rayleigh_b, rhs)[lap->drive_dof()];
      reduction_error = std::abs(Complex(uo[1], -uo[2]) - x_full) / std::abs(x_full);
      sum.worst_reduction = std::max(sum.worst_reduction, reduction_error);
    }
    // HB at each H (each from its own load ramp).
    std::vector<HbSolution> hbs;
    std::vector<std::unique_ptr<hb::InterfaceBalance>> balances;
    for (int h : cfg.harmonics) {
      balances.push_back(std::make_unique<hb::InterfaceBalance>(
          mi.model, hb::InterfaceBalanceOptions{.harmonics = h, .time_samples = std::max(32, 16 * h)}));
      HbSolution s = solve_hb(*balances.back(), omega, force, nullptr);
      Measure m;
      if (s.ok) m = from_coefficients("", s.output[1], s.output[2]);
      m.method = fmt::format("HB H={}", h);
      m.ok = s.ok;
      m.message = s.message;
      m.seconds = s.seconds;
      m.iterations = s.iterations;
      if (s.ok) {
        m.external_work = kPi * force * s.output[2];
        m.dissipation = s.e.dissipation;
      } else {
        std::printf("  HB H=%d at %.3f Hz failed: %s\n", h, omega / kTwoPi, s.message.c_str());
        sum.ok = false;
      }
      rows.push_back(m);
      hbs.push_back(std::move(s));
    }
    // Newmark from the HB solution at the largest H, N·2^level steps per period.
    const std::size_t best = hbs.size() - 1;
    std::vector<Measure> nm_runs;
    for (int level = 0; level < cfg.levels && hbs[best].ok; ++level) {
      const int steps = cfg.steps << level;
      timeint::FeSteadyStateOptions so;
      so.steps_per_period = steps;
      so.harmonics = 3;
      so.tolerance = cfg.tolerance;
      so.max_periods = cfg.max_periods;
      so.output_dofs = {lap->drive_dof()};
      so.integrator = nm;
      std::vector<double> changes;
      so.progress = [&](int, double change) { changes.push_back(change); };
      timeint::FeExcitation ex;
      ex.forces.push_back({lap->drive_dof(), force});
      const timeint::FeState start =
          newmark_start(*lap, *balances[best], hbs[best], omega, force, rayleigh_b, steps, nm);
      const auto r = timeint::fe_forced_steady_state(lap->model, lap->preload, ex, omega, so, start);
      Measure m;
      if (r.termination != Termination::failed) m = from_coefficients("", r.coefficients(0, 1), r.coefficients(0, 2));
      m.method = fmt::format("NM N={}", steps);
      m.ok = r.termination == Termination::converged;
      m.message = r.message;
      m.seconds = r.seconds;
      m.iterations = r.periods;
      m.change = r.change;
      if (r.termination != Termination::failed) {
        m.external_work = r.external_work;
        m.dissipation = r.contact_dissipation.at(0);
        // Remaining transient: geometric decay of the period changes, ρ over the last 5 periods
        // (a change that has stopped falling, ρ → 1, is creep, not a decaying transient: the
        // estimate then overstates it).
        const std::size_t c = changes.size();
        double rho = c >= 6 ? std::pow(changes[c - 1] / changes[c - 6], 1.0 / 5.0) : 0.9;
        rho = std::min(rho, 0.99);
        m.transient = changes.empty() ? 0.0 : changes.back() * rho / (1.0 - rho);
      }
      if (!m.ok) {
        std::printf("  Newmark N=%d at %.3f Hz: %s\n", steps, omega / kTwoPi, r.message.c_str());
        sum.ok = false;
      }
      std::printf("  NM N=%d: %s, %.1f s (%.2f ms/step, %.2f Newton it/step), transient est. %.1e\n", steps,
                  r.message.c_str(), r.seconds, 1e3 * r.seconds_per_step,
                  static_cast<double>(r.newton_iterations) / static_cast<double>(std::max(1L, r.steps)),
                  m.transient);
      std::fflush(stdout);
      nm_runs.push_back(m);
      rows.push_back(m);
    }
    if (nm_runs.size() < 2) {
      sum.ok = false;
      continue;
    }
    // Richardson (Δt²) from the two finest levels: x_2N + (x_2N − x_N)/3, per complex amplitude
    // and per energy; with three levels the observed order log2(|x_N − x_2N| / |x_2N − x_4N|).
    const Measure& a = nm_runs[nm_runs.size() - 2];
    const Measure& c = nm_runs.back();
    const auto phasor = [](const Measure& m) { return std::polar(m.amplitude, -m.phase); };
    Measure ref;
    ref.method = "NM extrapolated";
    {
      const Complex xa = phasor(a), xc = phasor(c);
      const Complex xr = xc + (xc - xa) / 3.0;
      ref.amplitude = std::abs(xr);
      ref.phase = -std::arg(xr);
      ref.external_work = c.external_work + (c.external_work - a.external_work) / 3.0;
      ref.dissipation = c.dissipation + (c.dissipation - a.dissipation) / 3.0;
      ref.ok = a.ok && c.ok;
      rows.push_back(ref);
      sum.worst_dt_amp = std::max(sum.worst_dt_amp, relative(c.amplitude, ref.amplitude));
      for (const Measure& m : nm_runs) sum.worst_transient = std::max(sum.worst_transient, m.transient);
      if (nm_runs.size() >= 3) {
        const Measure& z = nm_runs[nm_runs.size() - 3];
        const double order_x = std::log2(std::abs(phasor(z) - xa) / std::abs(xa - xc));
        const double order_w = std::log2(std::abs(z.dissipation - a.dissipation) / std::abs(a.dissipation - c.dissipation));
        std::printf("  observed Newmark order (N = %d, %d, %d): X1 %.2f, W_D %.2f\n", cfg.steps,
                    2 * cfg.steps, 4 * cfg.steps, order_x, order_w);
        if (order_csv)
          std::fprintf(order_csv, "%s,%.10g,%.6f,%d,%.4f,%.4f\n", cfg.label.c_str(), omega / kTwoPi, ratio, cfg.steps,
                       order_x, order_w);
      }
    }
    std::printf("  f = %.3f Hz (%.3f Ω_bb), F = %.4g N, stuck-model reduction error %.2e\n", omega / kTwoPi,
                ratio, force, reduction_error);
    std::printf("    %-16s %12s %10s %12s %12s   %9s %9s %9s %9s\n", "method", "|X1| [m]", "phase", "W_ext [J]",
                "W_D [J]", "e|X1|", "e_phase", "e_Wext", "e_WD");
    for (const Measure& m : rows) {
      const double ea = relative(m.amplitude, ref.amplitude), ep = std::abs(m.phase - ref.phase),
                   ew = relative(m.external_work, ref.external_work), ed = relative(m.dissipation, ref.dissipation);
      std::printf("    %-16s %12.6e %10.6f %12.6e %12.6e   %9.2e %9.2e %9.2e %9.2e\n", m.method.c_str(), m.amplitude,
                  m.phase, m.external_work, m.dissipation, ea, ep, ew, ed);
      if (points_csv)
        std::fprintf(points_csv, "%s,%.10g,%.6f,%.8g,%s,%.10e,%.10f,%.10e,%.10e,%.3e,%.3e,%.3e,%.3e,%.3e,%d,%.3e,%.3e,%.2f,%d\n",
                     cfg.label.c_str(), omega / kTwoPi, ratio, force, m.method.c_str(), m.amplitude, m.phase,
                     m.external_work, m.dissipation, ea, ep, ew, ed, reduction_error, m.iterations, m.change,
                     m.transient, m.seconds, m.ok ? 1 : 0);
    }
    if (points_csv) std::fflush(points_csv);
    sum.best_h1_amp = std::min(sum.best_h1_amp, relative(rows[0].amplitude, ref.amplitude));
    // The best H against the time-exact reference.
    const Measure& h = rows[best];
    sum.worst_hb_amp = std::max(sum.worst_hb_amp, relative(h.amplitude, ref.amplitude));
    sum.worst_hb_phase = std::max(sum.worst_hb_phase, std::abs(h.phase - ref.phase));
    sum.worst_hb_wext = std::max(sum.worst_hb_wext, relative(h.external_work, ref.external_work));
    sum.worst_hb_wd = std::max(sum.worst_hb_wd, relative(h.dissipation, ref.dissipation));
  }
  std::printf("%s: %.1f s\n", cfg.label.c_str(), seconds_since(t_start));
  return sum;
}

}  // namespace

int run(int argc, char** argv) {
  const validation_study::Arguments args = validation_study::parse_arguments(argc, argv);
  if (!args.ok) return 2;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress lines of a long run
  std::vector<Config> configs;
  if (args.ci) {
    configs.push_back({.label = "10x3x1", .harmonics = {1, 3}, .ratios = {1.0}});
  } else {
    configs.push_back({.label = "10x3x1", .harmonics = {1, 3, 5, 7}, .ratios = {0.97, 0.985, 1.0, 1.015, 1.03},
                       .levels = 3});
    // The 192-point mesh at H = 1 only: its dense HB Jacobian at H = 3 (4172 unknowns) costs about
    // a minute per LU on this machine.
    configs.push_back({.label = "20x6x1", .nx = 20, .ny = 6, .nz = 1, .radius = 0.0045, .harmonics = {1},
                       .ratios = {1.0}});
  }
  std::FILE* points = std::fopen((args.prefix + "_points.csv").c_str(), "w");
  if (points)
    std::fprintf(points, "mesh,frequency_hz,omega_ratio,force_N,method,amplitude_m,phase_rad,external_work_J,"
                         "friction_dissipation_J,err_amplitude,err_phase_rad,err_external_work,err_dissipation,"
                         "reduction_error,iterations_or_periods,period_change,transient_estimate,seconds,ok\n");
  std::FILE* order = std::fopen((args.prefix + "_newmark_order.csv").c_str(), "w");
  if (order) std::fprintf(order, "mesh,frequency_hz,omega_ratio,steps_N,order_amplitude,order_dissipation\n");
  std::FILE* summary = std::fopen((args.prefix + "_summary.csv").c_str(), "w");
  if (summary)
    std::fprintf(summary, "mesh,hb_amplitude_error,hb_phase_error_rad,hb_external_work_error,hb_dissipation_error,"
                          "newmark_2N_amplitude_error,transient_estimate,reduction_error,ok\n");
  bool ok = true;
  for (const Config& c : configs) {
    const Summary s = run(c, points, order);
    std::fflush(stdout);
    std::printf("%s: best H vs time-exact Newmark: |X1| %.2e, phase %.2e rad, W_ext %.2e, W_D %.2e; Newmark(2N) "
                "|X1| %.2e; transient %.1e; reduction %.2e\n",
                c.label.c_str(), s.worst_hb_amp, s.worst_hb_phase, s.worst_hb_wext, s.worst_hb_wd, s.worst_dt_amp,
                s.worst_transient, s.worst_reduction);
    if (summary)
      std::fprintf(summary, "%s,%.3e,%.3e,%.3e,%.3e,%.3e,%.3e,%.3e,%d\n", c.label.c_str(), s.worst_hb_amp,
                   s.worst_hb_phase, s.worst_hb_wext, s.worst_hb_wd, s.worst_dt_amp, s.worst_transient,
                   s.worst_reduction, s.ok ? 1 : 0);
    // Bounds (README: measured 10 × 3 × 1, H = 3 at resonance: |X1| 6.5e-3, phase 2.5e-2 rad,
    // W_ext 4.6e-3, W_D 2.0e-2): HB with the largest H within these of the time-exact Newmark,
    // and closer than H = 1 at every frequency.
    // A configuration run at H = 1 only (the 192-point mesh) is reported, not scored: H = 1 is
    // 13 % off there (README).
    ok = ok && s.ok;
    if (c.harmonics.back() >= 3)
      ok = ok && s.worst_hb_amp < 0.02 && s.worst_hb_phase < 0.05 && s.worst_hb_wext < 0.02 &&
           s.worst_hb_wd < 0.05 && s.worst_hb_amp < s.best_h1_amp;
  }
  if (points) std::fclose(points);
  if (summary) std::fclose(summary);
  if (order) std::fclose(order);
  std::printf("%s\n", ok ? "lap_hb_vs_newmark: all bounds met" : "lap_hb_vs_newmark: a bound was exceeded");
  return ok ? 0 : 1;
}

}  // namespace jointhb_study_fe_lap_hb_vs_newmark
