#pragma once
// The finite-element pipeline as one object (docs/pipeline.md):
//
//   FeModel + FeAnalysis ──► structure ──► preload ──► modes ──► interface model ──► backbone / frf
//                            (fe::assemble) (preload/)  (modal/)  (reduction/: condensed, coincident
//                                                                  points merged, eq. T-31)
//
// Each stage is computed when first asked for, kept (memoised) while its key (pipeline/fe_model.hpp)
// is unchanged, and stored in / read from a StageStore under that key. A parameter set through
// set_parameter changes the typed inputs, hence exactly the keys of the stages it enters: a
// contact-law value or a bolt preload recomputes preload, modes and condensation; a damping value
// recomputes none of them (the condensed model only carries the Rayleigh coefficients); a friction
// value set for the dynamics only (ParameterScope::dynamics) changes the laws of the condensed
// model and nothing stored.
//
// Every front end drives this object: `jointhb run` (case file → pipeline → outputs), `jointhb
// fit` (parameters → pipeline → residuals, pipeline/fe_fit_model.hpp), the Python package and the
// validation programs. The object prints nothing; progress comes through callbacks.
//
// Failures: a stage that fails numerically reports it in its result (PreloadResult::termination,
// ModalResult::termination, a curve's StopReason; each result's status() says it in the one convention
// of contact/termination.hpp); asking for a stage that needs a failed one throws StageError naming
// the failed stage. Invalid inputs throw std::invalid_argument.

#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "jointhb/continuation/interface_response.hpp"
#include "jointhb/fe/assembly.hpp"
#include "jointhb/hb/interface_model.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/pipeline/fe_analysis.hpp"
#include "jointhb/pipeline/fe_model.hpp"
#include "jointhb/pipeline/interface_settings.hpp"
#include "jointhb/pipeline/stage_store.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/field_recovery.hpp"

