#pragma once
// Alternating frequency/time (AFT) evaluation of one 1D friction contact element:
//   gap samples g(t_i) → periodic steady-state force F(t_i) (contact::solve_periodic_state)
// and, for the Jacobian, the exact derivative of the force coefficients with respect to the gap
// coefficients, ∂F/∂G = A · ∂F(t)/∂g(t) · E (A: analysis, E: synthesis, hb/fourier.hpp), from
// the scalar recursion of the periodic-state sensitivity (docs/theory.md, eq. T-10):
//   δF_{i+1} = a_i δF_i + b_i (δg_{i+1} − δg_i),   δF_0 = r_N/(1 − Π a_i)  (or the anchor
//   k (δg_0) when the contact sticks throughout and 1 − Π a_i vanishes).
// A Jenkins contact whose elastic trial F_ref + k (g − g_ref) stays within μF_N at every sample
// sticks throughout: evaluated as that spring (`skipped`), which is what the periodic solve
// returns.

#include <Eigen/Core>
#include <string>

#include "jointhb/contact/tangential_law.hpp"
#include "jointhb/hb/contact_state.hpp"
#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/hb/fourier.hpp"

namespace jointhb::hb {

struct ContactAftOptions {
  double periodic_tolerance = 1e-14;  ///< (0, 1e-3]
  bool skip_stuck = true;             ///< linear-spring shortcut for Jenkins contacts that stick
  bool jacobian = false;              ///< compute ∂F/∂G
};

struct ContactAftResult {
  Eigen::VectorXd force_samples;  ///< F(t_i), size N
  Eigen::MatrixXd d_force;        ///< ∂F/∂G (m × m) when requested
  double dissipation = 0.0;       ///< W_D over the period [J]
  bool stuck = true;              ///< no slip over the period
  bool skipped = false;           ///< linear-spring shortcut taken
  double limit_share = 0.0;       ///< share of the samples with |F| at the slip limit μF_N
  double limit_ratio = 0.0;       ///< max_i |F(t_i)|/(μF_N)
  ContactState state = ContactState::stuck;  ///< from the above (hb/contact_state.hpp)
  /// Periodic state converged. A per-evaluation flag of the AFT loop, kept a bool rather than a
  /// Status (contact/termination.hpp): see hb::ContactDiagnostics::converged.
  bool converged = true;
  int iterations = 0;
  std::string message;
};

/// `gap_samples`: g(t_i) (size N); `gap_coefficients`: the same signal's coefficients (size m).
ContactAftResult evaluate_contact(const ContactElement& element, const contact::TangentialLaw& law,
                                  const FourierBasis& basis, const Eigen::VectorXd& gap_samples,
                                  const ContactAftOptions& options);

}  // namespace jointhb::hb
