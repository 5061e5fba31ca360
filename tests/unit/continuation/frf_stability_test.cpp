// Stability, folds and peaks of FRFs (continuation/frf.hpp with hb/hill_stability.hpp and
// continuation/curve_refinement.hpp): the located peak of a linear oscillator against its closed
// form, the folds of a friction oscillator against a second method (the extremum of Ω along the
// branch parametrised by the amplitude, by golden-section search), the multiplier +1 at a fold,
// and the unstable stretch between two folds.
#include "jointhb/continuation/frf.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <optional>

#include "jenkins_oscillator.hpp"

namespace jointhb::continuation {
namespace {

using test::force_at_dof0;
using test::jenkins_oscillator;

// The branch point with |fundamental| = A near the guess (X, Ω): Newton on (R = 0, |X₁| = A).
std::optional<std::pair<Eigen::VectorXd, double>> point_at_amplitude(const hb::HarmonicBalance& b,
                                                                     double a, Eigen::VectorXd x,
                                                                     double omega) {
  const Eigen::Index n = x.size();
  const Eigen::Index i = b.index(0, b.basis().cosine_index(1));
  for (int it = 0; it < 40; ++it) {
    hb::HarmonicBalanceEvaluation ev;
    b.evaluate(x, omega, true, ev);
    const double amplitude = std::hypot(x[i], x[i + 1]);
    Eigen::VectorXd r(n + 1);
    r.head(n) = ev.residual;
    r[n] = amplitude - a;
    if (r.lpNorm<Eigen::Infinity>() < 1e-14) return std::pair{x, omega};
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n + 1, n + 1);
    j.topLeftCorner(n, n) = ev.d_coefficients;
    j.topRightCorner(n, 1) = ev.d_omega;
    j(n, i) = x[i] / amplitude;
    j(n, i + 1) = x[i + 1] / amplitude;
    const Eigen::VectorXd d = j.partialPivLu().solve(-r);
    x += d.head(n);
    omega += d[n];
  }
  return std::nullopt;
}

// The extremum of Ω(A) on [a0, a1] by golden-section search (sign +1: maximum, −1: minimum).
double fold_by_golden_section(const hb::HarmonicBalance& b, double a0, double a1, double sign,
                              Eigen::VectorXd x, double omega) {
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double best = omega;
  for (int k = 0; k < 80 && a1 - a0 > 1e-13 * a1; ++k) {
    const double c = a1 - g * (a1 - a0);
    const double d = a0 + g * (a1 - a0);
    const auto pc = point_at_amplitude(b, c, x, omega);
    const auto pd = point_at_amplitude(b, d, x, omega);
    if (!pc || !pd) return std::nan("");
    if (sign * pc->second > sign * pd->second) {
      a1 = d;
      std::tie(x, omega) = *pc;
    } else {
      a0 = c;
      std::tie(x, omega) = *pd;
    }
    best = omega;
  }
  return best;
}

FrfOptions options(double w0, double w1, int harmonics) {
  FrfOptions o;
  o.omega_start = w0;
  o.omega_end = w1;
  o.harmonics = harmonics;
  o.time_samples = 128;
  o.stability = Stability::always;
  return o;
}

TEST(FrfStability, LinearPeakIsLocatedToTheClosedFormWithinItsBound) {
  // |X| = F / √((1 − Ω²)² + (cΩ)²): maximum at Ω² = 1 − c²/2, of F / (c √(1 − c²/4)).
  const double c = 0.02, f = 0.01;
  const FrfCurve curve = trace_frf(jenkins_oscillator(0.0, 0.0, c), force_at_dof0(f), options(0.5, 1.5, 3));
  ASSERT_TRUE(curve.completed()) << curve.message;
  ASSERT_TRUE(curve.peak && curve.peak->refined) << (curve.peak ? curve.peak->message : "");
  const double omega = std::sqrt(1.0 - c * c / 2.0);
  const double amplitude = f / (c * std::sqrt(1.0 - c * c / 4.0));
  EXPECT_LE(std::abs(curve.peak->amplitude_h1 - amplitude), curve.peak->value_bound + 1e-12 * amplitude);
  EXPECT_LT(curve.peak->value_bound, 1e-9 * amplitude);
  EXPECT_NEAR(curve.peak->omega, omega, 1e-6);
  // The highest accepted point alone is much further off.
  double top = 0.0;
  for (const auto& p : curve.points) top = std::max(top, p.amplitude_h1);
  EXPECT_GT(amplitude - top, 100.0 * curve.peak->value_bound);
  for (const auto& p : curve.points) EXPECT_TRUE(p.stability_known && p.stable) << p.omega;
}

TEST(FrfStability, FoldsAgreeWithTheAmplitudeParametrisationAndCarryHillMultiplierOne) {
  // kt0 = 3, μF_N = 0.1, c = 1e-4 under F = 0.1, H = 5 with N_t = 128 samples: the discrete
  // harmonic-balance problem turns back just below Ω = 1.172 and forward again (an S) — an effect
  // of aliasing at this N_t (with N_t ≥ 256 the curve does not fold; docs/stability.md §4) that
  // makes a well-defined test problem: Hill's method on its Jacobian sees ρ = +1 at each fold and
  // the stretch between them unstable.
  const hb::DiscreteSystem s = jenkins_oscillator(3.0, 0.1, 1e-4);
  const hb::Excitation e = force_at_dof0(0.1);
  FrfOptions o = options(0.5, 4.0, 5);
  o.stability_method = StabilityMethod::hill;
  const FrfCurve curve = trace_frf(s, e, o);
  ASSERT_TRUE(curve.completed()) << curve.message;
  ASSERT_EQ(curve.folds.size(), 2u);
  hb::HarmonicBalanceOptions ho;
  ho.harmonics = o.harmonics;
  ho.time_samples = o.time_samples;
  const hb::HarmonicBalance balance(s, e, ho);
  const hb::HillStability hill(balance);
  for (std::size_t k = 0; k < curve.folds.size(); ++k) {
    const FrfExtremum& fold = curve.folds[k];
    ASSERT_TRUE(fold.refined) << fold.message;
    EXPECT_LT(fold.value_bound, 1e-8);
    // The second method: Ω's extremum over the amplitude (first fold a maximum, second a minimum).
    const double a = fold.amplitude_h1;
    const double second = fold_by_golden_section(balance, 0.9 * a, 1.1 * a, k == 0 ? 1.0 : -1.0,
                                                 fold.coefficients, fold.omega);
    EXPECT_NEAR(fold.omega, second, fold.value_bound + 1e-9) << "fold " << k;
    // J is singular at a fold: a Floquet multiplier is +1 there. The fold is located to 1e-8 in Ω,
    // i.e. to ~1e-4 in the arclength of a quadratic turn, where J's smallest eigenvalue is O(1e-4).
    const hb::FloquetResult r = hill.evaluate(fold.coefficients, fold.omega);
    ASSERT_TRUE(r.ok) << r.message;
    double closest = 1e300;
    for (const auto& rho : r.multipliers) closest = std::min(closest, std::abs(rho - 1.0));
    EXPECT_LT(closest, 1e-3) << "fold " << k;
  }
  // Stable before the first fold and after the second, unstable between them.
  const double w0 = curve.folds[0].omega, w1 = curve.folds[1].omega;
  int unstable = 0;
  bool between = false;
  for (const auto& p : curve.points) {
    ASSERT_TRUE(p.stability_known);
    if (p.bifurcation == hb::Bifurcation::fold) between = !between;
    if (between) {
      EXPECT_FALSE(p.stable) << p.omega;
      EXPECT_GE(p.omega, w1 - 1e-9);
      EXPECT_LE(p.omega, w0 + 1e-9);
      ++unstable;
    } else {
      EXPECT_TRUE(p.stable) << p.omega << " (|ρ| = " << p.max_multiplier << ")";
    }
  }
  EXPECT_GE(unstable, 1);
}

TEST(FrfStability, ATurnWithoutAMultiplierCrossingIsAReversalNotAFold) {
  // k_T0/k = 0.3, μF_N = 0.1, c = 1e-4, F = 0.0046: the curve climbs the stuck resonance to slip
  // onset (Ω ≈ 1.1342) where the continuation turns back down the same branch (issue 23). Every
  // |ρ| stays below 1 on both sides: no fold. Should the continuation pass the kink one day, the
  // curve completes and has no reversal either way.
  const hb::DiscreteSystem s = jenkins_oscillator(0.3, 0.1, 1e-4);
  FrfOptions o = options(0.5, 2.0 * std::sqrt(1.3), 5);
  o.time_samples = 1024;
  const FrfCurve curve = trace_frf(s, force_at_dof0(0.00464158883361278), o);
  int reversals = 0;
  for (const auto& p : curve.points) {
    ASSERT_TRUE(p.stability_known);
    EXPECT_TRUE(p.stable) << p.omega;
    reversals += p.bifurcation == hb::Bifurcation::reversal ? 1 : 0;
    EXPECT_NE(p.bifurcation, hb::Bifurcation::fold) << p.omega;
  }
  EXPECT_TRUE(curve.folds.empty());
  if (curve.completed()) {
    EXPECT_EQ(reversals, 0);
  } else {
    EXPECT_EQ(curve.reason, StopReason::left_range) << curve.message;
    EXPECT_EQ(reversals, 1);
    EXPECT_NE(curve.message.find("reversed at"), std::string::npos) << curve.message;
  }
}

TEST(FrfStability, AutomaticStabilitySkipsLargeProblemsAndSaysSo) {
  FrfOptions o = options(0.5, 1.5, 3);
  o.stability = Stability::automatic;
  EXPECT_TRUE(computes_stability(o, 10));
  EXPECT_FALSE(computes_stability(o, 11));
  o.stability_method = StabilityMethod::hill;
  EXPECT_TRUE(computes_stability(o, 1));
  EXPECT_FALSE(computes_stability(o, 30));
  o.stability = Stability::never;
  EXPECT_FALSE(computes_stability(o, 1));
  o.stability = Stability::always;
  EXPECT_TRUE(computes_stability(o, 30));
}

}  // namespace
}  // namespace jointhb::continuation
