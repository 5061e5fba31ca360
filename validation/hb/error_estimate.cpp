// The error estimates of discrete damping-curve and FRF points (continuation/error_estimate.hpp,
// docs/theory.md §13, T-41, T-42) against the TRUE errors (README_error_estimate.md).
//
// Description: every point is solved at exactly its parameter (λ = log10 q of a damping curve,
// Ω of an FRF) by the curve driver itself (trace_backbone / trace_frf with max_points = 1: Newton
// from the linear start at that parameter), so that its `error` is the estimate the driver
// reports. Its true errors (tests/unit/continuation/error_reference.hpp): Newton at the same
// parameter at (H, N_ref = 2048) gives the aliasing part, at (H_ref = 63, N_ref) the total; the
// truncation part is their difference. All relative to the point's value.
// Models (as epmc_convergence.cpp): m = 1, k = 1e4, one contact to ground k_T0 = 3e4, μF_N = 1,
// ζ = 0.2 % of the stuck system:
//   jenkins     Jenkins (slip at |x| = 3.33e-5)      q = 1e-5 (stuck), 4e-5, 1.2e-4, 1e-3
//   gm          Gaul–Mayer n = 1/3 (g_max = 5e-5)    q = 5e-6, 1.2e-4, 1e-3
//   2dof-*      the 2-DOF system of tests/unit/hb/test_nonlinear_mode.cpp (K = [2 −1; −1 2],
//               C = 0.01 K, contact 0–1 k_T0 = 1, μF_N = 0.01, contact 1–ground k_T0 = 0.5)
//               q = 3e-3, 1e-2, 3e-2, 1e-1
//   frf-jenkins / frf-gm: the 1-DOF models forced by F cos Ωt, F = 0.5 (< 4μF_N/π: bounded by
//               friction), Ω = 150, 190, 200, 230 rad/s
// at H = 1, 3, 5, 7 and N_t = 256 (and N_t = 2H + 2, the smallest allowed, for the aliasing
// estimate). Columns: the estimates, the true errors and their ratios (estimate/true) per output.
//
// Bounds (exit code 1 when one is exceeded; README_error_estimate.md gives the measured
// brackets): every point and reference solves (except FRF starts at N_t = 2H + 2, listed as
// skipped); where the true total error exceeds 1e-8 and one source dominates (the other's true
// part < 10 % of it), the truncation estimate is within a factor kTruncationFactor of the true part
// with the right sign, and for H ≤ 3 the aliasing estimate within kAliasingFactor (for H = 5, 7 at
// N_t = 2H + 2 the sampling error is not monotone in N_t and one doubling can miss it by 10–25×:
// listed, not scored); at N_t = 2H + 2 on a slipping 1-DOF Jenkins point the aliasing estimate of
// Ω or ζ exceeds 1e-4; at N_t = 256 every aliasing estimate is below 1e-3.
// --ci: H = 1, 3; the jenkins, gm and frf-jenkins models at two amplitudes each.
//
// Sample run:
//   build/validation/hb/jointhb_validate_hb_error_estimate validation/hb/results/error_estimate

#include <optional>

#include "../../tests/unit/continuation/error_reference.hpp"
#include "jointhb/continuation/backbone.hpp"
#include "jointhb/continuation/error_estimate.hpp"
#include "jointhb/continuation/frf.hpp"
#include "study_common.hpp"