namespace jointhb::pipeline {

/// A stage was asked for whose input stage failed (the message names that stage and its reason).
class StageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How a stage's current result was obtained.
struct StageInfo {
  std::string key;               ///< its key (32 hex digits)
  bool from_store = false;       ///< read from the store instead of computed
  std::string location;          ///< where the store keeps it (file name, "memory")
  double store_seconds = 0.0;    ///< reading it, or writing it after computing it [s]
  std::string warning;           ///< a stored result that did not fit the model (then computed)
};

/// The condensed model of the interfaces (eq. T-21–T-23), coincident points merged (eq. T-31),
/// with the damping and the dynamics' contact laws set.
struct InterfaceStage {
  hb::InterfaceModel model;
  reduction::FieldRecovery recovery;  ///< merged; empty unless volume fields are asked for
  std::vector<int> patch_of_point;    ///< fine contact point → merged point
  InterfaceSettings settings;
  int fine_points = 0;                ///< contact points before the merge
  double merge_seconds = 0.0;
  bool truncated_by_max_modes = false;
  /// The condensation's own timings (0 when read from the store).
  double modes_seconds = 0.0, factor_seconds = 0.0, residual_seconds = 0.0, seconds = 0.0;
  std::string brief;                  ///< one line on the condensation (kept modes, points, time)
  StageInfo info;
};

/// One accepted point of a damping curve (a row of backbone.csv).
struct BackbonePoint {
  int mode = 0;
  double amplitude = 0.0;             ///< q [m √kg]
  double output_amplitude = 0.0;      ///< |fundamental| of the first output [m]
  double omega = 0.0;                 ///< [rad/s]
  double frequency_hz = 0.0;
  double damping_ratio = 0.0;         ///< ζ of the EPMC
  double dissipation = 0.0;           ///< W_D per cycle [J]
  double damping_ratio_energy = 0.0;  ///< ζ_E from the sampled loops' energy
  double viscous_dissipation = 0.0;   ///< work of the kept modes' damping per cycle [J]
  int slipping_points = 0, open_points = 0, newton_iterations = 0;
  hb::ContactStateCounts states;  ///< points per contact state (hb/contact_state.hpp)
  int contact_points = 0;             ///< P, for the slip fraction
  double step = 0.0;                  ///< arclength step that reached the point
  continuation::BackboneError error;  ///< estimated relative errors of Ω and ζ (error_estimate)
  int harmonics = 0, time_samples = 0;  ///< the level the point was computed at (accuracy: per point)
};

struct BackboneCurve {
  int mode = 0;
  continuation::InterfaceBackbone curve;  ///< the continuation's points (with unknowns), reason, timings
  std::vector<BackbonePoint> points;      ///< one per accepted point
  bool reached_frequency_drop = false;    ///< stopped because the frequency moved by frequency_drop
  bool stopped_by_callback = false;
  std::string stop_message;               ///< why it ended, one line
  double energy_gap = 0.0;                ///< largest |ζ/ζ_E − 1| along the curve
  std::string energy_warning;             ///< set when energy_gap > energy_gap_warning
  int harmonics = 0, time_samples = 0;
  /// The status convention (contact/termination.hpp), message `stop_message`: the curve reached
  /// its end or the frequency drop → reached_end (status().ok()); on_point returned false
  /// → stopped_by_user; a non-finite point → failed; otherwise continuation::termination(reason).
  [[nodiscard]] Status status() const;
};

/// One accepted point of a nonlinear FRF (a row of frf.csv).
struct FrfPoint {
  std::size_t level = 0;
  double force = 0.0;          ///< F [N]
  double omega = 0.0;          ///< [rad/s]
  double frequency_hz = 0.0;
  double amplitude_h1 = 0.0;   ///< |fundamental| of the output [m]
  double amplitude_max = 0.0;  ///< max_t |u_o(t)| [m]
  double dissipation = 0.0;    ///< W_D per cycle [J]
  int slipping_points = 0, open_points = 0, newton_iterations = 0;
  hb::ContactStateCounts states;  ///< points per contact state (hb/contact_state.hpp)
  continuation::FrfError error;   ///< estimated relative errors of the amplitudes (error_estimate)
  int harmonics = 0, time_samples = 0;  ///< the level the point was computed at (accuracy: per point)
  // Stability (FeFrfSpec::stability; continuation::InterfaceFrfPoint)
  bool stability_known = false, stable = true;
  double max_multiplier = 0.0;  ///< max |ρ| of the Floquet multipliers
  hb::Bifurcation bifurcation = hb::Bifurcation::none;
};

struct FrfCurve {
  std::size_t level = 0;
  double force = 0.0;
  std::string output;                ///< the output's name
  continuation::InterfaceFrf curve;
  std::vector<FrfPoint> points;
  bool stopped_by_callback = false;
  /// The resonance peak: located between the points where refined (curve.peak, bound
  /// curve.peak->value_bound), else the largest accepted |fundamental|
  double peak_amplitude = 0.0, peak_frequency_hz = 0.0;
  bool peak_refined = false;
  /// The status convention (contact/termination.hpp), message `curve.message`: the end reached →
  /// reached_end (status().ok()); on_point returned false → stopped_by_user; a non-finite
  /// point → failed; otherwise continuation::termination(reason).
  [[nodiscard]] Status status() const;
};

/// Return false to stop the curve (it ends with the points accepted so far).
using BackboneCallback = std::function<bool(const BackbonePoint&)>;
using FrfCallback = std::function<bool(const FrfPoint&)>;

/// How often each stage was computed, read from the store, or reused as kept (its key unchanged
/// since it was last asked for): what a parameter change recomputes.
struct StageCounters {
  int assembled = 0;
  int preload_solved = 0, preload_read = 0, preload_reused = 0;
  int modes_solved = 0, modes_read = 0, modes_reused = 0;
  int condensed = 0, condensation_read = 0, condensation_reused = 0;
  int curves = 0;
};

/// Where a parameter applies: everywhere (the stages it enters are recomputed), or only in the
/// contact laws of the condensed model (friction μ and n; the preload keeps the model's values:
/// an approximation, docs/identification.md §9).
enum class ParameterScope { everywhere, dynamics };

/// The parameter names a model and analysis offer (FePipeline::parameter_names).
[[nodiscard]] std::vector<std::string> fe_parameter_names(const FeModel& model, const FeAnalysis& analysis);

class FePipeline {
 public:
  /// `store`: where stage results are kept between keys (nullptr: nowhere).
  FePipeline(FeModel model, FeAnalysis analysis, std::shared_ptr<StageStore> store = nullptr);

