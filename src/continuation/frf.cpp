// Nonlinear FRF: harmonic balance continued over Ω (continuation/frf.hpp).
#include "jointhb/continuation/frf.hpp"

#include "../support/stopwatch.hpp"
#include "curve_refinement.hpp"
#include "frf_extrema.hpp"
#include "linear_limits.hpp"
#include "balance_adapters.hpp"
#include "phase_bridge.hpp"
#include "segmented_curve.hpp"

#include <fmt/format.h>

#include "jointhb/hb/jacobian_check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <utility>
#include <stdexcept>
#include <vector>

#include "jointhb/contact/harmonic_loop.hpp"

namespace jointhb::continuation {
namespace {

using support::Clock;
using support::seconds_since;

hb::HarmonicBalanceOptions balance_options(const FrfOptions& o) {
  hb::HarmonicBalanceOptions b;
  b.harmonics = o.harmonics;
  b.time_samples = o.time_samples;
  b.selection = o.selection;
  b.periodic_tolerance = o.periodic_tolerance;
  return b;
}

using detail::residual_of;

// A sampled linear response more than this many times the median of the sweep has met an
// undamped resonance to within round-off (a detuning ~1e-6 of ω² or less), not a peak: a 10-DOF
// chain of unit springs and masses has its contact-free mode at exactly 1 rad/s, a sweep point
// of [0.1, 2.5], where the response came out 5e14 times the sweep's median; that scale made the
// bordered matrices singular (reciprocal condition 1.9e-16) right after the first point, at every
// force.
// A lightly damped peak is 1/(2ζ) times the off-resonance level: 5e3 at ζ = 1e-4.
constexpr double kMaxSweepOverMedian = 1e6;

// The largest |coefficient| of a linear response over the range (65 frequencies): all contacts
// stuck (k_T0 springs), or with `free`, all contacts removed (what gross slip tends to when the
// force exceeds the friction limit by far). Infinite values and those above kMaxSweepOverMedian
// times the median (an undamped resonance met exactly) are skipped; 0 when nothing finite
// remains. A lightly damped peak lies between the frequencies (it is a scale for the probe below,
// which resolves the peak).
double linear_peak(const DiscreteSystem& system, const Excitation& excitation,
                   const FrfOptions& options, bool free) {
  DiscreteSystem linear = system;
  if (free) linear.contacts.clear();
  hb::HarmonicBalanceOptions ho;
  ho.harmonics = 1;
  ho.time_samples = 8;
  std::vector<double> sampled;
  try {
    const hb::HarmonicBalance balance(linear, excitation, ho);
    constexpr int kSweep = 64;
    for (int i = 0; i <= kSweep; ++i) {
      const double omega =
          options.omega_start + (options.omega_end - options.omega_start) * i / kSweep;
      const double a = balance.stuck_solution(omega).lpNorm<Eigen::Infinity>();
      if (std::isfinite(a)) sampled.push_back(a);
    }
  } catch (const std::exception&) {
    return 0.0;  // e.g. a system that needs its contacts to be well posed
  }
  if (sampled.empty()) return 0.0;
  std::vector<double> sorted = sampled;
  const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  const double cap = kMaxSweepOverMedian * *middle;
  double peak = 0.0;
  for (const double a : sampled)
    if (a <= cap || !(cap > 0.0)) peak = std::max(peak, a);
  return peak;
}

// The largest |coefficient| along a cheap probe of the curve at one harmonic, traced with the
// unknowns scaled by `scale`, and whether the probe covered the range.
struct Probe {
  double peak = 0.0;
  bool complete = false;
};
Probe probe_peak(const DiscreteSystem& system, const Excitation& excitation,
                 const FrfOptions& options, double scale) {
  Probe out;
  try {
    hb::HarmonicBalanceOptions ho;
    ho.harmonics = 1;
    ho.time_samples = 32;
    ho.periodic_tolerance = options.periodic_tolerance;
    const hb::HarmonicBalance probe(system, excitation, ho);
    Options c = options.continuation;
    c.parameter_start = options.omega_start;
    c.parameter_end = options.omega_end;
    c.direction = options.omega_end > options.omega_start ? 1 : -1;
    c.parameter_scale = std::abs(options.omega_end - options.omega_start);
    c.max_step = std::max(c.max_step, 0.1);
    c.max_points = std::max(c.max_points, 5000);
    if (c.max_state_turn == 0.0) c.max_state_turn = kMaxStateTurn;  // else it steps over sharp peaks
    const Eigen::VectorXd x0 = probe.stuck_solution(options.omega_start);
    c.state_scale = Eigen::VectorXd::Constant(x0.size(), scale);
    const Result r = trace(residual_of(probe), x0, c);
    for (const auto& p : r.points) out.peak = std::max(out.peak, p.x.lpNorm<Eigen::Infinity>());
    out.complete = r.completed();
  } catch (const std::exception&) {
    return {};  // the probe is a heuristic: the caller falls back
  }
  if (!std::isfinite(out.peak)) return {};
  return out;
}

// The scale of the unknowns in the arclength, so that a step weighs the response against Ω evenly:
// the peak of a cheap one-harmonic probe of the same curve (a friction-limited peak can be far
// below the linear bounds), traced first with the stuck system's peak as its scale and, when that
// probe does not finish, with the larger of the stuck and contact-free peaks (in gross slip the
// response approaches the contact-free one: with only the stuck bound, a probe and then the curve
// crawled, 1000 points over 0.01 % of the range). Else the larger of that linear peak and the
// highest point a stopped probe reached (ζ = 1e-4, k_T0/k = 100, F = 10 μF_N: the probes stop on
// the way up a gross-slip peak of 4342 and the contact-free sweep's 114 alone made the curve take
// 1163 points), else 1.
double response_scale(const DiscreteSystem& system, const Excitation& excitation,
                      const FrfOptions& options) {
  const double stuck = linear_peak(system, excitation, options, false);
  const double bound = std::max(stuck, linear_peak(system, excitation, options, true));
  double reached = 0.0;  // the highest point of a probe that stopped: a lower bound of the peak
  for (const double scale : {stuck, bound}) {
    if (!(scale > 0.0)) continue;
    const Probe probe = probe_peak(system, excitation, options, scale);
    if (probe.complete && probe.peak > 0.0) return probe.peak;
    reached = std::max(reached, probe.peak);
    if (bound == stuck) break;
  }
  const double fallback = std::max(bound, reached);
  return fallback > 0.0 ? fallback : 1.0;
}

// The solution at Ω_start by continuation in the force scale s ∈ [0, 1] from the reference state
// (s = 0: exact), R_s = R(X, Ω_start) − (s − 1) F_ex.
std::optional<Eigen::VectorXd> force_ramp(const hb::HarmonicBalance& b, double omega,
                                          const Options& base, int& iterations, std::string& why) {
  Options h = base;
  h.state_scale = Eigen::VectorXd::Constant(
      b.unknowns(), base.state_scale.size() > 0 ? base.state_scale[0] : 1.0);
  const Eigen::VectorXd load_part = -b.forcing();
  const Result ramp = segment_detail::trace_load_ramp(residual_of(b), omega, load_part, b.stuck_solution(omega, 0.0), h);
  iterations += ramp.corrector_iterations;
  if (ramp.completed()) return ramp.points.back().x;
  why = "force ramp: " + ramp.message;
  return std::nullopt;
}

// Damped Newton at fixed Ω from x0 (the continuation's start corrector).
std::optional<Eigen::VectorXd> newton_at(const hb::HarmonicBalance& b, double omega,
                                         const Eigen::VectorXd& x0, const Options& base,
                                         int& iterations, std::string& why) {
  Options o = base;
  o.parameter_start = omega;
  o.max_points = 1;
  o.state_scale = Eigen::VectorXd::Constant(
      b.unknowns(), base.state_scale.size() > 0 ? base.state_scale[0] : 1.0);
  const Result r = trace(residual_of(b), x0, o);
  iterations += r.corrector_iterations;
  if (!r.points.empty()) return r.points.front().x;
  why = r.message;
  return std::nullopt;
}

// The start on a harmonic ladder H_l = 1, 3, 7, 15, ... < H, then H: level 1 (few unknowns, 32
// samples: few kinks) by the force ramp, every next level by Newton from the previous level's
// solution padded with zeros (or, failing that, by its own force ramp).
std::optional<Eigen::VectorXd> start_by_ladder(
    const DiscreteSystem& system, const Excitation& excitation, const FrfOptions& options,
    const hb::HarmonicBalance& target, const Options& base, int& iterations, std::string& why) {
  std::vector<int> levels;
  for (int h = 1; h < options.harmonics; h = 2 * h + 1) levels.push_back(h);
  std::optional<Eigen::VectorXd> x;
  std::optional<hb::FourierBasis> previous;
  for (std::size_t l = 0; l <= levels.size(); ++l) {
    const bool last = l == levels.size();
    std::optional<hb::HarmonicBalance> level;
    if (!last) {
      hb::HarmonicBalanceOptions o = balance_options(options);
      o.harmonics = levels[l];
      o.time_samples = std::min(options.time_samples, std::max(32, 16 * levels[l]));
      level.emplace(system, excitation, o);
    }
    const hb::HarmonicBalance& b = last ? target : *level;
    std::string reason;
    std::optional<Eigen::VectorXd> next;
    if (x)
      next = newton_at(b, options.omega_start, hb::transfer_coefficients(*previous, b.basis(), *x, system.dofs()), base,
                       iterations, reason);
    if (!next) next = force_ramp(b, options.omega_start, base, iterations, reason);
    if (!next) {
      why = fmt::format("the harmonic ladder failed at H = {}: {}", b.basis().harmonics(), reason);
      return std::nullopt;
    }
    x = std::move(next);
    previous = b.basis();
  }
  return x;
}

// Why a curve that did not reach its end stopped, in physical terms, or empty: the last Ω lies
// within 2 % of a natural frequency ω_j of the stuck (k_T0 springs) or the contact-free linear
// system whose modal damping ratio ζ_j = φ_jᵀ C φ_j / (2 ω_j) (mass-normalised φ_j) is below 1e-3.
// There the response is bounded only by slip (stuck) or not at all when the force drives the
// contacts into gross slip (contact-free: friction dissipates at most 4 μF_N X per period against
// the π F X the force puts in, so it cannot bound a resonance once F > 4 μF_N / π).
std::string stop_diagnosis(const DiscreteSystem& system, const FrfCurve& curve) {
  if (curve.points.empty()) return {};
  const double omega = curve.points.back().omega;
  const std::optional<detail::NearResonance> best = detail::nearest_resonance(system, omega, {1}, 0.02, 1e-3);
  if (!best) return {};
  double peak = 0.0;
  for (const auto& p : curve.points) peak = std::max(peak, p.amplitude_max);
  if (best->stuck) {
    return fmt::format(
        "Ω = {:.6g} rad/s is within {:.2g} % of the stuck system's natural frequency {:.6g} rad/s, "
        "where it is damped only ζ = {:.2g}: the response (here up to {:.3g}) is bounded there "
        "only by slip of the contacts; more damping or a larger force moves the curve away from it",
        omega, 100.0 * best->distance, best->omega, best->zeta, peak);
  }
  return fmt::format(
      "Ω = {:.6g} rad/s is within {:.2g} % of the natural frequency {:.6g} rad/s of the system "
      "with every contact slipping, damped only ζ = {:.2g}: the force drives the contacts into "
      "gross slip (for one contact: F > 4 μF_N / π), friction cannot bound that resonance and "
      "the response (here up to {:.3g}) grows without bound; add damping or end the range before it",
      omega, 100.0 * best->distance, best->omega, best->zeta, peak);
}

// For a completed curve: its highest point lies within 2 % of a natural frequency of the
// contact-free system damped below ζ = 1e-3 (stop_diagnosis), i.e. the curve passed a resonance that
// friction cannot bound (crossing it at fixed phase, docs/continuation.md): a note saying so, or
// empty. The points beside it are the two flanks of a peak without bound, not a bounded maximum.
std::string unbounded_passage(const DiscreteSystem& system, const FrfCurve& curve) {
  const auto top = std::max_element(curve.points.begin(), curve.points.end(),
                                    [](const FrfPoint& a, const FrfPoint& b) { return a.amplitude_max < b.amplitude_max; });
  if (top == curve.points.end()) return {};
  const std::optional<detail::NearResonance> best = detail::nearest_resonance(system, top->omega, {1}, 0.02, 1e-3);
  if (!best || best->stuck) return {};
  return fmt::format(
      ". The curve passed Ω = {:.6g} rad/s, within {:.2g} % of the natural frequency {:.6g} rad/s of the system "
      "with every contact slipping, damped only ζ = {:.2g}: friction cannot bound that resonance (for one "
      "contact: F > 4 μF_N / π) and the response there (here up to {:.3g}) grows without bound",
      top->omega, 100.0 * best->distance, best->omega, best->zeta, top->amplitude_max);
}

// The first guess at Ω_start: the stuck linear response, or, where the stuck system is undamped
// and Ω_start is its natural frequency (a singular dynamic stiffness: no finite stuck response),
// the stuck response 0.1 % above or below it. That guess is far into slip; the start corrector
// (damped Newton at fixed Ω) brings it down to the slip-limited response.
Eigen::VectorXd start_guess(const hb::HarmonicBalance& balance, double omega) {
  Eigen::VectorXd x0 = balance.stuck_solution(omega);
  for (const double shift : {1.001, 0.999}) {
    if (x0.allFinite()) break;
    x0 = balance.stuck_solution(shift * omega);
  }
  return x0.allFinite() ? x0 : Eigen::VectorXd::Zero(x0.size());
}


// q = |fundamental| of the output DOF, √(a₁² + b₁²), with its gradient (the resonance peak).
detail::CurveQuantity fundamental_quantity(const hb::HarmonicBalance& b, int dof) {
  const int a1 = b.basis().cosine_index(1);
  const Eigen::Index at = b.index(dof, a1);
  detail::CurveQuantity q;
  q.value = [at](const Eigen::VectorXd& x, double) { return std::hypot(x[at], x[at + 1]); };
  q.gradient = [at](const Eigen::VectorXd& x, double) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
    const double a = std::hypot(x[at], x[at + 1]);
    if (a > 0.0) {
      g[at] = x[at] / a;
      g[at + 1] = x[at + 1] / a;
    }
    return std::pair<Eigen::VectorXd, double>{g, 0.0};
  };
  return q;
}

}  // namespace

