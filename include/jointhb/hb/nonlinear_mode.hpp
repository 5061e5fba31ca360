#pragma once
// The extended periodic motion concept (EPMC; M. Krack, "Nonlinear modal analysis of
// nonconservative systems: extension of the periodic motion concept", Computers & Structures 154
// (2015) 59–71): the free, damped system is made periodic by a negative mass-proportional damping
// term,
//   M ẍ + (C − ξ M) ẋ + K x + f_nl(x) = 0,    ξ = 2 ζ Ω,
// and its periodic solutions, normalised in amplitude and phase, are the nonlinear mode.
//
// Unknowns Y = (X̂, Ω, ξ) with X̂ = X / q the harmonic coefficients divided by the modal amplitude
// q (so that Y stays O(1) over decades of q); parameter λ = log10 q. Equations (docs/theory.md §9):
//   R̂ = [S(Ω) − ξ S_M(Ω)] X̂ + F_nl(q X̂)/q = 0          (harmonic balance, scaled by 1/q)
//   a₁ᵀ M a₁ + b₁ᵀ M b₁ − 1 = 0                          (amplitude: fundamental q (Φc cos + Φs
//   sin)
//                                                         with Φcᵀ M Φc + Φsᵀ M Φs = 1)
//   b₁ᵀ M φ = 0                                          (phase: no sine part along the linear mode
//   φ)
// where S_M(Ω) holds the velocity blocks of M: [0, kΩ M; −kΩ M, 0] per harmonic k.
// The case must be symmetric about the origin (no static force, zero contact reference states):
// the scaling by q would blow up a constant offset at small amplitude.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "jointhb/hb/discrete_system.hpp"
#include "jointhb/hb/harmonic_balance.hpp"

namespace jointhb::hb {

struct NonlinearModeOptions {
  int mode = 1;            ///< ≥ 1: linear mode (of the system with contacts stuck) followed
  int harmonics = 7;       ///< H ≥ 1
  int time_samples = 128;  ///< N_t ≥ 2H + 2
  HarmonicSelection selection = HarmonicSelection::automatic;
  double periodic_tolerance = 1e-14;
  [[nodiscard]] std::string validate(int dofs) const;
};

/// Diagnostics of one point of the nonlinear mode.
struct NonlinearModeState {
  double amplitude = 0.0;             ///< q
  double omega = 0.0;                 ///< Ω [rad/s]
  double damping_ratio = 0.0;         ///< ζ = ξ / (2Ω)
  double dissipation = 0.0;           ///< Σ contact W_D from the Fourier coefficients [J]
  double viscous_dissipation = 0.0;   ///< work of C over the period [J]
  double injected_energy = 0.0;       ///< work of the EPMC term ξ M ẋ over the period [J]
  /// (W_D + viscous work) / (4π E), E = ½ Ω² q² (kinetic energy amplitude): the energy
  /// balance's damping ratio, equal to ζ up to the EPMC's truncation (the same definition as the
  /// FE damping curve's, hb/interface_mode.hpp)
  double damping_ratio_energy = 0.0;
  double slip_fraction = 0.0;         ///< share of contacts in microslip or gross slip
  int slipping_points = 0;            ///< contacts in microslip or gross slip (hb/contact_state.hpp)
  ContactStateCounts states;          ///< contacts per state (hb/contact_state.hpp)
};

class NonlinearModeResidual {
 public:
  /// Throws std::invalid_argument for an invalid system or options, a case that is not symmetric,
  /// or a mode number beyond the system's.
  NonlinearModeResidual(DiscreteSystem system, NonlinearModeOptions options);

  [[nodiscard]] Eigen::Index unknowns() const;  ///< n·m + 2
  [[nodiscard]] const HarmonicBalance& balance() const { return balance_; }
  /// Y of the linear mode (contacts stuck): X̂ = φ in a₁, Ω = ω, ξ = φᵀ C φ.
  [[nodiscard]] Eigen::VectorXd linear_start() const;
  /// Y of the same-numbered linear mode of the system with every friction contact slipping (the
  /// contacts removed: the limit q → ∞, where the slip forces μF_N are negligible against the
  /// elastic ones), signed to agree with φ: the start of a curve at large amplitude. Empty when
  /// the system has a normal contact (whose large-amplitude limit is not the contact-free system)
  /// or that mode has zero frequency.
  [[nodiscard]] std::optional<Eigen::VectorXd> slipping_start() const;
  [[nodiscard]] double linear_omega() const { return omega_; }
  [[nodiscard]] double linear_damping_ratio() const;

  /// Residual (n·m + 2) at (Y, λ = log10 q), with ∂/∂Y and ∂/∂λ when `jacobian`.
  struct Evaluation {
    Eigen::VectorXd residual;
    Eigen::MatrixXd d_state;
    Eigen::VectorXd d_parameter;
    bool ok = true;
    std::string message;
    double fourier_dissipation = 0.0;          ///< Σ contact W_D at (q X̂, Ω) [J]
    std::vector<ContactDiagnostics> contacts;  ///< per contact at (q X̂, Ω)
  };
  void evaluate(const Eigen::VectorXd& y, double lambda, bool jacobian, Evaluation& out) const;

  /// Physical diagnostics of a converged point. `at_point`, when given, is this residual's
  /// evaluation at exactly (y, λ) (e.g. the corrector's last): its contact results are reused
  /// instead of evaluating the contacts again.
  [[nodiscard]] NonlinearModeState state(const Eigen::VectorXd& y, double lambda,
                                         const Evaluation* at_point = nullptr) const;

 private:
  // (a_k, b_k): the DOF vectors of harmonic `order` in DOF-major coefficients x.
  [[nodiscard]] std::pair<Eigen::VectorXd, Eigen::VectorXd> harmonic(const Eigen::VectorXd& x,
                                                                     int order) const;
  // The velocity blocks of a symmetric matrix A times the coefficients: Σ_k k [A b_k; −A a_k].
  [[nodiscard]] Eigen::VectorXd velocity_product(const SparseMatrix& a,
                                                 const Eigen::VectorXd& x) const;
  DiscreteSystem system_;
  NonlinearModeOptions options_;
  HarmonicBalance balance_;
  // Y of a mass-normalised linear mode: `shape` in a₁, Ω = ω, ξ = 2ζω of that mode.
  [[nodiscard]] Eigen::VectorXd mode_start(const Eigen::VectorXd& shape, double omega, double xi) const;

  Eigen::VectorXd phi_;    // linear mode, mass-normalised
  Eigen::VectorXd m_phi_;  // M φ
  double omega_ = 0.0;
};

}  // namespace jointhb::hb
