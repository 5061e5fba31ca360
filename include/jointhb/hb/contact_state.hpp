#pragma once
// What a contact point does over one period of a harmonic-balance solution, from the law's own
// variables (docs/theory.md §14): the share of the period it is open, the share it spends at the
// slip limit |t_T| = μ p_N, and its force ratio max_t |t_T|/(μ p_N) over the closed samples.
//
//   open        open at every sample
//   gapping     open during part of the period
//   gross slip  at the slip limit during part of the period (Coulomb sliding, |t_T| = μ p_N)
//   stuck       never at the limit, and either the law is linear below its limit (Jenkins: elastic
//               throughout) or the force ratio stays below `stuck_ratio` (stuck-like)
//   microslip   the rest: closed, below the limit, on the law's nonlinear branch
//
// Why a force-ratio threshold for laws without a linear range: the Gaul–Mayer law (eq. 10) softens
// from the first slip on, dF_T/dg_T = k_T0 (1 − |F_T|/F_s)^n, so every point of a vibrating joint
// "slips". Along a loop whose force ratio stays below r the tangent stiffness stays within a
// factor (1 − r)^n ≥ 1 − r of k_T0 (0 < n < 1): with the default r = 0.01 a stuck-like point is
// within 1 % of stuck for any n, and its dissipation per cycle, of order n r³ F_s²/k_T0 (T-7 at
// small r), is negligible beside that of a point near the limit.

#include <array>
#include <span>
#include <string>
#include <string_view>

namespace jointhb::hb {

enum class ContactState { stuck = 0, microslip = 1, gross_slip = 2, gapping = 3, open = 4 };
inline constexpr int kContactStateCount = 5;

/// "stuck", "microslip", "gross_slip", "gapping", "open" (the names of output columns and keys).
[[nodiscard]] std::string_view contact_state_name(ContactState state);

/// What classify_contact_state needs of one point's periodic state.
struct ContactStateInputs {
  double open_fraction = 0.0;  ///< share of the samples below the gapping floor
  double limit_share = 0.0;    ///< share of the samples with |t_T| at the slip limit
  double limit_ratio = 0.0;    ///< max over the closed samples of |t_T|/(μ p_N) (0 when μ = 0)
  bool law_sticks_below_limit = false;  ///< the law is linear below its limit (Jenkins)
};

struct ContactStateOptions {
  /// Force ratio below which a point of a law without a linear range is stuck-like, in (0, 1)
  double stuck_ratio = 0.01;
  /// |t_T| ≥ (1 − limit_tolerance) μ p_N counts as at the limit (round-off of the laws' capping)
  double limit_tolerance = 1e-9;
  [[nodiscard]] std::string validate() const;  ///< empty when valid; names the field
};

[[nodiscard]] ContactState classify_contact_state(const ContactStateInputs& inputs,
                                                  const ContactStateOptions& options = {});

/// Points per state, indexed by ContactState.
struct ContactStateCounts {
  std::array<int, kContactStateCount> count{};
  void add(ContactState state) { ++count[static_cast<std::size_t>(state)]; }
  [[nodiscard]] int operator[](ContactState state) const { return count[static_cast<std::size_t>(state)]; }
  [[nodiscard]] int total() const;
  /// Points that slip: microslip + gross slip.
  [[nodiscard]] int slipping() const { return (*this)[ContactState::microslip] + (*this)[ContactState::gross_slip]; }
};

/// Share of the samples at the slip limit and the largest force ratio |t_T,i|/L_i over the samples
/// with L_i > 0, from the tangential traction magnitudes |t_T,i| and slip limits L_i = μ p_N,i
/// (equal sizes; throws std::invalid_argument otherwise).
struct LimitMeasures {
  double share = 0.0;
  double ratio = 0.0;
};
[[nodiscard]] LimitMeasures limit_measures(std::span<const double> traction_magnitude,
                                           std::span<const double> limit, double limit_tolerance);

}  // namespace jointhb::hb
