// Harmonic balance with a stiffening Jenkins contact against Den Hartog's exact Coulomb solution.
//
// Description: m ẍ + k x + F_f sgn(ẋ) = P cos ωt (m = k = P = 1, F_f = r P, r = 0.3, no viscous
// damping) has Den Hartog's exact continuous ("non-stop") steady motion (timeint/den_hartog.hpp,
// verified there against an event-driven exact Coulomb integration). A Jenkins contact of
// stiffness k_T0 = κ k tends to the Coulomb slider as κ → ∞. For β = ω/ω_n ∈ {0.6, 0.8, 1.25,
// 1.5, 2.0} and κ = 10 … 1e5 the program solves harmonic balance (H = 31, N_t = 1024, at ω itself)
// (from Den Hartog's coefficients as the initial guess) and compares the fundamental (complex:
// amplitude and phase) and max |x(t)| with the exact values.
//
// Expected: the error falls like κ^(-1/2) (a Jenkins contact sticks for a slip 2F_f/k_T0 after each
// reversal; the stick phase lasts ∝ √(F_f/(k_T0 X0)) of the period, docs/time-integration.md)
// until the sampling limits it: once the stick slip 2F_f/k_T0 is shorter than the motion between
// two samples (κ ≳ 1e4 at N_t = 1024), every reversal completes within one sample interval, the
// AFT sees a Coulomb slider cut at the samples and the result no longer depends on κ (a floor of
// 3–5e-3 here, set by N_t: the "reversal between samples" error of docs/theory.md §7). Bounds: the
// observed slope between κ = 10 and 1e3 lies in [−0.6, −0.4] at every β, and the error at κ = 1e3
// is ≤ 3 %.
//
// Sample runs:
//   build/validation/hb/jointhb_validate_hb_den_hartog validation/hb/results/den_hartog
// --ci: κ = 10, 1e2, 1e3 only.

#include <fmt/format.h>
#include <fmt/os.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "jointhb/continuation/frf.hpp"
#include "jointhb/timeint/den_hartog.hpp"
#include "study_arguments.hpp"

