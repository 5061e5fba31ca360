#pragma once
// Multi-harmonic balance (MHB) of a discrete system with friction contacts, with the contact forces
// evaluated by the alternating frequency/time scheme (AFT) through the laws' exact periodic steady
// state (contact/periodic_state.hpp).
//
// Unknowns: the Fourier coefficients X of all DOFs (hb/fourier.hpp; DOF-major: X[i·m + j] is
// coefficient j of DOF i, m = basis size). Residual (docs/theory.md, eq. T-9):
//   R(X, Ω) = S(Ω) X + F_nl(X) − F_ex,
// where S(Ω) is block-diagonal in the harmonics k:
//   S_0 = K,   S_k = [ K − (kΩ)² M    kΩ C        ]   acting on (a_k, b_k) of
//                    [ −kΩ C          K − (kΩ)² M ]   x = Σ a_k cos kΩt + b_k sin kΩt,
// F_ex the coefficients of f_ex(t) and F_nl the coefficients of the contact forces: per contact,
// g(t_i) from the coefficients of g = x_a − x_b (inverse FFT), the periodic tangential force
// F(t_i) (periodic steady state), and its coefficients (forward FFT), scattered +F to a, −F to b.
// The laws are rate independent, so F_nl does not depend on Ω.
//
// Jacobian: ∂R/∂X = S(Ω) + ∂F_nl/∂X with ∂F_nl/∂G = A · (∂F(t)/∂g(t)) · E per contact, where the
// middle factor is the sensitivity of the periodic state (contact::periodic_sensitivity), exact;
// ∂R/∂Ω = S'(Ω) X.
//
// Shortcuts (same answer to round-off, tested): a Jenkins contact whose elastic trial force stays
// within its slip limit at every sample sticks throughout and is evaluated as the linear spring
// F = F_ref + k (g − g_ref) without AFT; a symmetric case may keep odd harmonics only.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "jointhb/hb/contact_state.hpp"
#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/hb/fourier.hpp"

namespace jointhb::hb {

/// Which harmonics harmonic balance keeps.
enum class HarmonicSelection {
  automatic,  ///< odd only when the case is symmetric (is_symmetric), else all
  all,        ///< 0, 1, ..., H
  odd,        ///< 1, 3, 5, ... ≤ H (an error for a case that is not symmetric)
};

/// True when the response may be sought with odd harmonics only: no static force, only odd
/// forcing harmonics, and odd contacts (ContactElement::odd: friction laws with zero reference
/// force and slip; a normal element is not odd).
bool is_symmetric(const DiscreteSystem& system, const Excitation& excitation);

struct HarmonicBalanceOptions {
  int harmonics = 7;       ///< H ≥ 1
  int time_samples = 128;  ///< N_t ≥ 2H + 2, samples per period in the AFT
  HarmonicSelection selection = HarmonicSelection::automatic;
  double periodic_tolerance = 1e-14;  ///< (0, 1e-3]: contact periodic-state tolerance (relative)
  bool skip_stuck_contacts = true;    ///< evaluate Jenkins contacts that stick as linear springs
  [[nodiscard]] std::string validate() const;  ///< empty when valid; names the field
};

/// Per-contact diagnostics of one evaluation.
struct ContactDiagnostics {
  double dissipation = 0.0;  ///< W_D over one period [J] (periodic state, exact on the samples)
  /// W_D from the Fourier coefficients, π Σ_k k (a_k^F b_k^g − b_k^F a_k^g) (docs/theory.md §7): the
  /// work of the truncated force that harmonic balance balances; → dissipation as H grows.
  double fourier_dissipation = 0.0;
  bool stuck = true;     ///< no slip during the period
  bool skipped = false;  ///< evaluated as a linear spring (no AFT)
  ContactState state = ContactState::stuck;  ///< hb/contact_state.hpp
  double limit_ratio = 0.0;                  ///< max_t |F|/(μF_N)
  int iterations = 0;    ///< periodic-state iterations
  /// The contact's periodic state converged. A bool, not a Status (contact/termination.hpp): one
  /// per contact per residual evaluation, inside the Newton loop, where a message string would be
  /// an allocation each; it is not how a computation ended but a validity flag of one evaluation,
  /// which the continuation turns into its StopReason (and so into a status) when it matters.
  bool converged = true;
};

/// π Σ_k k (a_k^F b_k^g − b_k^F a_k^g): the work of F on g over one period from coefficients.
double fourier_work(const FourierBasis& basis, const Eigen::VectorXd& force,
                    const Eigen::VectorXd& gap);

/// Cumulative wall time per phase [s].
struct HarmonicBalanceTimings {
  double aft = 0.0;       ///< FFTs, periodic states and their sensitivities
  double assembly = 0.0;  ///< S(Ω), its derivative and the scatter of contact blocks
  int evaluations = 0;
  int jacobians = 0;
};

struct HarmonicBalanceEvaluation {
  Eigen::VectorXd residual;        ///< R
  Eigen::MatrixXd d_coefficients;  ///< ∂R/∂X (when requested)
  Eigen::VectorXd d_omega;         ///< ∂R/∂Ω (when requested)
  std::vector<ContactDiagnostics> contacts;
  double dissipation = 0.0;          ///< Σ contact W_D [J] (periodic states)
  double fourier_dissipation = 0.0;  ///< Σ contact W_D from the Fourier coefficients [J]
  /// false when a contact's periodic state did not converge: a validity flag of one residual
  /// evaluation (see ContactDiagnostics::converged), not a status; `message` names the contact.
  bool ok = true;
  std::string message;
};

class HarmonicBalance {
 public:
  /// Throws std::invalid_argument on an invalid system, excitation or options (and for
  /// selection = odd on a case that is not symmetric).
  HarmonicBalance(DiscreteSystem system, Excitation excitation, HarmonicBalanceOptions options);
  ~HarmonicBalance();
  HarmonicBalance(HarmonicBalance&&) noexcept;
  HarmonicBalance& operator=(HarmonicBalance&&) noexcept;

