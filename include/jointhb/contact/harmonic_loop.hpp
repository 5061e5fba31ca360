#pragma once
// One contact point driven through its periodic steady state by a prescribed slip
//   g_T(t) = a cos ωt + Σ_j a_j cos(k_j ωt + φ_j)
// with an optional normal motion that modulates the normal force by the exponential law (eq. 6):
//   F_N(t) = F_N exp(-λ g_N(t)),  g_N(t) = a_N cos(ωt + φ_N).
// This is the engine of `jointhb loop`, the default case, and the W_D validation.

#include <memory>
#include <string>
#include <vector>

#include "jointhb/contact/periodic_state.hpp"

namespace jointhb::contact {

struct LoopHarmonic {
  int order = 1;           ///< k ≥ 1 (multiple of the fundamental)
  double amplitude = 0.0;  ///< a_k [m]
  double phase = 0.0;      ///< φ_k [rad]
};

/// The range of (a + Σ|a_k|) k_T0/(μ F_N), the slip over the stick range, in which a loop is
/// computed (LoopOptions::validate refuses the rest: its energies would over- or underflow).
inline constexpr double kMinSlipRatio = 1e-100;
inline constexpr double kMaxSlipRatio = 1e100;

struct LoopOptions {
  std::string law = "gaul-mayer";         ///< "gaul-mayer" or "jenkins"
  double exponent = 1.0 / 3.0;            ///< n ∈ (0, 1) (gaul-mayer)
  double friction_coefficient = 0.3;      ///< μ > 0
  double normal_force = 100.0;            ///< F_N [N] > 0 (mean normal load)
  double stiffness = 1.0e6;               ///< k_T0 [N/m] > 0
  bool stiffness_follows_normal = false;  ///< k_T(t) = k_T0 F_N(t)/F_N when true
  double amplitude = 1.0e-5;              ///< a [m] ≥ 0 (fundamental)
  std::vector<LoopHarmonic> harmonics;    ///< optional higher harmonics
  double normal_amplitude = 0.0;          ///< a_N [m] (normal motion)
  double normal_phase = 0.0;              ///< φ_N [rad]
  double normal_decay = 0.0;              ///< λ [1/m] ≥ 0 (needed when a_N ≠ 0)
  int time_samples = 256;                 ///< N ≥ 4

  [[nodiscard]] std::string validate() const;
};

struct LoopResult {
  PeriodicStateResult state;
  std::vector<double> phase;         ///< ωt_i [rad]
  std::vector<double> slip;          ///< g_T(t_i) [m]
  std::vector<double> force;         ///< F_T(t_i) [N]
  std::vector<double> normal_force;  ///< F_N(t_i) [N]
  double dissipation = 0.0;          ///< W_D [J] over the steady period
  double force_amplitude = 0.0;      ///< F̂ = max |F_T|
  double loading_span = 0.0;         ///< slip per half period on the loading branch
  bool formulas_apply = false;       ///< single harmonic, no normal motion: eq. (11)/(12) apply
  double dissipation_paper = 0.0;    ///< eq. (11)/(12) as printed at ĝ = loading_span
  double dissipation_paper_amplitude_reading = 0.0;  ///< eq. (11)/(12) at ĝ = a (the other reading)
  double dissipation_general = 0.0;                  ///< general-n formula at ĝ = loading_span
  double dissipation_jenkins = 0.0;                  ///< Jenkins closed form (law = jenkins)
  double full_slip_span = 0.0;  ///< g_max = μF_N/((1-n)k) (gaul-mayer); μF_N/k (jenkins)
  double seconds = 0.0;         ///< wall time of the periodic solve
};

/// Throws std::invalid_argument (naming the option) on invalid options.
LoopResult run_loop(const LoopOptions& options);

/// Factory: the tangential law by name ("gaul-mayer" with exponent n, or "jenkins").
std::shared_ptr<const TangentialLaw> make_tangential_law(const std::string& name, double exponent);

}  // namespace jointhb::contact
