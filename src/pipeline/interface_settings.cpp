// Policy of the dynamic stage (pipeline/interface_settings.hpp).
#include "jointhb/pipeline/interface_settings.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "jointhb/pipeline/fingerprint.hpp"

#include "../support/numeric_constants.hpp"

namespace jointhb::pipeline {
namespace {
using support::kTwoPi;
}  // namespace

int default_time_samples(int harmonics) {
  int n = 32;
  while (n < 16 * harmonics) n *= 2;
  return n;
}

Eigen::VectorXd FeNodeDirection::functional(int num_dofs) const {
  Eigen::VectorXd c = Eigen::VectorXd::Zero(num_dofs);
  c.segment<3>(3 * node) = direction;
  return c;
}

std::vector<double> elastic_frequencies(const modal::ModalResult& modes) {
  std::vector<double> f;
  for (Eigen::Index j = 0; j < modes.frequencies_hz.size(); ++j)
    if (std::abs(modes.frequencies_hz[j]) >= rigid_mode_hz) f.push_back(modes.frequencies_hz[j]);
  return f;
}

InterfaceSettings resolve_interface_settings(const FeDynamicsSpec& d, const std::optional<modal::ModalOptions>& modal,
                                             const modal::ModalResult& modes) {
  const std::vector<double> f = elastic_frequencies(modes);
  InterfaceSettings s;
  s.options.modal = modal.value_or(modal::ModalOptions{});
  s.options.rigid_tolerance_hz = rigid_mode_hz;
  int highest_mode = 0;
  if (d.nonlinear_modes) highest_mode = *std::max_element(d.nonlinear_modes->modes.begin(), d.nonlinear_modes->modes.end());
  if (highest_mode > static_cast<int>(f.size()))
    throw std::runtime_error(fmt::format(
        "analysis.nonlinear_modes: mode {} asked for, but the modes stage found {} elastic modes "
        "(raise analysis.modes.count)", highest_mode, f.size()));
  if (f.empty()) throw std::runtime_error("the modes stage found no elastic mode (raise analysis.modes.count)");
  s.followed_hz = highest_mode > 0 ? f[static_cast<std::size_t>(highest_mode - 1)] : f.front();
  if (d.frf) s.followed_hz = std::max(s.followed_hz, std::max(d.frf->omega_start, d.frf->omega_end) / kTwoPi);
  if (d.cutoff_hz > 0.0) {
    s.options.cutoff_hz = d.cutoff_hz;
    s.cutoff_source = "analysis.reduction.cutoff_hz";
  } else {
    s.options.cutoff_hz = d.cutoff_factor * s.followed_hz;
    s.cutoff_source = fmt::format("{} x {:.6g} Hz (the highest frequency of interest)", d.cutoff_factor, s.followed_hz);
  }
  if (d.damping_ratio > 0.0) {
    // ζ at f_d from stiffness-proportional damping: ζ = b ω_d / 2, so b = 2ζ/ω_d.
    const int first = d.nonlinear_modes ? d.nonlinear_modes->modes.front() : 1;
    const double fd = d.damping_frequency_hz > 0.0 ? d.damping_frequency_hz
                                                   : f[static_cast<std::size_t>(std::max(1, first) - 1)];
    s.options.rayleigh_stiffness = 2.0 * d.damping_ratio / (kTwoPi * fd);
    s.damping_source = fmt::format("ratio {} at {:.6g} Hz, stiffness-proportional", d.damping_ratio, fd);
  } else {
    s.options.rayleigh_mass = d.rayleigh_mass;
    s.options.rayleigh_stiffness = d.rayleigh_stiffness;
    s.damping_source = d.rayleigh_mass > 0.0 || d.rayleigh_stiffness > 0.0 ? "rayleigh" : "none";
  }
  return s;
}

std::string interface_model_key(const std::string& modes_key, const reduction::ModalInterfaceOptions& o,
                                const reduction::ModalLoad& load,
                                const std::vector<reduction::ModalOutputSpec>& outputs) {
  Fingerprint k = Fingerprint::chain(modes_key);
  // The Rayleigh coefficients are not part of it: the condensation only copies them into the
  // model (T-23 uses them at evaluation time), so they are set after a store hit.
  k.add("interface model").add(o.cutoff_hz).add(o.initial_count).add(o.max_modes).add(o.rigid_tolerance_hz);
  k.add(o.modal.shift).add(o.modal.tolerance).add(o.modal.ncv);
  k.add(load.name).add(load.force);
  for (const auto& out : outputs) k.add(out.name).add(out.functional);
  return k.hex();
}

}  // namespace jointhb::pipeline
