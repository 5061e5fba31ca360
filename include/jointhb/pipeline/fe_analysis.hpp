#pragma once
// The analyses of a finite-element model and the settings of its stages, as typed values
// (docs/case-files.md, "Finite-element cases" gives the case-file keys that fill them):
//   FeAnalysis      analysis.preload, analysis.modes and the dynamics below;
//   FeDynamicsSpec  damping curves (EPMC) and nonlinear FRFs of the preloaded joint by harmonic
//                   balance in modal/interface form (docs/theory.md §11), with the settings of the
//                   condensation stage (damping, reduction, excitation, outputs).

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/hb/interface_balance.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/preload/preload_solver.hpp"

namespace jointhb::pipeline {

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
  /// Error estimates of Ω and ζ at every point (continuation/interface_error_estimate.hpp); off
  /// by default (they cost about twice the curve).
  bool error_estimate = false;
  /// Harmonics and time samples chosen per point for a requested accuracy (continuation/accuracy.hpp),
  /// starting from balance's; inactive by default (fixed harmonics and time_samples).
  continuation::Accuracy accuracy;
  hb::InterfaceBalanceOptions balance;
  /// The library's defaults of the interface drivers (matrix-free GMRES, steps, tolerances): the
  /// case's `continuation:` keys change only what they name.
  continuation::Options continuation = continuation::InterfaceBackboneOptions{}.continuation;
};

struct FeFrfSpec {
  double omega_start = 0.0, omega_end = 0.0;  ///< [rad/s]
  std::vector<double> forces;                 ///< F [N] of F cos Ωt along the excitation, one curve each
  int output = 0;                             ///< index into FeDynamicsSpec::outputs
  /// Error estimates of the amplitudes at every point (continuation/interface_error_estimate.hpp);
  /// off by default.
  bool error_estimate = false;
  /// H and N_t chosen per point for a requested accuracy of the amplitudes (accuracy.amplitude;
  /// continuation/accuracy.hpp), starting from balance's; inactive by default.
  continuation::Accuracy accuracy;
  /// Floquet multipliers of every point (continuation::InterfaceFrfOptions::stability): automatic
  /// as continuation::computes_interface_stability says (monodromy: at most 10 points; Hill's method:
  /// 3P(2H + 1) ≤ 2100).
  continuation::Stability stability = continuation::Stability::automatic;
  /// How (InterfaceFrfOptions::stability_method): the monodromy (default) or Hill's method.
  continuation::StabilityMethod stability_method = continuation::StabilityMethod::monodromy;
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

/// The time samples N_t of the AFT when a case gives only the harmonics H: the smallest power of
/// two ≥ max(32, 16 H), i.e. 16 samples per period of the highest harmonic.
[[nodiscard]] int default_time_samples(int harmonics);

/// Which linear algebra the FE stages use (docs/distributed.md): CHOLMOD and ARPACK in this process
/// (the default), or MUMPS (or CG with algebraic multigrid) and SLEPc across the MPI ranks of a
/// petsc::Session. Not part of the stage keys: the paths give the same results to round-off (MUMPS)
/// or to the iterative tolerance (CG) (tests/cli/petsc.sh).
struct FeSolvers {
  fe::LinearSolver linear = fe::LinearSolver::cholmod;  ///< preload Newton, K − σM, condensation
  modal::ModalOptions::EigenSolver eigen = modal::ModalOptions::EigenSolver::arpack;
  /// linear = cg: preconditioner and tolerance; each stage sets the mesh's rigid-body modes as the
  /// near-null space on its own DOFs.
  fe::IterativeSettings iterative = {};
};

/// What is computed on a finite-element model and with which settings.
struct FeAnalysis {
  preload::PreloadOptions preload;           ///< the preloaded static state (defaults when not given)
  bool preload_requested = false;            ///< the preload is wanted for itself (analysis.preload)
  std::optional<modal::ModalOptions> modes;  ///< the modes of K_t about the preloaded state
  /// Damping curves / FRFs; they need the preload and the modes, which then run with their
  /// defaults when not given.
  std::optional<FeDynamicsSpec> dynamics;
  FeSolvers solvers;  ///< applied to every stage's options by the pipeline
};

}  // namespace jointhb::pipeline