std::string FrfOptions::validate(int dofs) const {
  if (!(omega_start > 0.0) || !std::isfinite(omega_start)) {
    return fmt::format("omega_start: must be finite and > 0, got {}", omega_start);
  }
  if (!(omega_end > 0.0) || !std::isfinite(omega_end)) {
    return fmt::format("omega_end: must be finite and > 0, got {}", omega_end);
  }
  if (omega_end == omega_start) return "omega_end: must differ from omega_start";
  if (output_dof < 0 || output_dof >= dofs) {
    return fmt::format("output_dof: must be in [0, {}], got {}", dofs - 1, output_dof);
  }
  if (auto msg = hill.validate(); !msg.empty()) return "hill." + msg;
  if (auto msg = monodromy.validate(); !msg.empty()) return "monodromy." + msg;
  if (std::string msg = accuracy.validate({harmonics, time_samples}); !msg.empty()) return msg;
  return balance_options(*this).validate();
}

std::string to_string(StabilityMethod method) {
  return method == StabilityMethod::hill ? "hill" : "monodromy";
}

bool computes_stability(const FrfOptions& options, int dofs) {
  // Hill's method works on the full basis 0..H even where the curve keeps odd harmonics only.
  if (options.stability != Stability::automatic) return options.stability == Stability::always;
  if (options.stability_method == StabilityMethod::monodromy) return dofs <= kAutomaticStabilityDofs;
  const long long unknowns = static_cast<long long>(dofs) * (2LL * options.harmonics + 1);
  return unknowns <= kAutomaticStabilityUnknowns;
}

