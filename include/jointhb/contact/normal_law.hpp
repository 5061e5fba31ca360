#pragma once
// Normal contact of rough surfaces: the exponential pressure-gap law of Gaul & Mayer, eq. (6),
//   p_N(g_N) = p_N0 exp(-λ (g_N - g_N0)),  λ = 1/σ,
// whose normal stiffness per area is k_N = -dp_N/dg_N = λ p_N (the paper's k_N = -λ p_N is the
// slope dp_N/dg_N). The law never reaches p_N = 0: "gapping" means p_N has fallen below a floor.
//
// Sign convention used throughout jointhb: g_N is the normal gap (opening positive), and the normal
// traction conjugate to g_N in the virtual work (eq. 22) is t_N = -p_N (the paper's p_N = -t_N).
//
// Two further laws for interfaces that are not rough contacts (docs/zero-thickness-elements.md
// §"Other interface laws"):
//   exponential with a cutoff gap g_c (as commercial codes cut their exponential laws off):
//     p_N = p_N0 [e^{-λ(g_N - g_N0)} - e^{-λ(g_c - g_N0)}] for g_N < g_c, 0 beyond,   (N-1)
//     so that the pressure vanishes continuously at g_c; k_N = -dp_N/dg_N = λ p_N0 e^{-λ(g_N - g_N0)}
//     below g_c (it falls from λ p_c to 0 there, p_c = p_N0 e^{-λ(g_c - g_N0)}), 0 beyond;
//   linear penalty:  p_N = k_N (g_N0 - g_N) for g_N ≤ g_N0, 0 beyond; k_N constant up to g_N0  (N-2)
//     (at g_N0 itself the point is closed with p_N = 0: its normal stiffness holds there).
// For every law, stiffness() is -dp_N/dg_N and stiffness_slope() is dk_N/dg_N (-λ k_N for the
// exponential laws, 0 for the linear one), so that a tangential stiffness k_T = χ k_N has the
// derivative χ dk_N/dg_N.

#include <limits>
#include <string>

namespace jointhb::contact {

enum class NormalLawKind {
  exponential,  ///< eq. (6), with the optional cutoff gap of (N-1)
  linear,       ///< linear penalty, (N-2)
};

struct NormalLaw {
  double reference_pressure =
      1.0e6;                   ///< p_N0 [Pa] (or [N] in force mode), > 0: value at g_N = g_N0
  double decay = 1.0e5;        ///< λ = 1/σ [1/m], > 0: inverse standard deviation of roughness
  double reference_gap = 0.0;  ///< g_N0 [m]: gap at which p_N = p_N0 (linear: where p_N = 0)
  /// g_c [m] > g_N0 of (N-1), exponential law only; +∞: no cutoff (eq. 6 as it stands).
  double cutoff_gap = std::numeric_limits<double>::infinity();
  double penalty_stiffness = 0.0;  ///< k_N [Pa/m] > 0 of (N-2), linear law only
  NormalLawKind kind = NormalLawKind::exponential;  ///< last: {p_N0, λ, g_N0} still initialises

  /// Empty when valid, otherwise a message naming the field and the violated constraint.
  [[nodiscard]] std::string validate() const;

  /// p_N(g_N), eq. (6), (N-1) or (N-2). The exponent is capped so that the result stays finite for
  /// any closure.
  [[nodiscard]] double pressure(double gap) const;
  /// p_N(g_N + δ) − p_N(g_N) without cancellation, so that a tiny δ (the linear limit of a
  /// vibration about a preloaded state) keeps its relative accuracy: p_N(g_N) expm1(−λδ) for
  /// eq. (6) and (N-1) while both gaps carry pressure, −k_N δ for (N-2) while both are closed;
  /// the plain difference elsewhere (across a cutoff or a cap, where nothing cancels).
  [[nodiscard]] double pressure_change(double gap, double delta) const;
  /// k_N = -dp_N/dg_N (normal stiffness per area): λ p_N for eq. (6).
  [[nodiscard]] double stiffness(double gap) const;
  /// dk_N/dg_N: -λ k_N (exponential laws), 0 (linear law).
  [[nodiscard]] double stiffness_slope(double gap) const;
  /// A representative stiffness of the law, for floors: λ p_N0 (exponential), k_N (linear).
  [[nodiscard]] double stiffness_scale() const;
  /// The pressure scale of the gapping floor ε_gap (contact_point.hpp): p_N0 (exponential laws),
  /// 0 (linear law: a point is open exactly where k_N = 0, g_N > g_N0).
  [[nodiscard]] double open_reference() const;
  /// Gap at which the pressure equals p (inverse of the law), p > 0.
  [[nodiscard]] double gap_at_pressure(double p) const;
};

}  // namespace jointhb::contact
