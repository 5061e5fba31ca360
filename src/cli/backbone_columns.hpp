#pragma once
// The columns of backbone.csv, one schema for discrete and finite-element damping curves
// (docs/cli.md "Damping-curve outputs"): a script reads both with the same names.

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "jointhb/hb/contact_state.hpp"

namespace jointhb::cli {

inline const std::vector<std::string> kBackboneColumns = {
    "mode",                  // the linear mode followed
    "amplitude",             // modal amplitude q [m √kg]
    "output_amplitude",      // |fundamental| of the output DOF [m]
    "omega",                 // Ω [rad/s]
    "frequency_hz",          // Ω/2π [Hz]
    "damping_ratio",         // ζ = ξ/(2Ω) of the EPMC term
    "W_D",                   // contact dissipation per cycle [J]
    "viscous_dissipation",   // work of the viscous damping per cycle [J]
    "damping_ratio_energy",  // (W_D + viscous work) / (2π Ω² q²)
    "slip_fraction",         // share of contact points in microslip or gross slip
    "slipping_points",       // contact points in microslip or gross slip
    "open_points",           // contact points open throughout the cycle
    // contact points per state over the cycle (hb/contact_state.hpp, docs/theory.md §14); with
    // microslip + gross slip = slipping_points and the five states adding up to every point
    "stuck_points", "microslip_points", "gross_slip_points", "gapping_points",
    "newton_iterations",     // corrector iterations of the point
    "step",                  // arclength step that reached the point
    // Estimated relative errors of Ω and ζ (continuation/error_estimate.hpp, docs/theory.md §13):
    // harmonic truncation (T-41) and time sampling (T-42), signed; empty where not computed
    // (error_estimate: false, a failed estimate, and every finite-element curve)
    "omega_error_truncation", "omega_error_aliasing", "damping_error_truncation",
    "damping_error_aliasing"};

/// The fields of the state columns of kBackboneColumns (stuck … gapping; open_points is its own).
inline std::vector<std::optional<double>> contact_state_fields(const hb::ContactStateCounts& c) {
  return {static_cast<double>(c[hb::ContactState::stuck]), static_cast<double>(c[hb::ContactState::microslip]),
          static_cast<double>(c[hb::ContactState::gross_slip]), static_cast<double>(c[hb::ContactState::gapping])};
}

/// {"stuck": n, "microslip": n, "gross_slip": n, "gapping": n, "open": n}: the counts of summary.json.
inline nlohmann::ordered_json contact_states_json(const hb::ContactStateCounts& c) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (int k = 0; k < hb::kContactStateCount; ++k) {
    const auto s = static_cast<hb::ContactState>(k);
    out[std::string(hb::contact_state_name(s))] = c[s];
  }
  return out;
}

/// The fields of the error columns of kBackboneColumns, empty (nullopt) when not computed.
inline std::vector<std::optional<double>> backbone_error_fields(bool known, double omega_truncation,
                                                                double omega_aliasing, double damping_truncation,
                                                                double damping_aliasing) {
  if (!known) return {std::nullopt, std::nullopt, std::nullopt, std::nullopt};
  return {omega_truncation, omega_aliasing, damping_truncation, damping_aliasing};
}

}  // namespace jointhb::cli