namespace {

// The FRF's options at `level` (H, N_t).
FrfOptions frf_options_at(const FrfOptions& options, Level level) {
  FrfOptions o = options;
  o.harmonics = level.harmonics;
  o.time_samples = level.time_samples;
  return o;
}

// The runs of one segment (DiscreteFrfSegment::run_legs): a continuation run whose accepted point
// exceeds kRescaleFactor times the state scale starts again with the scale raised to it; at most
// kMaxLegs runs (rescalings and crossings at fixed phase) per segment.
constexpr double kRescaleFactor = 10.0;
constexpr int kMaxLegs = 24;
// A restart beyond a crossing may not turn the phase back by more than this (radians).
constexpr double kPhaseBacktrack = 1e-3;
// The fixed frequencies tried beyond a crossing: Ω_B (1 ± kBeyondFirst 2^k), k < kBeyondSteps (up to
// 0.8 % of Ω_B).
constexpr double kBeyondFirst = 1e-9;
constexpr int kBeyondSteps = 24;

// Adds run r's counts and timings to the segment's `total`, whose reason and message become r's.
void add_run(Result& total, const Result& r) {
  total.rejected_steps += r.rejected_steps;
  total.corrector_iterations += r.corrector_iterations;
  total.evaluations += r.evaluations;
  total.evaluation_seconds += r.evaluation_seconds;
  total.linear_solve_seconds += r.linear_solve_seconds;
  total.factorisations += r.factorisations;
  total.reason = r.reason;
  total.message = r.message;
}

// What every segment of one FRF shares: the system, the options, the scales of the arclength (one
// probe per curve), the Floquet result of the last kept point and the curve being built.
struct DiscreteFrfShared {
  DiscreteFrfShared(const DiscreteSystem& s, const Excitation& e, const FrfOptions& o, FrfCurve& c)
      : system(s), excitation(e), options(o), curve(c) {}
  const DiscreteSystem& system;
  const Excitation& excitation;
  const FrfOptions& options;
  FrfCurve& curve;
  double state_scale = 1.0;
  double residual_scale = 1.0;
  std::optional<hb::FloquetResult> previous_floquet;
  std::optional<double> overflow_at;
  double overflow_ratio = 0.0;
  int ladder_iterations = 0;
};

// One continuation run of a discrete FRF at one level (H, N_t) (segmented_curve.hpp): the balance,
// its stability and error estimators, the cached last evaluation, and the kept points' positions
// in the curve with their tangents (for the folds and the peak, located within a segment).
class DiscreteFrfSegment {
 public:
  using Judge = std::function<bool(FrfPoint&, const Point&)>;

