#pragma once
// The dynamic analyses of a finite-element case (docs/case-files.md, "Finite-element cases:
// dynamics"): damping curves (EPMC) and nonlinear FRFs of the preloaded joint by harmonic balance
// in modal/interface form (docs/theory.md §11), with the settings of the condensation stage.
//
//   analysis:
//     damping: {ratio: 0.005}                 # or {ratio: ζ, frequency_hz: f} or
//                                             #    {rayleigh: {alpha: a [1/s], beta: b [s]}}
//     reduction: {cutoff_factor: 20, contact_patch: 0}   # or {cutoff_hz: 25000}
//     excitation: {point: [0.16, 0.015, 0.008], direction: [0, 0, 1]}
//     outputs: [{name: tip, point: [0.16, 0.015, 0.008], direction: [0, 0, 1]}]
//     nonlinear_modes: {mode: 1, log10_amplitude: [-9, -4], frequency_drop: 0.05, harmonics: 1}
//     frf: {frequency_hz: [900, 1000], force: [1, 5, 20], harmonics: 1}

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/hb/interface_balance.hpp"

namespace jointhb::io {

/// A direction at a mesh node: the unit load of the excitation, or an output u_o = dᵀ u_node.
struct FeNodeDirection {
  std::string name;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      ///< as written [m]
  int node = 0;                                         ///< the mesh node nearest to `point`
  double distance = 0.0;                                ///< |x_node − point| [m]
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  ///< unit vector

  /// The functional over the full mesh DOFs (3 per node): `direction` at `node`.
  [[nodiscard]] Eigen::VectorXd functional(int num_dofs) const;
};

struct FeNonlinearModesSpec {
  std::vector<int> modes{1};  ///< elastic modes followed (1 = the lowest elastic mode), ascending
  double log10_amplitude_start = -9.0, log10_amplitude_end = -4.0;  ///< λ = log10 q [m √kg]
  /// > 0: stop a curve once its frequency has moved by this fraction of the linear one (it falls
  /// into macroslip; it rises where open regions clap); 0: run to log10_amplitude_end.
  double frequency_drop = 0.0;
  /// Accepted points (spread in log q, the first and the last among them) written as VTK fields:
  /// contact surfaces always, the volume too when volume_fields (eq. T-33; the condensation then
  /// keeps and caches n × (n_s + 3P_d) doubles). 0: no fields.
  int fields = 5;
  bool volume_fields = true;
  hb::InterfaceBalanceOptions balance;
  /// The library's defaults of the interface drivers (matrix-free GMRES, steps, tolerances): the
  /// case's `continuation:` keys change only what they name.
  continuation::Options continuation = continuation::InterfaceBackboneOptions{}.continuation;
};

struct FeFrfSpec {
  double omega_start = 0.0, omega_end = 0.0;  ///< [rad/s]
  std::vector<double> forces;                 ///< F [N] of F cos Ωt along the excitation, one curve each
  int output = 0;                             ///< index into FeDynamicsSpec::outputs
  hb::InterfaceBalanceOptions balance;
  continuation::Options continuation = continuation::InterfaceFrfOptions{}.continuation;  ///< as above
};

struct FeDynamicsSpec {
  // ---- analysis.damping: C = a M + b K_t ---------------------------------------------------
  double rayleigh_mass = 0.0;       ///< a [1/s]
  double rayleigh_stiffness = 0.0;  ///< b [s]
  /// > 0: b = 2ζ/ω at damping_frequency_hz (0: at the first followed mode's linear frequency, or
  /// the first elastic mode for an FRF-only case); a = 0.
  double damping_ratio = 0.0;
  double damping_frequency_hz = 0.0;
  // ---- analysis.reduction: modes of K_t kept up to the cutoff ----------------------------------
  double cutoff_hz = 0.0;       ///< > 0: explicit cutoff
  double cutoff_factor = 20.0;  ///< else cutoff = factor × the highest frequency of interest
  /// [m] ≥ 0: contact points merged into square patches of this size (reduction/contact_patches.hpp,
  /// eq. T-31); 0: only coincident points (exact: nodal integration's node pairs)
  double contact_patch = 0.0;
  // ---- load shape and outputs --------------------------------------------------------------------
  FeNodeDirection excitation;
  std::vector<FeNodeDirection> outputs;  ///< at least one (default: the excitation point)
  // ---- analyses ----------------------------------------------------------------------------------
  std::optional<FeNonlinearModesSpec> nonlinear_modes;
  std::optional<FeFrfSpec> frf;
};

}  // namespace jointhb::io
