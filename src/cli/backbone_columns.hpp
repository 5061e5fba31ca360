#pragma once
// The columns of backbone.csv, one schema for discrete and finite-element damping curves
// (docs/cli.md "Damping-curve outputs"): a script reads both with the same names.

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "jointhb/continuation/accuracy.hpp"
#include "jointhb/continuation/curve_turn.hpp"
#include "jointhb/continuation/error_estimate.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/hb/contact_state.hpp"
#include "jointhb/hb/hill_stability.hpp"

namespace jointhb::cli {

// The columns of an frf.csv (discrete or finite-element) after its numeric `base`: with
// stability, "stable" (1, 0; −1 where it failed) and "max_floquet_multiplier" (max |ρ|; −1 where
// unknown), and the word column "bifurcation" (hb::to_string(Bifurcation)) last.
inline std::vector<std::string> frf_columns_with_stability(std::vector<std::string> base, bool stability) {
  if (stability) {
    base.emplace_back("stable");
    base.emplace_back("max_floquet_multiplier");
  }
  base.emplace_back("bifurcation");
  return base;
}

// The points of an FRF (discrete or finite-element: stability_known, stable, omega, bifurcation)
// whose stability is known, the unstable ones and the Ω range they span.
struct StabilityCounts {
  int known = 0;
  int unstable = 0;
  double lo = 0.0, hi = 0.0;  // Ω range of the unstable points (when there are any)
};

template <class Point>
StabilityCounts stability_counts(const std::vector<Point>& points) {
  StabilityCounts c;
  for (const auto& p : points) {
    if (!p.stability_known) continue;
    ++c.known;
    if (p.stable) continue;
    c.lo = c.unstable == 0 ? p.omega : std::min(c.lo, p.omega);
    c.hi = c.unstable == 0 ? p.omega : std::max(c.hi, p.omega);
    ++c.unstable;
  }
  return c;
}

// summary.json's "bifurcations" of an FRF: type, point index, Ω and the Ω of the point before.
template <class Point>
nlohmann::ordered_json bifurcations_json(const std::vector<Point>& points) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < points.size(); ++k) {
    const auto& p = points[k];
    if (p.bifurcation == hb::Bifurcation::none) continue;
    nlohmann::ordered_json b = {{"type", hb::to_string(p.bifurcation)}, {"point", k}, {"omega", p.omega}};
    if (k > 0) b["previous_omega"] = points[k - 1].omega;
    out.push_back(b);
  }
  return out;
}

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
    // (error_estimate: false or a failed estimate)
    "omega_error_truncation", "omega_error_aliasing", "damping_error_truncation",
    "damping_error_aliasing",
    // the harmonics H and time samples N_t the point was computed with (per point with `accuracy`,
    // continuation/accuracy.hpp)
    "harmonics", "time_samples"};

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

/// A truncation estimate's field: empty where the point's truncation part was not computed.
template <class Error>
std::optional<double> truncation_field(const Error& e, double value) {
  return e.truncation_known ? std::optional<double>(value) : std::nullopt;
}

/// The fields of the error columns of kBackboneColumns, empty (nullopt) where not computed (the
/// truncation parts alone where e.truncation_known is false).
inline std::vector<std::optional<double>> backbone_error_fields(const continuation::BackboneError& e) {
  if (!e.known) return {std::nullopt, std::nullopt, std::nullopt, std::nullopt};
  return {truncation_field(e, e.omega.truncation), e.omega.aliasing, truncation_field(e, e.damping.truncation),
          e.damping.aliasing};
}

/// The fields of the four error columns of an FRF row (amplitude_h1, amplitude_max; truncation,
/// aliasing), empty (nullopt) where not computed as above; discrete and finite-element frf.csv alike.
inline std::vector<std::optional<double>> frf_error_fields(const continuation::FrfError& e) {
  if (!e.known) return {std::nullopt, std::nullopt, std::nullopt, std::nullopt};
  return {truncation_field(e, e.amplitude_h1.truncation), e.amplitude_h1.aliasing,
          truncation_field(e, e.amplitude_max.truncation), e.amplitude_max.aliasing};
}

/// summary.json's `turn_points` of a damping curve (BackboneCurve::turns, InterfaceBackbone::turns),
/// as fold_points of FRFs.
inline nlohmann::ordered_json turns_json(const std::vector<continuation::BackboneTurn>& turns) {
  nlohmann::ordered_json located = nlohmann::ordered_json::array();
  for (const auto& t : turns) {
    nlohmann::ordered_json turn = {{"log10_amplitude", t.log10_amplitude},
                                   {"amplitude", std::pow(10.0, t.log10_amplitude)},
                                   {"omega", t.omega},
                                   {"frequency_hz", t.omega / (2.0 * std::numbers::pi)},
                                   {"damping_ratio", t.damping_ratio},
                                   {"log10_amplitude_error_bound", t.log10_amplitude_bound},
                                   {"refined", t.refined}};
    if (t.after_point >= 0) turn["after_point"] = t.after_point;  // between points after_point − 1 and after_point
    if (!t.message.empty()) turn["note"] = t.message;
    located.push_back(turn);
  }
  return located;
}

