// An experiment for issue 23 (README_light_damping.md, "The friction cap crossed at fixed phase"):
// the four undamped 1-DOF Jenkins FRFs at F = 1e-6 μF_N that the light-damping corpus listed as
// stops until stop 51 (k_T0/k = 1e-2, 1, 1e2, 1e6) ended where the stuck leg reaches the slip
// amplitude X_s just below ω_stuck and the branch turns by ~90° onto the friction cap: there slip holds |X₁| within
// 1e-6 of X_s while the phase of the response turns by π at nearly constant Ω. Neither the
// arclength hyperplane nor a fixed Ω meets that cap robustly. This study crosses it with a corrector
// at fixed phase θ of the fundamental — Newton on [R(X, Ω); −sin θ a₁ + cos θ b₁] in (X, Ω), with
// the predictor rotating harmonic h of the previous point by h Δθ — for θ = kπ/64, k = 1 … 63, and
// checks each point against the closed form of the cap at one harmonic: the energy balance
// π F |X₁| sin θ = 4 μF_N (|X₁| − X_s) (the Jenkins element's dissipation per cycle, docs/theory.md
// §2.3), i.e. |X₁|/X_s − 1 ≈ π (F/μF_N) sin θ / 4. It is not the library's FRF driver: the experiment of
// stop 51 that showed a phase parametrisation carries the curve across; since stop 52 the driver
// does so (continuation/phase_bridge.hpp, docs/continuation.md, "Crossing a resonance at fixed
// phase").
//
//   cap_phase_crossing [--ci] OUTPUT_PREFIX
// H = 7, N_t = 256 (the corpus's); --ci the same (0.1 s). Scored: every point converges
// (‖R‖_∞ ≤ 1e-13) and |X₁|/X_s − 1 is within 2 % of the closed form at θ = π/2 (harmonics beyond
// the first carry the rest). Table: PREFIX_points.csv.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <Eigen/Dense>

#include "jointhb/hb/harmonic_balance.hpp"
#include "study_arguments.hpp"
#include "study_common.hpp"

