#pragma once
// The exponential normal contact of Gaul & Mayer, eq. (6), p_N = p_N0 exp(−λ (g_N − g_N0)), as a
// one-dimensional element about its preloaded state (discrete models, hb/discrete_system.hpp):
//   F(g) = F_N0 (1 − e^{−λ g}),   λ = k_N / F_N0,                                         (N-3)
// where g is the opening of the gap from the preloaded state (g > 0 opens), F_N0 the preload that
// the static load balances, and F(g) = F_N0 − F_N(g) the change of the contact force, acting like
// a spring force (+F on the opening DOF). Its tangent F'(g) = λ (F_N0 − F) = k_N e^{−λ g} is k_N at
// the preload; the element softens as the gap opens (F → F_N0: the contact unloads fully) and
// stiffens exponentially as it closes. Expanded about the preload,
//   F = k_N (g − λ g²/2 + λ² g³/6 − …),
// so a mass m on it (alone) has the backbone ω = ω_0 (1 − λ² a²/24 + O(a⁴)), ω_0² = k_N/m
// (Lindstedt–Poincaré with the quadratic and cubic terms: ω = ω_0 + (9 α₃ ω_0² − 10 α₂²) a²/(24 ω_0³),
// α₂ = −k_N λ/(2m), α₃ = k_N λ²/(6m); Nayfeh & Mook, Nonlinear Oscillations, 1979, §4.1).
//
// The law is elastic and has no memory; it is written as an exact increment so that the
// incremental consumers of TangentialLaw (time integration) use it unchanged:
//   F_1 = F_N0 − (F_N0 − F_0) e^{−λ Δg}                                                 (N-3')
// with the slip limit of TangentialLimits read as F_N0 and the stiffness as k_N. It dissipates
// nothing. Harmonic balance evaluates F(g) directly (hb/contact_aft.cpp).

#include "jointhb/contact/tangential_law.hpp"

namespace jointhb::contact {

class PreloadedNormalLaw final : public TangentialLaw {
 public:
  [[nodiscard]] std::string_view name() const override { return "normal-exponential"; }

  /// F(g) of (N-3) and its tangent F'(g) for preload `preload` > 0 and stiffness `stiffness` > 0.
  [[nodiscard]] static double force(double gap, double preload, double stiffness);
  [[nodiscard]] static double tangent(double gap, double preload, double stiffness);

 protected:
  [[nodiscard]] ScalarStep evaluate(double f0, double slip, const TangentialLimits& limits,
                                    bool dissipation) const override;
};

}  // namespace jointhb::contact
