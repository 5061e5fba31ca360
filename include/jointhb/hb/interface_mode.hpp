#pragma once
// The nonlinear mode (EPMC, as in hb/nonlinear_mode.hpp) of a preloaded FE joint in the
// modal/interface form of hb/interface_balance.hpp (docs/theory.md §11, eq. T-29).
//
// Unknowns Ŷ = (ŷ, Ω, ξ) with ŷ = y / q, q the amplitude of the followed mode's modal coordinate
// (its cosine coefficient of harmonic 1), parameter λ = log10 q:
//   R(q ŷ, Ω, ξ) / q = 0                    (harmonic balance with the EPMC damping −ξ M, no load)
//   ŷ[η_f, a₁] − 1 = 0,   ŷ[η_f, b₁] = 0    (amplitude and phase of the followed mode)
// The mean coefficients are scaled by q too: with the static mean tangential closure (T-28) they
// are O(q²) (rectification of the exponential normal law), so ŷ stays bounded as q → 0.
// ζ = ξ / (2Ω); the energy check ζ_E = (W_contact + W_viscous) / (2π Ω² q²) uses the dissipation
// over one period of the contact (Σ A_p W_D) and of the kept modes' viscous damping.

#include <Eigen/Core>
#include <functional>
#include <string>

#include "jointhb/hb/interface_balance.hpp"
#include "jointhb/hb/interface_local_preconditioner.hpp"

namespace jointhb::hb {

struct InterfaceModeOptions {
  int mode = 1;  ///< ≥ 1: elastic kept mode followed (1 = lowest elastic mode)
  InterfaceBalanceOptions balance;
  [[nodiscard]] std::string validate(const InterfaceModel& model) const;
};

struct InterfaceModeState {
  double amplitude = 0.0;             ///< q (modal coordinate of the followed mode) [m √kg]
  double omega = 0.0;                 ///< Ω [rad/s]
  double damping_ratio = 0.0;         ///< ξ / (2Ω)
  double damping_ratio_energy = 0.0;  ///< (W_contact + W_viscous) / (2π Ω² q²)
  double dissipation = 0.0;           ///< Σ A_p W_D [J]
  double fourier_dissipation = 0.0;   ///< work of the truncated contact forces [J]
  double injected_energy = 0.0;       ///< work of the EPMC term ξ over the period, kept modes [J]
  double viscous_dissipation = 0.0;   ///< π Ω Σ_j c_j Σ_k k² (a_jk² + b_jk²), kept modes [J]
  int open_points = 0, slipping_points = 0;
  ContactStateCounts states;  ///< points per contact state (hb/contact_state.hpp)
};

class InterfaceModeResidual {
 public:
  /// Throws std::invalid_argument for invalid options or model.
  InterfaceModeResidual(InterfaceModel model, InterfaceModeOptions options);

  [[nodiscard]] const InterfaceBalance& balance() const { return balance_; }
  [[nodiscard]] Eigen::Index unknowns() const { return balance_.unknowns() + 2; }
  [[nodiscard]] int followed_mode() const { return mode_; }  ///< index among kept modes
  [[nodiscard]] double linear_omega() const;
  [[nodiscard]] double linear_damping_ratio() const;
  /// Ŷ of the linear mode: η_f a₁ = 1 (its gaps Gφ_f), Ω = ω_f, ξ = c_f.
  [[nodiscard]] Eigen::VectorXd linear_start() const;

  struct Evaluation {
    Eigen::VectorXd residual;
    Eigen::MatrixXd d_state;
    Eigen::VectorXd d_parameter;
    InterfaceBalanceEvaluation balance;  ///< at y = q ŷ
    bool ok = true;
    std::string message;
  };
  /// With balance options dense_jacobian = false, d_state stays empty (use apply_jacobian).
  void evaluate(const Eigen::VectorXd& y_hat, double lambda, bool jacobian, Evaluation& out) const;
  /// ∂residual/∂Ŷ · v without the matrix, from an evaluation `at` (with the Jacobian) at
  /// (Ŷ, λ): [J v_y + (∂R/∂Ω v_Ω + ∂R/∂ξ v_ξ)/q; v_y[η_f, a₁]; v_y[η_f, b₁]].
  /// single_precision: as InterfaceBalance::apply_jacobian (an inexact inner product).
  [[nodiscard]] Eigen::VectorXd apply_jacobian(const Evaluation& at, const Eigen::VectorXd& y_hat,
                                               double lambda, const Eigen::VectorXd& v,
                                               bool single_precision = false) const;
  /// Approximate inverse of ∂residual/∂Ŷ at `at`: an approximate inverse of the balance's
  /// Jacobian (`kind`: the point-local J_loc⁻¹ of eq. T-34, or the harmonic block-Jacobi J̃⁻¹ of
  /// eq. T-32c) bordered exactly by the Ω, ξ columns and the two normalisation rows (block
  /// elimination with a 2 × 2 Schur complement).
  [[nodiscard]] std::function<Eigen::VectorXd(const Eigen::VectorXd&)> preconditioner(
      const Evaluation& at, const Eigen::VectorXd& y_hat, double lambda,
      InterfacePreconditioner kind = InterfacePreconditioner::point_local) const;
  /// Diagnostics of a converged point; `at_point` (an evaluation at exactly (Ŷ, λ)) avoids a new
  /// AFT evaluation.
  [[nodiscard]] InterfaceModeState state(const Eigen::VectorXd& y_hat, double lambda,
                                         const Evaluation* at_point = nullptr) const;

 private:
  InterfaceBalance balance_;
  int mode_ = 0;
};

}  // namespace jointhb::hb