  DiscreteFrfSegment(DiscreteFrfShared& shared, Level level)
      : shared_(shared),
        options_(frf_options_at(shared.options, level)),
        balance_(shared.system, shared.excitation, balance_options(options_)),
        stability_(computes_stability(options_, shared.system.dofs())) {
    if (stability_ && options_.stability_method == StabilityMethod::hill) hill_.emplace(balance_, options_.hill);
    // The finer balances of the error estimates; none when the H + 2 basis cannot be built (the
    // points then carry error.known = false).
    if (options_.error_estimate || options_.accuracy.active()) {
      try {
        estimator_.emplace(shared.system, shared.excitation, balance_options(options_));
      } catch (const std::invalid_argument&) {
        estimator_.reset();
      }
    }
  }

  [[nodiscard]] const hb::HarmonicBalance& balance() const { return balance_; }
  [[nodiscard]] bool stability() const { return stability_; }
  [[nodiscard]] const ResidualFunction& residual() const { return residual_; }
  [[nodiscard]] const std::vector<std::size_t>& kept() const { return kept_; }
  [[nodiscard]] const std::vector<Eigen::VectorXd>& tangents() const { return tangents_; }
  [[nodiscard]] const Options& options() const { return continuation_; }

  // The first guess at Ω_start (start_guess), or the start's coefficients transferred to this level.
  [[nodiscard]] Eigen::VectorXd start_state(const segment_detail::SegmentStart& from) {
    first_segment_ = from.y.size() == 0;
    if (first_segment_) return start_guess(balance_, options_.omega_start);
    return segment_detail::transfer_unknowns(from.y, from.from, balance_.basis(), shared_.system.dofs());
  }

  [[nodiscard]] Options continuation(double omega0, double end) {
    Options c = options_.continuation;
    c.parameter_start = omega0;
    c.parameter_end = end;
    c.direction = end > omega0 ? 1 : -1;
    c.state_scale = Eigen::VectorXd::Constant(balance_.unknowns(), shared_.state_scale);
    c.parameter_scale = std::abs(options_.omega_end - options_.omega_start);
    c.residual_scale = shared_.residual_scale;
    if (c.max_state_turn == 0.0) c.max_state_turn = kMaxStateTurn;
    // |fundamental| of the output DOF, for max_output_change.
    c.outputs = [this](const Eigen::VectorXd& x, double) {
      return Eigen::VectorXd::Constant(1, balance_.fundamental_amplitude(x, options_.output_dof));
    };
    continuation_ = c;
    return c;
  }