  [[nodiscard]] const FourierBasis& basis() const;
  [[nodiscard]] const DiscreteSystem& system() const;
  [[nodiscard]] const HarmonicBalanceOptions& options() const;
  [[nodiscard]] Eigen::Index unknowns() const;  ///< n · basis().size()
  /// Index of coefficient j (basis order) of DOF i in X.
  [[nodiscard]] Eigen::Index index(int dof, int coefficient) const;

  /// R(X, Ω), with ∂R/∂X and ∂R/∂Ω when `jacobian` is true.
  void evaluate(const Eigen::VectorXd& coefficients, double omega, bool jacobian,
                HarmonicBalanceEvaluation& out) const;

  /// The harmonic coefficients of the linear system with every contact stuck (k_T0 springs about
  /// their reference state): the initial guess of a continuation and the small-force limit.
  /// `forcing_scale` multiplies F_ex (0: the reference state alone).
  [[nodiscard]] Eigen::VectorXd stuck_solution(double omega, double forcing_scale = 1.0) const;

  /// F_ex: the coefficients of the excitation.
  [[nodiscard]] const Eigen::VectorXd& forcing() const;

  /// x_dof(t_i) over one period on the AFT samples.
  [[nodiscard]] Eigen::VectorXd time_history(const Eigen::VectorXd& coefficients, int dof) const;
  /// |fundamental| √(a₁² + b₁²) of a DOF (0 when the basis lacks harmonic 1).
  [[nodiscard]] double fundamental_amplitude(const Eigen::VectorXd& coefficients, int dof) const;
  /// The largest slip over the stick range, max_t |g(t) − g_ref| k_T0 / (μ F_N), of the contacts
  /// (0 without contacts): the curve drivers stop where it leaves the range in which the laws are
  /// computed (contact::kMaxSlipRatio, harmonic_loop.hpp).
  [[nodiscard]] double max_slip_ratio(const Eigen::VectorXd& coefficients) const;

  [[nodiscard]] HarmonicBalanceTimings timings() const;
  void reset_timings();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace jointhb::hb
