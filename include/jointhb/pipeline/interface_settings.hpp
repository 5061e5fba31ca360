#pragma once
// Physics policy of the dynamic stage of a finite-element model (docs/pipeline.md): which modes
// are elastic, where the condensation cuts off, how a damping ratio becomes Rayleigh damping,
// and the key under which a condensed model is stored. Every front end (CLI, fit, Python) gets
// these from here, not from its own copy.

#include <string>
#include <vector>

#include "jointhb/modal/modes.hpp"
#include "jointhb/pipeline/fe_analysis.hpp"
#include "jointhb/reduction/modal_interface.hpp"

namespace jointhb::pipeline {

/// |f| below this [Hz]: a rigid-body mode (build_modal_interface's default rigid tolerance).
inline constexpr double rigid_mode_hz = 1.0;

/// ζ and ζ_E (the sampled loops' energy ratio) of a damping-curve point differ by more than this
/// (relative): the contact forces are not resolved by the harmonics and time samples (a warning).
inline constexpr double energy_gap_warning = 0.1;

/// The condensation settings of a dynamic analysis: cutoff (explicit, or cutoff_factor × the
/// highest frequency of interest) and Rayleigh damping (a ratio becomes stiffness-proportional at
/// the followed mode), with where each came from (for reports).
struct InterfaceSettings {
  reduction::ModalInterfaceOptions options;
  double followed_hz = 0.0;  ///< highest frequency of interest [Hz]
  std::string cutoff_source, damping_source;
};

/// Frequencies [Hz] of the elastic modes among `modes` (|f| ≥ rigid_mode_hz).
[[nodiscard]] std::vector<double> elastic_frequencies(const modal::ModalResult& modes);

/// Throws std::runtime_error when the modes stage found no elastic mode or fewer than followed.
[[nodiscard]] InterfaceSettings resolve_interface_settings(const FeDynamicsSpec& dynamics,
                                                           const std::optional<modal::ModalOptions>& modal,
                                                           const modal::ModalResult& modes);

/// Key of the condensed model: the modes key + every condensation option but the damping (the
/// condensation only copies it into the model), and the load and output vectors.
[[nodiscard]] std::string interface_model_key(const std::string& modes_key, const reduction::ModalInterfaceOptions& o,
                                              const reduction::ModalLoad& load,
                                              const std::vector<reduction::ModalOutputSpec>& outputs);

}  // namespace jointhb::pipeline