  // Discrete estimates are one Newton step each: the truncation part is always made.
  Result run(const Eigen::VectorXd& x0, const Options& c, const Judge& judge,
             const std::function<bool()>& /*wants_truncation*/) {
    Result r = run_legs(x0, c, judge);
    if (r.reason == StopReason::start_failed && first_segment_) {
      // Newton from the stuck solution can fail where the contacts slip grossly at Ω_start (stiff
      // Jenkins contacts make R piecewise linear with kinks wherever a sample switches between
      // stick and slip). Find the start on a harmonic ladder instead (start_by_ladder).
      std::string why;
      int iterations = 0;
      const std::optional<Eigen::VectorXd> start =
          start_by_ladder(shared_.system, shared_.excitation, options_, balance_, c, iterations, why);
      shared_.ladder_iterations += r.corrector_iterations + iterations;
      if (start) {
        r = run_legs(*start, c, judge);
      } else {
        r.message += "; " + why;
      }
    }
    return r;
  }

  // A point about to be kept (segmented_curve.hpp): its Floquet multipliers and the bifurcation
  // against the last kept point — only for kept points, not for those a finer level traces again.
  void complete(FrfPoint& f, const Point& p) {
    if (!stability_) return;
    const auto stability_start = Clock::now();
    hb::FloquetResult floquet =
        hill_ ? hill_->evaluate(p.x, p.lambda) : hb::orbit_floquet(balance_, p.x, p.lambda, options_.monodromy);
    shared_.curve.timings.stability += seconds_since(stability_start);
    f.stability_known = floquet.ok;
    f.stable = floquet.stable();
    f.max_multiplier = floquet.max_multiplier;
    f.unstable_multipliers = floquet.unstable;
    f.multipliers = floquet.multipliers;
    if (shared_.previous_floquet) f.bifurcation = hb::classify_bifurcation(*shared_.previous_floquet, floquet, p.fold);
    shared_.previous_floquet = std::move(floquet);
  }

 private:
  // The run in legs (docs/continuation.md, "Crossing a resonance at fixed phase"): a continuation
  // run from x0; where it stops short of its end (min_step), a crossing at fixed phase
  // (phase_bridge.hpp) and a new run beyond it; where an accepted point outgrows the arclength's
  // state scale kRescaleFactor times while the branch advances, a new run from that point with the
  // scale raised to it (a scale the probe underestimated makes the arclength crawl: 2.6e-11 rad/s
  // per point, 1000 points below an undamped stuck resonance). At most kMaxLegs runs.
  Result run_legs(const Eigen::VectorXd& x0, Options c, const Judge& judge) {
    Result total;
    Eigen::VectorXd x = x0;
    bool skip_first = false;  // the run starts on a point already kept
    int crossings = 0, rescalings = 0;
    Tally tally{0, c.parameter_start};
    const int budget = c.max_points;
    for (int leg = 0;; ++leg) {
      Options o = c;
      o.max_points = budget - tally.accepted + (skip_first ? 1 : 0);
      std::optional<double> rescale;
      bool first = true;
      const AcceptCallback accept = [&](const Point& p) {
        if (std::exchange(first, false) && skip_first) return true;
        tally.add(p.lambda);
        if (!accept_point(p, judge)) return false;
        const double size = p.x.lpNorm<Eigen::Infinity>();
        const bool onward = p.tangent.size() > 0 && p.tangent[p.tangent.size() - 1] * o.direction > 0.0;
        if (onward && size > kRescaleFactor * o.state_scale[0] && leg + 1 < kMaxLegs) {
          rescale = size;
          return false;
        }
        return true;
      };
      Result r = trace(residual_, x, o, accept);
      add_run(total, r);
      if (leg == 0 && r.reason == StopReason::start_failed) return total;
      if (rescale) {
        ++rescalings;
        const Point& last = r.points.back();
        Eigen::VectorXd tangent = last.tangent;  // unscaled with the scales it was traced with
        tangent.head(x.size()) = tangent.head(x.size()).cwiseProduct(o.state_scale);
        tangent[x.size()] *= o.parameter_scale;
        c.continued = Options::Continued{last.lambda, tangent};
        c.state_scale.setConstant(*rescale);
        x = last.x;
        c.initial_step = std::clamp(last.step, c.min_step, c.max_step);
        skip_first = true;
        continue;
      }
      if (r.reason != StopReason::min_step || r.points.empty() || leg + 1 >= kMaxLegs) break;
      std::optional<LegStart> next = cross_at_phase(r.points.back(), c, budget - tally.accepted, tally, judge, total);
      if (!next) break;
      ++crossings;
      x = std::move(next->x);
      c.continued = Options::Continued{next->omega, std::move(next->tangent)};
      c.initial_step = options_.continuation.initial_step;
      skip_first = next->kept;
    }
    if (crossings + rescalings > 0) {
      const std::string legs = fmt::format("{} crossing{} at fixed phase, {} rescaling{} of the state", crossings,
                                           crossings == 1 ? "" : "s", rescalings, rescalings == 1 ? "" : "s");
      // The counts of the whole segment, not of its last run.
      if (total.reason == StopReason::reached_end)
        total.message = fmt::format("reached λ_end = {:.10g} ({} points, {} rejected steps; {})", c.parameter_end,
                                    tally.accepted, total.rejected_steps, legs);
      else if (total.reason == StopReason::max_points)
        total.message = fmt::format("max_points = {} reached at λ = {:.10g} (point {}; {})", budget,
                                    tally.last_lambda, tally.accepted, legs);
      else
        total.message = fmt::format("{} ({})", total.message, legs);
    }
    return total;
  }

