#pragma once
// A discrete (lumped) mechanical system with friction contacts:
//   M ẍ + C ẋ + K x + f_nl(x) = f_ex(t)
// M, C, K are n × n (sparse storage; dense input converts). Each contact element acts on the
// relative displacement g of one DOF to ground (g = x_a) or of two DOFs (g = x_a - x_b) through a
// 1D tangential law (Jenkins or Gaul–Mayer, eq. 10) with constant slip limit μF_N and stiffness
// k_T0, or through the exponential normal law about its preload F_N0 (law "normal-exponential",
// contact/preloaded_normal_law.hpp, N-3: g is then the opening of the gap and k_T0 holds k_N);
// its force F(t) acts as +F on DOF a and -F on DOF b. The excitation is
//   f_ex(t) = f_static + Σ_j f_j cos(h_j Ω t).
// This is the model that harmonic balance (hb/harmonic_balance.hpp) and the time-domain reference
// (timeint/) share; later a condensed FE model maps onto the same matrices and contacts.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "jointhb/contact/tangential_law.hpp"

namespace jointhb::hb {

using SparseMatrix = Eigen::SparseMatrix<double>;

/// One contact between a DOF and ground or between two DOFs: friction, or normal (N-3).
struct ContactElement {
  std::string law = "jenkins";        ///< "jenkins", "gaul-mayer" or "normal-exponential"
  double exponent = 1.0 / 3.0;        ///< n ∈ (0, 1) (gaul-mayer only)
  int dof_a = 0;                      ///< g = x[dof_a] - x[dof_b] (x[dof_b] ≡ 0 if dof_b < 0)
  int dof_b = -1;                     ///< -1: to ground
  double friction_coefficient = 0.3;  ///< μ > 0 (friction laws only)
  double normal_force = 1.0;          ///< F_N [N] > 0 (normal law: the preload F_N0)
  double stiffness = 1.0;             ///< k_T0 [N/m] > 0 (normal law: k_N at the preload)
  double reference_force = 0.0;       ///< tangential force of the reference (preloaded) state [N]
  double reference_slip = 0.0;        ///< g of the reference state [m]

  /// The exponential normal law about its preload (no friction, no reference offsets).
  [[nodiscard]] bool normal() const { return law == "normal-exponential"; }
  /// A reference state other than zero force at zero slip (the response then has a static part).
  [[nodiscard]] bool has_reference_offset() const { return reference_force != 0.0 || reference_slip != 0.0; }
  /// F(−g) = −F(g): a friction law about a zero reference state (a normal element is not odd), so
  /// that a symmetric forcing keeps odd harmonics only.
  [[nodiscard]] bool odd() const { return !normal() && !has_reference_offset(); }
  /// μF_N; for a normal element F_N0, the bound its force F = F_N0 − F_N(g) tends to as it opens.
  [[nodiscard]] double slip_limit() const {
    return normal() ? normal_force : friction_coefficient * normal_force;
  }
  /// Relative displacement g = x_a - x_b.
  [[nodiscard]] double gap(const Eigen::Ref<const Eigen::VectorXd>& x) const {
    return x[dof_a] - (dof_b >= 0 ? x[dof_b] : 0.0);
  }
};

/// One harmonic forcing term f_j cos(h_j Ω t) on one DOF.
struct HarmonicForce {
  int dof = 0;
  double amplitude = 0.0;  ///< [N]
  int harmonic = 1;        ///< h_j ≥ 1
};

/// The forcing of one level: static part plus harmonic terms.
struct Excitation {
  Eigen::VectorXd static_force;       ///< size n or empty (zero)
  std::vector<HarmonicForce> forces;  ///< cos terms

  /// f_ex(t) for the fundamental frequency Ω.
  [[nodiscard]] Eigen::VectorXd at(double omega, double time, int dofs) const;
  [[nodiscard]] bool has_static_part() const;
};

struct DiscreteSystem {
  SparseMatrix mass;       ///< M, symmetric positive definite
  SparseMatrix damping;    ///< C, symmetric positive semi-definite (may be empty: zero)
  SparseMatrix stiffness;  ///< K, symmetric positive semi-definite
  std::vector<ContactElement> contacts;

  [[nodiscard]] int dofs() const { return static_cast<int>(mass.rows()); }
  /// Empty when consistent (sizes, symmetry, DOF indices, contact parameters), else a one-line
  /// description of the first violated constraint naming the field ("contacts[1].dofs: ...").
  [[nodiscard]] std::string validate() const;
  /// The contact's tangential law object (built from law and exponent).
  [[nodiscard]] static std::shared_ptr<const contact::TangentialLaw> make_law(
      const ContactElement& element);
};

/// C = M Φ diag(2 ζ_i ω_i) Φᵀ M from the mass-normalised modes of (K, M) (ω_i ascending), with
/// ζ_i given for the first ζ.size() modes (zero for the others). Throws std::invalid_argument when
/// M is not positive definite or ζ has more entries than the system has modes.
SparseMatrix modal_damping_matrix(const SparseMatrix& mass, const SparseMatrix& stiffness,
                                  const std::vector<double>& damping_ratios);

/// Natural frequencies ω_i [rad/s] (ascending) and mass-normalised mode shapes (columns) of the
/// linear system K (+ stuck contact stiffness when `with_stuck_contacts`), dense eigensolver.
struct LinearModes {
  Eigen::VectorXd omega;
  Eigen::MatrixXd shapes;
};
LinearModes linear_modes(const DiscreteSystem& system, bool with_stuck_contacts);

/// K plus the k_T0 of every contact element (the linearisation of a fully stuck joint).
SparseMatrix stuck_stiffness(const DiscreteSystem& system);

}  // namespace jointhb::hb