  [[nodiscard]] const FeModel& model() const { return model_; }
  [[nodiscard]] const FeAnalysis& analysis() const { return analysis_; }
  [[nodiscard]] StageStore& store() { return *store_; }
  [[nodiscard]] FeStageKeys keys() const;
  [[nodiscard]] const StageCounters& counters() const { return counters_; }

  /// Whether the analyses need the preloaded state (asked for, or modes/dynamics on a model with
  /// interfaces or bolts); without it the modes are those of the unloaded structure.
  [[nodiscard]] bool needs_preload() const;
  /// The modal options the modes stage uses (analysis.modes, or the defaults when a dynamic
  /// analysis needs modes); nullopt when nothing needs modes.
  [[nodiscard]] std::optional<modal::ModalOptions> modal_options() const;

  // ---- stages (each computed on first use, then kept while its key is unchanged) -------------
  /// The assembled structure (K_s with the ties' stiffness) with the model's interfaces, bolts,
  /// constraints and ties.
  const preload::PreloadModel& structure();
  /// The preloaded static state (computed even when needs_preload() is false, if asked for).
  const preload::PreloadResult& preload();
  [[nodiscard]] const StageInfo& preload_info() const { return preload_info_; }
  /// The free DOFs (the constraints removed).
  const fe::DofMap& dofs();
  /// The modes of K_t about the preloaded state (of K_s without one). Throws StageError when the
  /// preload it needs did not converge.
  const modal::ModalResult& modes();
  [[nodiscard]] const StageInfo& modes_info() const { return modes_info_; }
  /// The condensed interface model. Throws StageError when the modes failed,
  /// std::invalid_argument when the analysis has no dynamics or the model no interfaces.
  const InterfaceStage& interface_stage();

  // ---- curves ------------------------------------------------------------------------------------
  /// The damping curve (EPMC) of elastic mode `mode` with the analysis' nonlinear_modes settings,
  /// or with `spec`.
  BackboneCurve backbone(int mode, const BackboneCallback& on_point = {});
  BackboneCurve backbone(int mode, const FeNonlinearModesSpec& spec, const BackboneCallback& on_point = {});
  /// The nonlinear FRF at force level `level` of the analysis' frf settings, or of `spec`.
  FrfCurve frf(std::size_t level, const FrfCallback& on_point = {});
  FrfCurve frf(std::size_t level, const FeFrfSpec& spec, const FrfCallback& on_point = {});

  // ---- parameters (docs/identification.md, "Finite-element cases") --------------------------
  //   interfaces.<name>.pressure | decay | mu | n (gaul-mayer) | stiffness_ratio | kt
  //   bolts.<name>.preload
  //   damping.ratio | damping.rayleigh.alpha | damping.rayleigh.beta   (as the analysis gives it)
  /// The names this model and analysis offer.
  [[nodiscard]] std::vector<std::string> parameter_names() const { return fe_parameter_names(model_, analysis_); }
  /// The current value. Throws std::invalid_argument naming an unknown parameter.
  [[nodiscard]] double parameter(const std::string& name) const;
  /// Sets a value. Throws std::invalid_argument naming the parameter and the violated constraint
  /// (the pipeline is then unchanged).
  void set_parameter(const std::string& name, double value, ParameterScope scope = ParameterScope::everywhere);

 private:
  const FeStageKeys& current_keys();
  void refresh_dynamics(InterfaceStage& stage) const;
  reduction::ModalLoad load_vector() const;
  std::vector<reduction::ModalOutputSpec> output_vectors() const;

  FeModel model_;
  FeAnalysis analysis_;
  std::shared_ptr<StageStore> store_;
  StageCounters counters_;
  std::optional<FeStageKeys> keys_;                   ///< reset by every change of the model
  std::optional<preload::PreloadModel> structure_;
  std::optional<fe::DofMap> dofs_;
  mutable std::optional<Eigen::MatrixXd> rigid_body_modes_;  ///< modal_options(), CG path only
  std::optional<preload::PreloadResult> preload_;
  std::optional<modal::ModalResult> modes_;
  std::optional<InterfaceStage> interface_;
  std::string interface_memo_;                        ///< the key interface_ was built for
  StageInfo preload_info_, modes_info_;
  /// Per interface: the law of the dynamics when a parameter was set with ParameterScope::dynamics.
  std::vector<std::optional<contact::ContactPoint>> dynamic_laws_;
};

}  // namespace jointhb::pipeline
