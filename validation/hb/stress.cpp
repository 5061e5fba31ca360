// Stress test of FRF tracing (continuation::trace_frf) on hard inputs: every run completes or stops
// with a clear message, and never returns NaN.
//
// Description: 1-DOF friction oscillators m ẍ + c ẋ + k x + F_T = F cos Ωt (m = 1, k = 1, one
// contact to ground, μF_N = 1, c = 2ζ√(k + k_T0)), unless stated otherwise, traced over
// Ω ∈ [0.5 ω_free, 1.5 ω_stuck] (ω_free = √(k/m), ω_stuck = √((k + k_T0)/m)) with H = 7,
// N_t = 128 and the continuation defaults. Scenarios:
//   * very light damping ζ = 1e-4 (sharp peaks): stuck (F = 1e-4), slipping (F = 0.5), Gaul–Mayer;
//   * near gross slip: F/μF_N ∈ {1.2, 4/π, 1.35} at ζ = 0.005 (above 4/π the friction force can no
//     longer bound the resonance: only viscous damping does);
//   * fully stuck (F = 1e-6 μF_N) and the force sweep F/μF_N ∈ {1e-6, 1e-4, 1e-2, 0.1, 1, 10, 1e2,
//     1e3} for Jenkins and {1e-6, 1e-2, 1, 1e3} for Gaul–Mayer (n = 1/3);
//   * k_T0/k ∈ {1e-3, 1e-1, 1, 1e2, 1e4, 1e6} at F = 0.3 μF_N (Jenkins);
//   * Gaul–Mayer with n = 0.05 and 0.95 at F/μF_N ∈ {1e-3, 0.5, 10};
//   * folds: a 2-DOF system (two unit masses, springs k = 1 to ground and between them, a Jenkins
//     contact from DOF 1 to ground with k_T0 = 4), ζ = 0.005, F on DOF 0, whose softening FRF turns
//     back on itself; a 10-DOF chain with 5 contacts (Jenkins and Gaul–Mayer);
//   * SI magnitudes: m = 0.1 kg, k = 1e6 N/m, k_T0 = 1e7 N/m, μF_N = 30 N, F = 10 N
//     (Ω ~ 1e4 rad/s, x ~ 1e-5 m), and H = 21, N_t = 512 on the base case.
// Each accepted point is re-evaluated with HarmonicBalance (same H, N_t): ‖R‖_∞/‖F‖_∞ is compared
// with the continuation's acceptance test (docs/continuation.md §2: ≤ residual_tolerance, or
// ≤ 1e3 residual_tolerance after a Newton step below step_tolerance).
//
// Bounds (exit code 1 when one is exceeded): every run either completes or stops with a non-empty
// message; no NaN or infinity in any accepted point (Ω, coefficients, amplitudes, W_D); every
// accepted point's re-evaluated residual ≤ residual_tolerance (the continuation may accept up to
// 1e3 × that after a Newton step below step_tolerance; no point in these scenarios needs it:
// measured max 1.0 × tolerance); the scenarios not marked expect_complete = false complete (since
// issue 23 all 45 are expected to). The six stops of the original run (README_convergence.md,
// "Stress"), when marked as known stops, are rerun with max_points = 20000 and with
// 4 N_t to tell a point budget from a failed step; a fold flag is checked for a branch that
// retraces itself (points after it on the curve traced before it).
// --ci: the same scenarios except the H = 21 case and the largest k_T0/k (the two slowest runs).
//
// Sample runs:
//   build-val/validation/hb/jointhb_validate_hb_stress validation/hb/results/stress

#include <functional>
#include <tuple>

#include "study_common.hpp"

