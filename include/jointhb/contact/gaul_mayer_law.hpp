#pragma once
// The Gaul–Mayer microslip law, eq. (10) of Gaul & Mayer:
//   dF_T/dg_T = k_T0 (1 - |F_T|/(μ F_N))^n   while |F_T| increases (loading), 0 < n < 1,
//   dF_T/dg_T = k_T0                          while |F_T| decreases (elastic unloading),
//   |F_T| = μ F_N                             once the limit is reached (Coulomb sliding).
// n = 1/3 is Mindlin's sphere (eq. 9). Exact integration: on a loading branch
//   (1 - |F|/μF_N)^(1-n)  falls linearly with the slip, at rate (1-n) k_T0/(μ F_N),
// so the virgin curve reaches full slip after g_max = μ F_N/((1-n) k_T0) (eq. 8 for n = 1/3).
// An unloading increment that passes through F_T = 0 is split there: beyond zero the loading
// branch applies in the opposite direction.

#include <string>

#include "jointhb/contact/tangential_law.hpp"

namespace jointhb::contact {

class GaulMayerLaw final : public TangentialLaw {
 public:
  /// exponent: n of eq. (10), in (0, 1). Throws std::invalid_argument otherwise.
  explicit GaulMayerLaw(double exponent);

  [[nodiscard]] std::string_view name() const override { return "gaul-mayer"; }
  [[nodiscard]] double exponent() const { return n_; }

  /// Force reached on the virgin (loading-from-zero) curve after slip s ≥ 0, eq. (8) generalised:
  ///   |F| = μF_N [1 - (1 - s/g_max)^(1/(1-n))],  g_max = μF_N/((1-n)k).
  [[nodiscard]] double virgin_force(double s, const TangentialLimits& limits) const;

 protected:
  [[nodiscard]] ScalarStep evaluate(double f0, double slip, const TangentialLimits& limits,
                                    bool dissipation) const override;

 private:
  double n_;
};

}  // namespace jointhb::contact
