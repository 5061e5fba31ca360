#pragma once
// The Jenkins element: a linear spring k_T0 in series with a Coulomb slider of limit μ F_N
// (elastic–perfectly-plastic). The classic comparison law for microslip models: it sticks
// completely below the limit and dissipates nothing until |F_T| reaches μ F_N.

#include "jointhb/contact/tangential_law.hpp"

namespace jointhb::contact {

class JenkinsLaw final : public TangentialLaw {
 public:
  [[nodiscard]] std::string_view name() const override { return "jenkins"; }
  [[nodiscard]] bool sticks_below_limit() const override { return true; }

 protected:
  /// The dissipation of Jenkins costs one product and is always evaluated.
  [[nodiscard]] ScalarStep evaluate(double f0, double slip, const TangentialLimits& limits,
                                    bool dissipation) const override;
};

}  // namespace jointhb::contact