  // The points a segment's runs passed to the judge, and the λ of the last.
  struct Tally {
    int accepted = 0;
    double last_lambda = 0.0;
    void add(double lambda) {
      ++accepted;
      last_lambda = lambda;
    }
  };

  // Where a run continues after a crossing: a point of the branch at Ω, kept already or not, and
  // the branch's direction there ((dx, dΩ), unscaled).
  struct LegStart {
    Eigen::VectorXd x;
    double omega = 0.0;
    bool kept = false;
    Eigen::VectorXd tangent;
  };

  // The crossing at fixed phase from the last point p of a stopped run (phase_bridge.hpp), its
  // points kept; then the start of the next run: the bridge's last point where the branch there
  // advances in Ω again, else the first solution at fixed Ω = Ω_B (1 ± δ) beyond it, δ =
  // kBeyondFirst 2^k, from B or from the stuck linear response, whose fundamental has not turned
  // back.
  std::optional<LegStart> cross_at_phase(const Point& p, const Options& c, int budget, Tally& tally,
                                         const Judge& judge, Result& total) {
    if (budget < 1) return std::nullopt;
    const int a1 = balance_.basis().cosine_index(1);
    if (a1 < 0) return std::nullopt;
    detail::PhaseBridgeOptions b;
    double largest = -1.0;
    for (int dof = 0; dof < shared_.system.dofs(); ++dof) {  // the DOF with the largest fundamental
      const Eigen::Index at = balance_.index(dof, a1);
      if (const double a = std::hypot(p.x[at], p.x[at + 1]); a > largest) {
        largest = a;
        b.phase_cosine = at;
      }
    }
    b.direction = c.direction;
    b.omega_low = std::min(options_.omega_start, options_.omega_end);
    b.omega_high = std::max(options_.omega_start, options_.omega_end);
    b.residual_tolerance = c.residual_tolerance;
    b.residual_scale = c.residual_scale;
    b.step_tolerance = c.step_tolerance;
    b.state_scale = c.state_scale[0];
    b.parameter_scale = c.parameter_scale;
    b.max_points = budget;
    const detail::PhaseRotation rotate = detail::harmonic_rotation(balance_, shared_.system.dofs());
    const Eigen::VectorXd scale = c.state_scale;
    const auto on_point = [&](const detail::PhaseBridgePoint& q) {
      Point point;
      point.x = q.x;
      point.lambda = q.omega;
      point.iterations = q.iterations;
      point.step = q.step;
      Eigen::VectorXd t(q.tangent.size());
      t.head(q.x.size()) = q.tangent.head(q.x.size()).cwiseQuotient(scale);
      t[q.x.size()] = q.tangent[q.x.size()] / c.parameter_scale;
      point.tangent = t.normalized();
      tally.add(q.omega);
      return accept_point(point, judge);
    };
    const detail::PhaseBridge bridge = detail::bridge_by_phase(residual_, rotate, p.x, p.lambda, b, on_point);
    total.corrector_iterations += bridge.iterations;
    total.rejected_steps += bridge.rejected_steps;
    using End = detail::PhaseBridge::End;
    if (bridge.end == End::stopped || bridge.end == End::budget) {
      total.reason = bridge.end == End::stopped ? StopReason::stopped_by_user : StopReason::max_points;
      return std::nullopt;
    }
    // The last point of the crossing, or p where the phase could not turn (p is a corner already
    // crossed: the far stuck leg of an undamped resonance, whose phase is π).
    const Eigen::VectorXd& last_x = bridge.points.empty() ? p.x : bridge.points.back().x;
    const double last_omega = bridge.points.empty() ? p.lambda : bridge.points.back().omega;
    if (!bridge.points.empty()) {
      const detail::PhaseBridgePoint& last = bridge.points.back();
      const double advance = bridge.points.size() > 1 ? last.omega - bridge.points[bridge.points.size() - 2].omega
                                                      : last.omega - p.lambda;
      if ((bridge.end == End::omega_dominated || bridge.end == End::range) && advance * c.direction > 0.0)
        return LegStart{last.x, last.omega, true, last.tangent};
    }
    const double theta = detail::fundamental_phase(last_x, b.phase_cosine);
    for (int k = 0; k < kBeyondSteps; ++k) {
      const double omega = last_omega * (1.0 + c.direction * kBeyondFirst * std::pow(2.0, k));
      if (omega < b.omega_low || omega > b.omega_high) break;
      // From B, and, only where that fails, from the stuck linear response (the far leg of a
      // resonance bounded by slip).
      for (int g = 0; g < 2; ++g) {
        const Eigen::VectorXd guess = g == 0 ? last_x : balance_.stuck_solution(omega);
        if (!guess.allFinite()) continue;
        detail::FixedOmegaSolve s = detail::solve_at_omega(residual_, guess, omega, b);
        total.corrector_iterations += s.iterations;
        if (!s.converged) continue;
        const double turn =
            std::remainder(detail::fundamental_phase(s.x, b.phase_cosine) - theta, 2.0 * std::numbers::pi);
        if (turn * c.direction < -kPhaseBacktrack) continue;
        Eigen::VectorXd along = Eigen::VectorXd::Zero(s.x.size() + 1);
        along[s.x.size()] = c.direction;
        return LegStart{std::move(s.x), omega, false, along};
      }
    }
    total.message += bridge.points.empty()
                         ? fmt::format("; the crossing at fixed phase found no point ({}), nor a solution at "
                                       "fixed Ω up to {:.3g} beyond", bridge.message,
                                       kBeyondFirst * std::pow(2.0, kBeyondSteps - 1))
                         : fmt::format("; crossed at fixed phase to Ω = {:.10g}, where no solution beyond was found",
                                       last_omega);
    return std::nullopt;
  }