// The study is one function of the multi-call program jointhb_validate_hb (CMakeLists.txt).
namespace jointhb_study_hb_den_hartog {

namespace {

using namespace jointhb;

struct Solution {
  bool ok = false;
  std::complex<double> x1;
  double amplitude_max = 0.0;
  std::string message;
};

// Harmonic balance at ω by the damped Newton start of continuation::trace, from Den Hartog's
// exact coefficients. From-scratch starts (stuck solution, force ramp, harmonic ladder) fail for
// this undamped system with stiff Jenkins contacts at most β (README_time_domain.md, "Limits"):
// the study measures accuracy, and the exact solution is a legitimate initial guess for that.
Solution solve(double kappa, double r, double omega, int harmonics, int samples,
               const Eigen::VectorXd& exact) {
  hb::DiscreteSystem s;
  s.mass = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  s.stiffness = Eigen::MatrixXd::Constant(1, 1, 1.0).sparseView();
  hb::ContactElement c;
  c.law = "jenkins";
  c.stiffness = kappa;
  c.friction_coefficient = 1.0;
  c.normal_force = r;
  s.contacts.push_back(c);
  hb::Excitation e;
  e.forces.push_back({0, 1.0, 1});
  const hb::HarmonicBalance balance(
      s, e, {harmonics, samples, hb::HarmonicSelection::automatic, 1e-14, true});
  const hb::FourierBasis& basis = balance.basis();  // odd harmonics: the case is symmetric
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(basis.size());
  for (int k : basis.orders()) {
    x0[basis.cosine_index(k)] = exact[2 * k - 1];
    x0[basis.cosine_index(k) + 1] = exact[2 * k];
  }
  continuation::Options o;
  o.parameter_start = omega;
  o.parameter_end = omega * 1.001;
  o.max_points = 1;
  o.max_start_iterations = 200;
  o.residual_tolerance = 1e-12;
  o.state_scale = Eigen::VectorXd::Constant(x0.size(), x0.lpNorm<Eigen::Infinity>());
  const continuation::Result res = continuation::trace(
      [&](const Eigen::VectorXd& x, double w, bool jacobian) {
        hb::HarmonicBalanceEvaluation ev;
        balance.evaluate(x, w, jacobian, ev);
        continuation::Evaluation out;
        out.ok = ev.ok;
        out.message = ev.message;
        out.residual = ev.residual;
        out.d_state = ev.d_coefficients;
        out.d_parameter = ev.d_omega;
        return out;
      },
      x0, o);
  Solution sol;
  if (res.points.empty()) {
    sol.message = res.message;
    return sol;
  }
  const Eigen::VectorXd& x = res.points.front().x;
  const int a = basis.cosine_index(1);
  sol.x1 = {x[a], -x[a + 1]};
  sol.amplitude_max = basis.peak_magnitude(x);
  sol.ok = true;
  return sol;
}

}  // namespace

int run(int argc, char** argv) {
  const validation_study::Arguments args = validation_study::parse_arguments(argc, argv);
  if (!args.ok) return 2;
  const bool ci = args.ci;
  const std::string& prefix = args.prefix;
  const double r = 0.3;
  const int harmonics = 31;
  const int samples = 1024;
  const std::vector<double> betas = {0.6, 0.8, 1.25, 1.5, 2.0};
  const std::vector<double> kappas =
      ci ? std::vector<double>{1e1, 1e2, 1e3} : std::vector<double>{1e1, 1e2, 1e3, 1e4, 1e5};
  auto out = fmt::output_file(prefix + "_table.csv");
  out.print("beta,kappa,X1_exact,X1_hb,err_x1,X0_exact,X0_hb,err_x0\n");
  int failures = 0;
  std::string slopes;
  for (double beta : betas) {
    const timeint::DenHartogResult exact = timeint::den_hartog(1.0, 1.0, r, 1.0, beta);
    if (!exact.non_stop) {
      std::printf("FAIL beta %.2f: Den Hartog's form does not apply (%s)\n", beta,
                  exact.message.c_str());
      ++failures;
      continue;
    }
    const Eigen::VectorXd c = exact.coefficients(harmonics);
    const std::complex<double> x1(c[1], -c[2]);
    double err_lo = 0.0, err_hi = 0.0;
    for (double kappa : kappas) {
      const Solution h = solve(kappa, r, beta, harmonics, samples, c);
      if (!h.ok) {
        std::printf("FAIL beta %.2f kappa %.0e: %s\n", beta, kappa, h.message.c_str());
        ++failures;
        continue;
      }
      const double err = std::abs(h.x1 - x1) / std::abs(x1);
      const double err0 = std::abs(h.amplitude_max - exact.amplitude) / exact.amplitude;
      out.print("{},{},{},{},{:.4e},{},{},{:.4e}\n", beta, kappa, std::abs(x1), std::abs(h.x1), err,
                exact.amplitude, h.amplitude_max, err0);
      if (kappa == 1e1) err_lo = err;
      if (kappa == 1e3) err_hi = err;
    }
    const double slope = std::log10(err_hi / err_lo) / 2.0;
    slopes += fmt::format(" {:.2f}", slope);
    if (!(slope >= -0.6 && slope <= -0.4) || !(err_hi <= 0.03)) {
      std::printf("FAIL beta %.2f: slope %.3f (expected -0.5), error at kappa 1e3 %.2e\n", beta,
                  slope, err_hi);
      ++failures;
    }
  }
  std::printf(
      "den_hartog: HB (H=%d, N=%d) with Jenkins k_T0 = kappa k vs Den Hartog's exact Coulomb "
      "solution, r = %.2f: observed slopes of the fundamental's error between kappa 10 and 1e3 at "
      "beta 0.6 0.8 1.25 1.5 2.0:%s; %d failures\n",
      harmonics, samples, r, slopes.c_str(), failures);
  return failures == 0 ? 0 : 1;
}

}  // namespace jointhb_study_hb_den_hartog