// The study is one function of the multi-call program jointhb_validate_hb (CMakeLists.txt).
namespace jointhb_study_hb_stress {

namespace {

using namespace validation_study;

struct Scenario {
  std::string name;
  std::string group;
  hb::DiscreteSystem system;
  hb::Excitation excitation;
  double omega_start = 0.0, omega_end = 0.0;
  int harmonics = 7;
  int samples = 128;
  int output_dof = 0;
  bool ci = true;               // part of the --ci run
  bool expect_complete = true;  // false: a known stop, investigated in README_convergence.md
};

Scenario one_dof(const std::string& name, const std::string& group, const ContactSpec& spec,
                 double zeta, double force) {
  Scenario s;
  s.name = name;
  s.group = group;
  s.system = oscillator(spec, zeta);
  s.excitation = cosine_force(0, force);
  s.omega_start = 0.5;
  s.omega_end = 1.5 * std::sqrt(1.0 + spec.stiffness);
  return s;
}

ContactSpec jenkins(double stiffness = 1.0) {
  ContactSpec c;
  c.law = "jenkins";
  c.stiffness = stiffness;
  c.slip_limit = 1.0;
  return c;
}

ContactSpec gaul_mayer(double exponent, double stiffness = 1.0) {
  ContactSpec c;
  c.law = "gaul-mayer";
  c.exponent = exponent;
  c.stiffness = stiffness;
  c.slip_limit = 1.0;
  return c;
}

std::vector<Scenario> scenarios() {
  std::vector<Scenario> list;
  // Very light damping: a sharp linear peak (stuck), the onset of slip at a peak 20× the slip
  // amplitude μF_N/k_T0, friction-limited peaks.
  for (auto [name, zeta, force] : {std::tuple{"zeta=1e-4 stuck F=1e-4", 1e-4, 1e-4},
                                   std::tuple{"zeta=1e-4 slip onset F=8e-3", 1e-4, 8e-3},
                                   std::tuple{"zeta=1e-3 slip onset F=0.08", 1e-3, 0.08}}) {
    list.push_back(one_dof(name, "light damping", jenkins(), zeta, force));
  }
  list.push_back(one_dof("zeta=1e-4 Jenkins F=0.5", "light damping", jenkins(), 1e-4, 0.5));
  list.push_back(
      one_dof("zeta=1e-4 GM n=1/3 F=0.05", "light damping", gaul_mayer(1.0 / 3.0), 1e-4, 0.05));
  // Near gross slip.
  for (const auto& [label, f] :
       {std::pair{"1.2", 1.2}, std::pair{"4/pi", 4.0 / kPi}, std::pair{"1.35", 1.35}}) {
    list.push_back(one_dof(fmt::format("near gross slip F={}", label), "near gross slip", jenkins(),
                           0.005, f));
  }
  // Force sweep (fully stuck at the smallest).
  for (const double f : {1e-6, 1e-4, 1e-2, 0.1, 1.0, 10.0, 1e2, 1e3}) {
    list.push_back(one_dof(fmt::format("Jenkins F={:g}", f), "force sweep", jenkins(), 0.02, f));
  }
  for (const double f : {1e-6, 1e-2, 1.0, 1e3}) {
    list.push_back(
        one_dof(fmt::format("GM n=1/3 F={:g}", f), "force sweep", gaul_mayer(1.0 / 3.0), 0.02, f));
  }
  // Stiffness ratio, in microslip/stick-slip (F = 0.3) and gross slip (F = 3).
  for (const double f : {0.3, 3.0}) {
    for (const double r : {1e-3, 1e-1, 1.0, 1e2, 1e4, 1e6}) {
      Scenario s =
          one_dof(fmt::format("kt0/k={:g} F={:g}", r, f), "stiffness ratio", jenkins(r), 0.02, f);
      s.ci = r < 1e6;
      list.push_back(std::move(s));
    }
  }
  // Gaul–Mayer exponents.
  for (const double n : {0.05, 0.95}) {
    for (const double f : {1e-3, 0.5, 10.0}) {
      list.push_back(
          one_dof(fmt::format("GM n={:g} F={:g}", n, f), "GM exponent", gaul_mayer(n), 0.02, f));
    }
  }
  // Folds and sharp turns: a near-Jenkins Gaul–Mayer contact (n = 0.05) with a stiff contact,
  // whose friction-limited peak has a sharp, jagged top; a 2-DOF system with a stiff Jenkins
  // contact on DOF 1.
  {
    Scenario s = one_dof("GM n=0.05 kt0/k=10 F=1.2", "folds", gaul_mayer(0.05, 10.0), 0.01, 1.2);
    s.harmonics = 5;
    s.samples = 64;
    list.push_back(std::move(s));
  }
  for (const double f : {0.3, 0.6}) {
    Scenario s;
    s.name = fmt::format("2dof F={:g}", f);
    s.group = "folds";
    MatrixXd k(2, 2);
    k << 2.0, -1.0, -1.0, 2.0;
    s.system.mass = sparse(MatrixXd::Identity(2, 2));
    s.system.stiffness = sparse(k);
    s.system.contacts.push_back(contact_element(jenkins(4.0), 1));
    s.system.damping =
        hb::modal_damping_matrix(s.system.mass, hb::stuck_stiffness(s.system), {0.005, 0.005});
    s.excitation = cosine_force(0, f);
    s.omega_start = 0.5;
    s.omega_end = 3.5;
    list.push_back(std::move(s));
  }
  // 10-DOF chain with 5 contacts.
  for (const auto& spec : {jenkins(2.0), gaul_mayer(1.0 / 3.0, 2.0)}) {
    Scenario s;
    s.name = fmt::format("10dof chain {} F=0.5", spec.law);
    s.group = "chain";
    s.system = chain(10, 1.0, spec, {{1, -1}, {3, 2}, {5, -1}, {7, 6}, {9, -1}}, 0.02);
    s.excitation = cosine_force(9, 0.5);
    s.omega_start = 0.1;
    s.omega_end = 2.5;
    s.output_dof = 9;
    list.push_back(std::move(s));
  }
  // SI magnitudes.
  {
    ContactSpec c = jenkins(1e7);
    c.slip_limit = 30.0;
    Scenario s;
    s.name = "SI magnitudes";
    s.group = "scaling";
    s.system = oscillator(c, 0.02, 0.1, 1e6);
    s.excitation = cosine_force(0, 10.0);
    s.omega_start = 0.5 * std::sqrt(1e6 / 0.1);
    s.omega_end = 1.5 * std::sqrt(1.1e7 / 0.1);
    list.push_back(std::move(s));
  }
  {
    Scenario s = one_dof("H=21 N_t=512 F=0.5", "scaling", jenkins(), 0.02, 0.5);
    s.harmonics = 21;
    s.samples = 512;
    s.ci = false;
    list.push_back(std::move(s));
  }
  return list;
}

struct Outcome {
  cont::FrfCurve curve;
  double seconds = 0.0;
  bool finite = true;
  double max_x = 0.0;         // max over points of max_t |x_out(t)|
  double max_residual = 0.0;  // max ‖R‖_∞ / r_s (re-evaluated) over the points
  int relaxed = 0;            // points with tol < residual ≤ 1e3 tol
  int folds = 0;
  double peak_omega = 0.0;
  double max_dissipation = 0.0;
  bool any_slip = false;
  // After a fold flag: how many of the following points lie on the part of the curve traced
  // before it (|X_1| within 2 % of the earlier curve, interpolated, at the same Ω): a branch that
  // retraces itself, not a genuine turning point.
  int retraced = 0, after_fold = 0;
  // Diagnosis of a run that did not complete: the same run with max_points = 20000, and with
  // 4 N_t.
  std::string retry_points, retry_samples;
};

// Linear interpolation of |X_1|(Ω) along points [0, end) where Ω is bracketed by a monotone
// piece; NaN when Ω is not covered.
double curve_amplitude_at(const std::vector<cont::FrfPoint>& p, std::size_t end, double omega) {
  for (std::size_t i = 1; i < end; ++i) {
    const double a = p[i - 1].omega, b = p[i].omega;
    if ((omega - a) * (omega - b) <= 0.0 && a != b) {
      const double t = (omega - a) / (b - a);
      return p[i - 1].amplitude_h1 + t * (p[i].amplitude_h1 - p[i - 1].amplitude_h1);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

std::string retry(const Scenario& s, cont::FrfOptions o) {
  const cont::FrfCurve c = cont::trace_frf(s.system, s.excitation, o);
  return fmt::format("{} ({} points)", c.completed() ? "completes" : "stops: " + c.message,
                     c.points.size());
}

Outcome run(const Scenario& s) {
  cont::FrfOptions o;
  o.omega_start = s.omega_start;
  o.omega_end = s.omega_end;
  o.harmonics = s.harmonics;
  o.time_samples = s.samples;
  o.output_dof = s.output_dof;
  // The continuation is what is stressed here: neither the Floquet multipliers nor the error
  // estimates of the points, which have studies of their own (stability_shooting,
  // error_estimate) and which the `seconds` column would otherwise mostly measure (the
  // monodromy of every point of the 10-DOF chains).
  o.stability = cont::Stability::never;
  o.error_estimate = false;
  Outcome out;
  const auto start = Clock::now();
  out.curve = cont::trace_frf(s.system, s.excitation, o);
  out.seconds = seconds_since(start);

  hb::HarmonicBalanceOptions ho;
  ho.harmonics = s.harmonics;
  ho.time_samples = s.samples;
  const hb::HarmonicBalance balance(s.system, s.excitation, ho);
  const double scale = force_scale(balance);
  const double tol = o.continuation.residual_tolerance;
  hb::HarmonicBalanceEvaluation ev;
  double best = -1.0;
  for (const auto& p : out.curve.points) {
    const bool finite = std::isfinite(p.omega) && std::isfinite(p.amplitude_h1) &&
                        std::isfinite(p.amplitude_max) && std::isfinite(p.dissipation) &&
                        p.coefficients.allFinite();
    out.finite = out.finite && finite;
    if (!finite) continue;
    balance.evaluate(p.coefficients, p.omega, false, ev);
    const double r = ev.residual.lpNorm<Eigen::Infinity>() / scale;
    out.max_residual = std::max(out.max_residual, std::isfinite(r) ? r : 1e300);
    if (r > tol) ++out.relaxed;
    for (const auto& d : ev.contacts) out.any_slip = out.any_slip || !d.stuck;
    out.max_x = std::max(out.max_x, p.amplitude_max);
    out.folds += p.fold ? 1 : 0;
    out.max_dissipation = std::max(out.max_dissipation, p.dissipation);
    if (p.amplitude_h1 > best) {
      best = p.amplitude_h1;
      out.peak_omega = p.omega;
    }
  }
  const auto& points = out.curve.points;
  for (std::size_t j = 0; j < points.size(); ++j) {
    if (!points[j].fold) continue;
    for (std::size_t i = j; i < points.size(); ++i) {
      ++out.after_fold;
      const double earlier = curve_amplitude_at(points, j - 1, points[i].omega);
      if (std::abs(points[i].amplitude_h1 / earlier - 1.0) <= 2e-2) ++out.retraced;
    }
    break;
  }
  if (!out.curve.completed()) {
    cont::FrfOptions more = o;
    more.continuation.max_points = 20000;
    out.retry_points = retry(s, more);
    cont::FrfOptions finer = o;
    finer.time_samples = 4 * o.time_samples;
    out.retry_samples = retry(s, finer);
  }
  return out;
}

}  // namespace

int run(int argc, char** argv) {
  const Arguments args = parse_arguments(argc, argv);
  if (!args.ok) return 2;
  Scorecard score;
  const auto start = Clock::now();
  const double tol = cont::Options{}.residual_tolerance;

  Csv table(args.prefix + "_scenarios.csv", {"scenario",
                                             "group",
                                             "dofs",
                                             "H",
                                             "N_t",
                                             "omega_start",
                                             "omega_end",
                                             "completed",
                                             "reason",
                                             "message",
                                             "points",
                                             "folds",
                                             "rejected_steps",
                                             "newton_iterations",
                                             "all_finite",
                                             "max_abs_x",
                                             "peak_omega",
                                             "max_W_D",
                                             "contacts_slip",
                                             "max_residual_over_tolerance",
                                             "points_above_tolerance",
                                             "points_after_fold",
                                             "points_retraced",
                                             "expected_to_complete",
                                             "retry_max_points_20000",
                                             "retry_4x_time_samples",
                                             "seconds"});
  struct Row {
    Scenario s;
    Outcome o;
  };
  std::vector<Row> rows;
  for (Scenario& s : scenarios()) {
    if (args.ci && !s.ci) continue;
    Outcome o = run(s);
    const auto& c = o.curve;
    const std::string where = fmt::format("[{}]", s.name);
    score.check(c.completed() || !c.message.empty(),
                fmt::format("{} stopped ({}) without a message", where,
                            std::string(cont::to_string(c.reason))));
    score.check(o.finite, fmt::format("{} non-finite values in an accepted point", where));
    score.check(o.max_residual <= tol,
                fmt::format("{} re-evaluated residual {:.2e} above the tolerance {:.0e} ({} "
                            "points)",
                            where, o.max_residual, tol, o.relaxed));
    if (s.expect_complete) {
      score.check(c.completed(),
                  fmt::format("{} did not complete: {} ({} points): {}", where,
                              std::string(cont::to_string(c.reason)), c.points.size(), c.message));
    }
    table.row({csv_text(s.name),
               csv_text(s.group),
               fmt::format("{}", s.system.dofs()),
               fmt::format("{}", s.harmonics),
               fmt::format("{}", s.samples),
               csv_number(s.omega_start),
               csv_number(s.omega_end),
               c.completed() ? "1" : "0",
               std::string(cont::to_string(c.reason)),
               csv_text(c.message),
               fmt::format("{}", c.points.size()),
               fmt::format("{}", o.folds),
               fmt::format("{}", c.rejected_steps),
               fmt::format("{}", c.newton_iterations),
               o.finite ? "1" : "0",
               csv_number(o.max_x),
               csv_number(o.peak_omega),
               csv_number(o.max_dissipation),
               o.any_slip ? "1" : "0",
               csv_number(o.max_residual / tol),
               fmt::format("{}", o.relaxed),
               fmt::format("{}", o.after_fold),
               fmt::format("{}", o.retraced),
               s.expect_complete ? "1" : "0",
               csv_text(o.retry_points),
               csv_text(o.retry_samples),
               csv_number(o.seconds)});
    rows.push_back({std::move(s), std::move(o)});
  }

  fmt::print("FRF stress test{}: {} scenarios, residual tolerance {:.0e} (relative to |F|)\n\n",
             args.ci ? " (--ci)" : "", rows.size(), tol);
  fmt::print("{:<28} {:>4} {:>12} {:>6} {:>5} {:>4} {:>6} {:>10} {:>8} {:>8} {:>5} {:>7}\n",
             "scenario", "done", "reason", "points", "folds", "rej", "newton", "max|x|", "peak Om",
             "R/tol", ">tol", "time[s]");
  int completed = 0;
  for (const auto& [s, o] : rows) {
    completed += o.curve.completed() ? 1 : 0;
    fmt::print(
        "{:<28} {:>4} {:>12} {:>6} {:>5} {:>4} {:>6} {:>10.3e} {:>8.4g} {:>8.2g} {:>5} "
        "{:>7.3f}\n",
        s.name, o.curve.completed() ? "yes" : "NO", std::string(cont::to_string(o.curve.reason)),
        o.curve.points.size(), o.folds, o.curve.rejected_steps, o.curve.newton_iterations, o.max_x,
        o.peak_omega, o.max_residual / tol, o.relaxed, o.seconds);
    if (!o.curve.completed()) {
      fmt::print("    message: {}\n", o.curve.message);
      fmt::print("    {}; with max_points = 20000: {}; with 4 N_t: {}\n",
                 s.expect_complete ? "NOT EXPECTED" : "known stop", o.retry_points,
                 o.retry_samples);
    }
    if (o.folds > 0) {
      fmt::print(
          "    {} fold flag(s); {} of the {} points after the first one retrace the curve "
          "before it\n",
          o.folds, o.retraced, o.after_fold);
    }
  }
  fmt::print("\n{} of {} completed; table {}; run time {:.1f} s\n", completed, rows.size(),
             table.path(), seconds_since(start));
  return score.finish();
}

}  // namespace jointhb_study_hb_stress