  bool accept_point(const Point& p, const Judge& judge) {
    FrfCurve& curve = shared_.curve;
    if (p.lambda != last_omega_ || p.x.size() != last_x_.size() || p.x != last_x_)
      balance_.evaluate(p.x, p.lambda, false, last_);
    FrfPoint f;
    f.omega = p.lambda;
    f.amplitude_h1 = balance_.fundamental_amplitude(p.x, options_.output_dof);
    f.amplitude_max =
        balance_.basis().peak_magnitude(p.x.segment(balance_.index(options_.output_dof, 0), balance_.basis().size()));
    f.dissipation = last_.dissipation;
    f.iterations = p.iterations;
    f.step = p.step;
    f.fold = p.fold;
    f.coefficients = p.x;
    f.harmonics = balance_.basis().harmonics();
    f.time_samples = balance_.basis().time_samples();
    if (const double ratio = balance_.max_slip_ratio(p.x);
        !std::isfinite(f.amplitude_h1) || !std::isfinite(f.amplitude_max) || !std::isfinite(f.dissipation) ||
        !(ratio <= contact::kMaxSlipRatio)) {
      shared_.overflow_at = p.lambda;
      shared_.overflow_ratio = ratio;
      return false;
    }
    if (!stability_ && p.fold) f.bifurcation = hb::Bifurcation::fold;  // else complete()
    if (estimator_) {
      const auto estimate_start = Clock::now();
      f.error = estimator_->estimate(balance_, p.x, p.lambda, options_.output_dof);
      curve.timings.error_estimate += seconds_since(estimate_start);
    }
    if (options_.check_jacobian) {
      const hb::JacobianCheck check = hb::check_jacobian(balance_, p.x, p.lambda);
      const double e = std::max(check.max_error, check.max_error_omega);
      if (!(e <= curve.jacobian_check_error)) {
        curve.jacobian_check_error = e;
        curve.jacobian_check_omega = p.lambda;
      }
    }
    const std::size_t before = curve.points.size();
    const bool go_on = judge(f, p);
    if (curve.points.size() > before) {  // kept (judge appended it)
      kept_.push_back(before);
      tangents_.push_back(p.tangent);
    }
    return go_on;
  }

  Evaluation evaluate(const Eigen::VectorXd& x, double omega, bool jacobian) {
    Evaluation e;
    last_x_.resize(0);  // an evaluation that throws leaves no valid cache behind
    balance_.evaluate(x, omega, jacobian, last_);
    last_x_ = x;
    last_omega_ = omega;
    e.ok = last_.ok;
    e.message = last_.message;
    e.residual = last_.residual;
    if (jacobian) {
      e.d_state = last_.d_coefficients;
      e.d_parameter = last_.d_omega;
    }
    return e;
  }

  DiscreteFrfShared& shared_;
  FrfOptions options_;
  hb::HarmonicBalance balance_;
  bool stability_;
  std::optional<hb::HillStability> hill_;
  std::optional<FrfErrorEstimator> estimator_;
  // The last evaluation, kept so that an accepted point's diagnostics cost nothing extra when the
  // corrector ended on it.
  hb::HarmonicBalanceEvaluation last_;
  Eigen::VectorXd last_x_;
  double last_omega_ = std::numeric_limits<double>::quiet_NaN();
  ResidualFunction residual_ = [this](const Eigen::VectorXd& x, double omega, bool jacobian) {
    return evaluate(x, omega, jacobian);
  };
  Options continuation_;
  bool first_segment_ = false;
  std::vector<std::size_t> kept_;
  std::vector<Eigen::VectorXd> tangents_;
};

// One fold detected on two neighbouring points: the turn of Ω at one accepted point and the count
// of unstable multipliers changing at the next (or the previous) one. Next to a fold the crossing
// multiplier is within its own error of +1 (the monodromy integrates the exact variational
// equation along the truncated orbit, whose fold lies a little apart from the balance's), so the
// verdicts of the two points can fall on the same side: a "reversal" beside a "branch point" whose
// multiplier crossed +1 is that fold, reported at the turn.
void merge_split_folds(std::vector<FrfPoint>& points) {
  using hb::Bifurcation;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    FrfPoint& a = points[k];
    FrfPoint& b = points[k + 1];
    const bool turn_first = a.bifurcation == Bifurcation::reversal && b.bifurcation == Bifurcation::branch_point;
    const bool turn_second = a.bifurcation == Bifurcation::branch_point && b.bifurcation == Bifurcation::reversal;
    if (!turn_first && !turn_second) continue;
    (turn_first ? a : b).bifurcation = Bifurcation::fold;
    (turn_first ? b : a).bifurcation = Bifurcation::none;
  }
}

}  // namespace