// The study is one function of the multi-call program jointhb_validate_hb (CMakeLists.txt).
namespace jointhb_study_hb_error_estimate {

namespace {

using namespace validation_study;
namespace reference = jointhb::error_reference;

// estimate/true within [1/factor, factor] where the source dominates (measured: truncation
// 0.37–3.3, aliasing at H ≤ 3 0.14–2.3)
constexpr double kTruncationFactor = 5.0;
constexpr double kAliasingFactor = 10.0;
constexpr double kAbove = 1e-8;  // true errors below this are round-off/tolerance level

struct Model {
  std::string name;
  hb::DiscreteSystem system;
  std::vector<double> parameters;  // q (damping curves) or Ω (FRF)
  bool frf = false;
  bool jenkins_slips(double q) const { return name == "jenkins" && q > 3.4e-5; }
};

hb::DiscreteSystem one_dof(const std::string& law) {
  ContactSpec spec;
  spec.law = law;
  spec.exponent = 1.0 / 3.0;
  spec.stiffness = 3e4;
  spec.slip_limit = 1.0;
  return oscillator(spec, 0.002, 1.0, 1e4);
}

hb::DiscreteSystem two_dof(const std::string& law) {
  hb::DiscreteSystem s;
  MatrixXd k(2, 2);
  k << 2.0, -1.0, -1.0, 2.0;
  s.mass = sparse(MatrixXd::Identity(2, 2));
  s.stiffness = sparse(k);
  s.damping = sparse(0.01 * k);
  ContactSpec spec;
  spec.law = law;
  spec.exponent = 0.4;
  spec.stiffness = 1.0;
  spec.slip_limit = 0.01;
  s.contacts.push_back(contact_element(spec, 0, 1));
  spec.stiffness = 0.5;
  s.contacts.push_back(contact_element(spec, 1, -1));
  return s;
}

struct Row {
  std::string output;
  cont::ErrorPair estimate;
  reference::TrueError truth;
};

// Writes one row per output and scores it.
void score_rows(const std::string& where, const std::vector<Row>& rows, int h, int samples,
                bool slipping_jenkins, Csv& csv, Scorecard& score,
                std::vector<std::string>& summary) {
  const auto ratio = [](double estimate, double truth) {
    return truth != 0.0 ? estimate / truth : 0.0;
  };
  bool alias_large = false;
  for (const Row& r : rows) {
    const double total = r.estimate.truncation + r.estimate.aliasing;
    csv.row({csv_text(where), csv_text(r.output), std::to_string(h), std::to_string(samples),
             csv_number(r.estimate.truncation), csv_number(r.truth.truncation),
             csv_number(ratio(r.estimate.truncation, r.truth.truncation)),
             csv_number(r.estimate.aliasing), csv_number(r.truth.aliasing),
             csv_number(ratio(r.estimate.aliasing, r.truth.aliasing)), csv_number(total),
             csv_number(r.truth.total), csv_number(ratio(total, r.truth.total))});
    summary.push_back(
        fmt::format("  {:<34} {:<13} H={} N_t={:<4} trunc {:>10.2e}/{:>10.2e} = {:>6.2f}   "
                    "alias {:>10.2e}/{:>10.2e} = {:>6.2f}",
                    where, r.output, h, samples, r.estimate.truncation, r.truth.truncation,
                    ratio(r.estimate.truncation, r.truth.truncation), r.estimate.aliasing,
                    r.truth.aliasing, ratio(r.estimate.aliasing, r.truth.aliasing)));
    const double t = std::abs(r.truth.total);
    const auto within = [&](double estimate, double truth, double factor, const char* what) {
      const double q = ratio(estimate, truth);
      score.check(q >= 1.0 / factor && q <= factor,
                  fmt::format("{} {} H={} N_t={}: {} estimate {:.3e} against true {:.3e}", where,
                              r.output, h, samples, what, estimate, truth));
    };
    if (t > kAbove && std::abs(r.truth.aliasing) < 0.1 * std::abs(r.truth.truncation))
      within(r.estimate.truncation, r.truth.truncation, kTruncationFactor, "truncation");
    if (t > kAbove && h <= 3 && std::abs(r.truth.truncation) < 0.1 * std::abs(r.truth.aliasing))
      within(r.estimate.aliasing, r.truth.aliasing, kAliasingFactor, "aliasing");
    alias_large = alias_large || std::abs(r.estimate.aliasing) > 1e-4;
    if (samples >= 256) {
      score.check(std::abs(r.estimate.aliasing) < 1e-3,
                  fmt::format("{} {} H={} N_t={}: aliasing estimate {:.3e} at ample sampling",
                              where, r.output, h, samples, r.estimate.aliasing));
    }
  }
  if (slipping_jenkins && samples == 2 * h + 2) {
    score.check(alias_large,
                fmt::format("{} H={} N_t={}: the aliasing estimate does not flag N_t = 2H + 2",
                            where, h, samples));
  }
}

void study_mode(const Model& m, double q, int h, int samples, Csv& csv, Scorecard& score,
                std::vector<std::string>& summary) {
  const cont::BackboneOptions o = reference::single_point_options(q, h, samples);
  const std::string where = fmt::format("{} q={:.3g}", m.name, q);
  const cont::BackboneCurve c = cont::trace_backbone(m.system, o);
  if (!score.check(c.points.size() == 1 && c.points[0].error.known,
                   fmt::format("{} H={} N_t={}: point or estimate not computed ({})", where, h,
                               samples, c.message)))
    return;
  const cont::BackbonePoint& p = c.points[0];
  const reference::ModeTruth t =
      reference::mode_truth(m.system, o.mode, p.unknowns, o.log10_amplitude_start);
  if (!score.check(t.ok, fmt::format("{} H={} N_t={}: reference not solved", where, h, samples)))
    return;
  score_rows(where, {{"omega", p.error.omega, t.omega}, {"damping", p.error.damping, t.damping}}, h,
             samples, m.jenkins_slips(q), csv, score, summary);
}

void study_frf(const Model& m, double omega, int h, int samples, Csv& csv, Scorecard& score,
               std::vector<std::string>& summary) {
  cont::FrfOptions o;
  o.omega_start = omega;
  o.omega_end = omega + 1.0;
  o.harmonics = h;
  o.time_samples = samples;
  o.stability = cont::Stability::never;
  o.refine_extrema = false;
  o.continuation.max_points = 1;
  o.continuation.residual_tolerance = 1e-13;
  const hb::Excitation e = cosine_force(0, 0.5);
  const std::string where = fmt::format("{} Omega={:.4g}", m.name, omega);
  const cont::FrfCurve c = cont::trace_frf(m.system, e, o);
  if (c.points.empty() && samples == 2 * h + 2) {
    // The FRF's start does not converge with the fewest samples here (the force ramp stalls): not
    // the estimate's failure; listed, not scored.
    summary.push_back(
        fmt::format("  {:<34} H={} N_t={}: no point (start failed), skipped", where, h, samples));
    return;
  }
  if (!score.check(c.points.size() == 1 && c.points[0].error.known,
                   fmt::format("{} H={} N_t={}: point or estimate not computed ({})", where, h,
                               samples, c.message)))
    return;
  const cont::FrfPoint& p = c.points[0];
  hb::HarmonicBalanceOptions bo;
  bo.harmonics = h;
  bo.time_samples = samples;
  const reference::FrfTruth t =
      reference::frf_truth(m.system, e, bo, p.coefficients, omega, 0, 0.5);
  if (!score.check(t.ok, fmt::format("{} H={} N_t={}: reference not solved", where, h, samples)))
    return;
  score_rows(where,
             {{"amplitude_h1", p.error.amplitude_h1, t.amplitude_h1},
              {"amplitude_max", p.error.amplitude_max, t.amplitude_max}},
             h, samples, false, csv, score, summary);
}

}  // namespace

int run(int argc, char** argv) {
  const Arguments args = parse_arguments(argc, argv);
  if (!args.ok) return 2;
  Scorecard score;
  const auto start = Clock::now();
  std::vector<std::string> summary;
  Csv csv(args.prefix + "_points.csv",
          {"point", "output", "H", "N_t", "truncation_estimate", "truncation_true",
           "truncation_ratio", "aliasing_estimate", "aliasing_true", "aliasing_ratio",
           "total_estimate", "total_true", "total_ratio"});
  std::vector<Model> models = {
      {"jenkins", one_dof("jenkins"), {1e-5, 4e-5, 1.2e-4, 1e-3}},
      {"gm", one_dof("gaul-mayer"), {5e-6, 1.2e-4, 1e-3}},
      {"2dof-jenkins", two_dof("jenkins"), {3e-3, 1e-2, 3e-2, 1e-1}},
      {"2dof-gm", two_dof("gaul-mayer"), {3e-3, 1e-2, 3e-2, 1e-1}},
      {"frf-jenkins", one_dof("jenkins"), {150.0, 190.0, 200.0, 230.0}, true},
      {"frf-gm", one_dof("gaul-mayer"), {150.0, 190.0, 200.0, 230.0}, true},
  };
  if (args.ci) {
    models = {{"jenkins", one_dof("jenkins"), {4e-5, 1e-3}},
              {"gm", one_dof("gaul-mayer"), {1.2e-4, 1e-3}},
              {"frf-jenkins", one_dof("jenkins"), {190.0, 230.0}, true}};
  }
  const std::vector<int> hs = args.ci ? std::vector<int>{1, 3} : std::vector<int>{1, 3, 5, 7};
  summary.push_back("estimate / true (relative, signed) per point:");
  for (const Model& m : models) {
    for (const double parameter : m.parameters) {
      for (const int h : hs) {
        for (const int samples : {256, 2 * h + 2}) {
          if (m.frf)
            study_frf(m, parameter, h, samples, csv, score, summary);
          else
            study_mode(m, parameter, h, samples, csv, score, summary);
        }
      }
    }
  }
  for (const auto& line : summary) fmt::print("{}\n", line);
  fmt::print("total {:.2f} s\n", seconds_since(start));
  return score.finish();
}

}  // namespace jointhb_study_hb_error_estimate