/// "the curve turns back in amplitude N time(s): log10 q = … (f = … Hz), …" (the stderr line; the
/// first eight turns, all in summary.json's turn_points).
inline std::string turns_line(const std::vector<continuation::BackboneTurn>& turns) {
  constexpr std::size_t kListed = 8;
  std::string where;
  for (std::size_t i = 0; i < std::min(turns.size(), kListed); ++i)
    where += fmt::format("{}log10 q = {:.6f} (f = {:.6g} Hz)", where.empty() ? "" : ", ", turns[i].log10_amplitude,
                         turns[i].omega / (2.0 * std::numbers::pi));
  if (turns.size() > kListed) where += fmt::format(", … ({} more in summary.json turn_points)", turns.size() - kListed);
  return fmt::format("the curve turns back in amplitude {} time(s): {}", turns.size(), where);
}

/// summary.json's `accuracy` of a damping curve or FRF: the request (its tolerances > 0), the range of H and N_t its points
/// used, the restarts at another level and the points kept above the request; null when the
/// request is not active.
template <class Points>
nlohmann::ordered_json accuracy_json(const continuation::Accuracy& a, const Points& points, int level_changes,
                                     int short_of_accuracy) {
  if (!a.active()) return nullptr;
  int h_min = 0, h_max = 0, n_min = 0, n_max = 0;
  for (const auto& p : points) {
    h_min = h_min == 0 ? p.harmonics : std::min(h_min, p.harmonics);
    h_max = std::max(h_max, p.harmonics);
    n_min = n_min == 0 ? p.time_samples : std::min(n_min, p.time_samples);
    n_max = std::max(n_max, p.time_samples);
  }
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (const auto& [name, tolerance] : {std::pair{"frequency", a.frequency}, std::pair{"damping", a.damping},
                                        std::pair{"amplitude", a.amplitude}})
    if (tolerance > 0.0) out[name] = tolerance;
  out.update(nlohmann::ordered_json{{"max_harmonics", a.max_harmonics},
          {"max_time_samples", a.max_time_samples},
          {"harmonics_used", {h_min, h_max}},
          {"time_samples_used", {n_min, n_max}},
          {"level_changes", level_changes},
          {"points_short_of_request", short_of_accuracy}});
  return out;
}

// The worst |estimate| of each source over the known points of a curve (summary.json).
struct WorstErrors {
  int known = 0;
  double first_truncation = 0.0, first_aliasing = 0.0;    // Ω (damping curve), amplitude_h1 (FRF)
  double second_truncation = 0.0, second_aliasing = 0.0;  // ζ (damping curve), amplitude_max (FRF)
  void add(const continuation::BackboneError& e) { add(e.known, e.truncation_known, e.omega, e.damping); }
  void add(const continuation::FrfError& e) { add(e.known, e.truncation_known, e.amplitude_h1, e.amplitude_max); }
  // {"points_known": n, first: {truncation, aliasing}, second: {...}}; null values when none is known.
  [[nodiscard]] nlohmann::ordered_json json(const char* first, const char* second) const {
    const auto value = [&](double v) { return known > 0 ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr); };
    return {{"points_known", known},
            {first, {{"truncation", value(first_truncation)}, {"aliasing", value(first_aliasing)}}},
            {second, {{"truncation", value(second_truncation)}, {"aliasing", value(second_aliasing)}}}};
  }

 private:
  void add(bool point_known, bool truncation_known, const continuation::ErrorPair& first,
           const continuation::ErrorPair& second) {
    if (!point_known) return;
    ++known;
    if (truncation_known) {
      first_truncation = std::max(first_truncation, std::abs(first.truncation));
      second_truncation = std::max(second_truncation, std::abs(second.truncation));
    }
    first_aliasing = std::max(first_aliasing, std::abs(first.aliasing));
    second_aliasing = std::max(second_aliasing, std::abs(second.aliasing));
  }
};

// summary.json "peak" of an FRF: the located peak (`located`, continuation/frf_extrema) where it
// was refined, else the highest accepted point; amplitude_max is the highest accepted point's.
template <class Point>
nlohmann::ordered_json peak_json(const std::optional<continuation::FrfExtremum>& located, const Point& highest) {
  const bool refined = located && located->refined;
  const double omega = refined ? located->omega : highest.omega;
  nlohmann::ordered_json j = {{"omega", omega},
                              {"frequency_hz", omega / (2.0 * std::numbers::pi)},
                              {"amplitude_h1", refined ? located->amplitude_h1 : highest.amplitude_h1},
                              {"amplitude_max", highest.amplitude_max},
                              {"refined", refined}};
  if (refined) {
    j["amplitude_h1_error_bound"] = located->value_bound;
    j["omega_bracket"] = located->omega_bracket;
  } else if (located) {
    j["note"] = located->message;
  }
  return j;
}

// summary.json "fold_points" of an FRF: each fold located between points, with its bound on Ω.
inline nlohmann::ordered_json fold_points_json(const std::vector<continuation::FrfExtremum>& folds) {
  nlohmann::ordered_json located = nlohmann::ordered_json::array();
  for (const auto& f : folds) {
    nlohmann::ordered_json fold = {{"omega", f.omega},
                                   {"frequency_hz", f.omega / (2.0 * std::numbers::pi)},
                                   {"amplitude_h1", f.amplitude_h1},
                                   {"omega_error_bound", f.value_bound},
                                   {"refined", f.refined}};
    if (!f.message.empty()) fold["note"] = f.message;
    located.push_back(fold);
  }
  return located;
}

}  // namespace jointhb::cli