FrfCurve trace_frf(const DiscreteSystem& system, const Excitation& excitation, const FrfOptions& options,
                   const std::function<bool(const FrfPoint&)>& on_point) {
  const auto start_time = Clock::now();
  if (auto msg = options.validate(system.dofs()); !msg.empty()) throw std::invalid_argument(msg);
  FrfCurve curve;
  DiscreteFrfShared shared(system, excitation, options, curve);
  shared.state_scale = response_scale(system, excitation, options);
  double force_scale = 0.0;
  for (const auto& f : excitation.forces) force_scale = std::max(force_scale, std::abs(f.amplitude));
  if (excitation.static_force.size() > 0)
    force_scale = std::max(force_scale, excitation.static_force.lpNorm<Eigen::Infinity>());
  shared.residual_scale = force_scale > 0.0 ? force_scale : 1.0;

  std::vector<std::unique_ptr<DiscreteFrfSegment>> segments;  // kept alive for the folds and the peak
  const auto make_segment = [&](Level level) {
    segments.push_back(std::make_unique<DiscreteFrfSegment>(shared, level));
    DiscreteFrfSegment* run = segments.back().get();
    if (segments.size() == 1) {
      const hb::FourierBasis& basis = run->balance().basis();
      curve.kept_harmonics = basis.orders();
      if (basis.has_mean()) curve.kept_harmonics.insert(curve.kept_harmonics.begin(), 0);
      if (!run->stability() && options.stability == Stability::automatic)
        curve.stability_note =
            options.stability_method == StabilityMethod::hill
                ? fmt::format("stability not computed: Hill's eigenproblem has 2n(2H+1) = {} unknowns "
                              "per point (automatic up to {}); set stability: true to compute it",
                              2LL * system.dofs() * (2 * options.harmonics + 1), 2 * kAutomaticStabilityUnknowns)
                : fmt::format("stability not computed: {} DOFs (automatic up to {}); set "
                              "stability: true to compute it",
                              system.dofs(), kAutomaticStabilityDofs);
    }
    return run;
  };
  const std::function<bool(FrfPoint&)> keep = segment_detail::append_to(curve.points, on_point);
  const auto after_run = [&](const DiscreteFrfSegment& run, const Result& r) {
    curve.newton_iterations += r.corrector_iterations;
    curve.rejected_steps += r.rejected_steps;
    curve.timings.linear_solve += r.linear_solve_seconds;
    const hb::HarmonicBalanceTimings t = run.balance().timings();
    curve.timings.aft += t.aft;
    curve.timings.assembly += t.assembly;
  };
  const segment_detail::SegmentedOutcome outcome = segment_detail::trace_in_segments(
      options.accuracy, {options.harmonics, options.time_samples}, options.omega_start, options.omega_end,
      options.continuation, make_segment, keep, after_run);
  curve.newton_iterations += shared.ladder_iterations;
  merge_split_folds(curve.points);
  if (options.refine_extrema) {
    const auto refinement_start = Clock::now();
    detail::locate_in_segments(segments, curve, [&](const DiscreteFrfSegment& run, bool peak) {
      const hb::HarmonicBalance& b = run.balance();
      const detail::CurveQuantity amplitude =
          b.basis().cosine_index(1) < 0 ? detail::CurveQuantity{} : fundamental_quantity(b, options.output_dof);
      return detail::locate_frf_extrema(
          run.residual(), run.options(),
          detail::run_points(curve.points, run.kept(), run.tangents(), &FrfPoint::coefficients), amplitude, peak);
    });
    curve.timings.refinement = seconds_since(refinement_start);
  }
  segment_detail::put_outcome(outcome, curve);
  if (shared.overflow_at) {
    curve.reason = StopReason::out_of_range;
    curve.message = fmt::format(
        "at Ω = {:.6g} rad/s the contacts slip {:.3g} times their stick range μF_N/k_T0 (or an "
        "output overflows): beyond {:g} the laws' energies leave the range of doubles; the curve "
        "ends on the last point before (rescale the units or the forces)",
        *shared.overflow_at, shared.overflow_ratio, contact::kMaxSlipRatio);
  } else if (curve.completed()) {
    curve.message += unbounded_passage(system, curve);
  } else if (curve.reason != StopReason::stopped_by_user) {
    if (const std::string why = stop_diagnosis(system, curve); !why.empty()) curve.message += ". " + why;
    for (const auto& p : curve.points) {
      if (p.bifurcation != hb::Bifurcation::reversal) continue;
      curve.message += fmt::format(
          ". The curve reversed at Ω = {:.6g} rad/s without a Floquet multiplier crossing +1: "
          "not a fold but the continuation turning back along the branch at a kink (issue 23)",
          p.omega);
      break;
    }
  }
  curve.timings.total = seconds_since(start_time);
  return curve;
}

}  // namespace jointhb::continuation