// The study is one function of the multi-call program jointhb_validate_hb (CMakeLists.txt).
namespace jointhb_study_hb_cap_phase_crossing {

namespace {

using namespace jointhb;
constexpr double kPi = std::numbers::pi;
constexpr int kSteps = 64;  // θ = kπ/64

struct Crossing {
  int failures = 0;
  double excess_at_quarter = 0.0;  // |X₁|/X_s − 1 at θ = π/2
  double omega_range = 0.0;        // max − min of Ω over the cap, relative to ω_stuck
  int iterations = 0;
};

// −sin θ a₁ + cos θ b₁: zero when the fundamental lags the force by θ.
double phase_condition(const Eigen::VectorXd& x, int a1, double theta) {
  return -std::sin(theta) * x[a1] + std::cos(theta) * x[a1 + 1];
}

// Newton with a backtracking line search on [R; phase] at fixed θ; true when ‖·‖_∞ ≤ 1e-13.
bool correct(const hb::HarmonicBalance& b, int a1, double theta, Eigen::VectorXd& x, double& omega, int& iterations) {
  const Eigen::Index n = b.unknowns();
  const auto norm_at = [&](const Eigen::VectorXd& xt, double wt, hb::HarmonicBalanceEvaluation& e, bool jacobian) {
    b.evaluate(xt, wt, jacobian, e);
    return std::max(e.residual.lpNorm<Eigen::Infinity>(), std::abs(phase_condition(xt, a1, theta)));
  };
  for (int it = 0; it < 50; ++it) {
    hb::HarmonicBalanceEvaluation e;
    const double r = norm_at(x, omega, e, true);
    if (r <= 1e-13) return true;
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n + 1, n + 1);
    j.topLeftCorner(n, n) = e.d_coefficients;
    j.topRightCorner(n, 1) = e.d_omega;
    j(n, a1) = -std::sin(theta);
    j(n, a1 + 1) = std::cos(theta);
    Eigen::VectorXd rhs(n + 1);
    rhs.head(n) = e.residual;
    rhs[n] = phase_condition(x, a1, theta);
    const Eigen::VectorXd d = j.fullPivLu().solve(rhs);
    ++iterations;
    bool moved = false;
    for (double alpha = 1.0; alpha > 1e-6 && !moved; alpha *= 0.5) {
      const Eigen::VectorXd xt = x - alpha * d.head(n);
      const double wt = omega - alpha * d[n];
      if (!xt.allFinite() || !std::isfinite(wt)) continue;
      hb::HarmonicBalanceEvaluation et;
      try {
        if (norm_at(xt, wt, et, false) < (1.0 - 1e-4 * alpha) * r) x = xt, omega = wt, moved = true;
      } catch (const std::exception&) {
      }
    }
    if (!moved) return false;
  }
  return false;
}

Crossing cross(double ratio, double force, std::FILE* csv) {
  validation_study::ContactSpec spec{"jenkins", 1.0 / 3.0, ratio, 1.0};  // μF_N = 1
  hb::HarmonicBalanceOptions o;
  o.harmonics = 7;
  o.time_samples = 256;
  const hb::HarmonicBalance b(validation_study::oscillator(spec, 0.0), validation_study::cosine_force(0, force), o);
  const int a1 = static_cast<int>(b.index(0, b.basis().cosine_index(1)));
  const double stuck = std::sqrt(1.0 + ratio), slip = 1.0 / ratio;  // ω_stuck, X_s
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.unknowns());
  double omega = stuck;
  Crossing c;
  double lo = 1e300, hi = -1e300;
  const double step = kPi / kSteps;
  for (int k = 1; k < kSteps; ++k) {
    const double theta = k * step;
    if (k == 1) {  // on the cap next to the corner: just above X_s (slipping), phase θ
      x[a1] = (1.0 + 0.1 * force) * slip * std::cos(theta);
      x[a1 + 1] = (1.0 + 0.1 * force) * slip * std::sin(theta);
    } else {  // predictor: harmonic h turned by h Δθ
      for (const int h : b.basis().orders()) {
        const auto i = b.index(0, b.basis().cosine_index(h));
        const double a = x[i], s = x[i + 1];
        x[i] = a * std::cos(h * step) - s * std::sin(h * step);
        x[i + 1] = a * std::sin(h * step) + s * std::cos(h * step);
      }
    }
    const bool ok = correct(b, a1, theta, x, omega, c.iterations);
    if (!ok) ++c.failures;
    const double excess = std::hypot(x[a1], x[a1 + 1]) / slip - 1.0;
    const double closed = kPi * force * std::sin(theta) / 4.0;
    if (k == kSteps / 2) c.excess_at_quarter = excess;
    lo = std::min(lo, omega);
    hi = std::max(hi, omega);
    std::fprintf(csv, "%g,%.10f,%d,%.12e,%.6e,%.6e\n", ratio, theta, ok ? 1 : 0, omega / stuck - 1.0, excess, closed);
  }
  c.omega_range = (hi - lo) / stuck;
  return c;
}

}  // namespace

int run(int argc, char** argv) {
  const validation_study::Arguments args = validation_study::parse_arguments(argc, argv);
  if (!args.ok) return 2;
  std::FILE* csv = std::fopen((args.prefix + "_points.csv").c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "cannot write %s_points.csv\n", args.prefix.c_str());
    return 1;
  }
  std::fprintf(csv, "kt0_over_k,theta,converged,omega_over_stuck_minus_1,amplitude_excess,closed_form_excess\n");
  const double force = 1e-6;
  const double closed = kPi * force / 4.0;
  bool ok = true;
  for (const double ratio : {1e-2, 1.0, 1e2, 1e6}) {
    const Crossing c = cross(ratio, force, csv);
    const double error = std::abs(c.excess_at_quarter / closed - 1.0);
    std::printf("k_T0/k = %-6g: %d of %d points failed, %.2f Newton iterations per point; |X1|/X_s - 1 at "
                "theta = pi/2: %.4e (closed form %.4e, %.2f %%); Omega varies by %.2e of omega_stuck\n",
                ratio, c.failures, kSteps - 1, double(c.iterations) / (kSteps - 1), c.excess_at_quarter, closed,
                100.0 * error, c.omega_range);
    if (c.failures > 0 || !(error < 0.02)) ok = false;
  }
  std::fclose(csv);
  std::printf("%s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}

}  // namespace jointhb_study_hb_cap_phase_crossing
