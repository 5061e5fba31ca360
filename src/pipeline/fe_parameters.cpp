// Typed parameters of the finite-element pipeline (pipeline/fe_pipeline.hpp, "parameters"): the
// names a model offers, their values, and setting one so that exactly the stages it enters change
// their keys.
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <string_view>
#include <stdexcept>

#include "jointhb/contact/harmonic_loop.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"

namespace jointhb::pipeline {
namespace {

// "interfaces.lap.mu" → {"interfaces", "lap", "mu"} (the middle part may contain dots: the first
// and the last dot split).
struct Name {
  std::string group, item, key;
};

Name split(const std::string& name) {
  const auto a = name.find('.'), b = name.rfind('.');
  if (a == std::string::npos || a == b) return {name, "", ""};
  return {name.substr(0, a), name.substr(a + 1, b - a - 1), name.substr(b + 1)};
}

[[noreturn]] void unknown(const std::string& name) {
  throw std::invalid_argument(fmt::format("parameter '{}' does not address a value of this model", name));
}

template <class T, class NameOf>
std::size_t index_of(const std::vector<T>& items, const std::string& item, NameOf name_of, const std::string& full) {
  for (std::size_t i = 0; i < items.size(); ++i)
    if (name_of(items[i]) == item) return i;
  unknown(full);
}

// The values of an interface's contact law that are parameters, in the order of the names.
constexpr std::array<const char*, 8> kLawKeys = {"pressure", "decay", "cutoff_gap", "normal_stiffness", "mu", "n", "stiffness_ratio", "kt"};

// A law's parameter values, editable; `slot` is the one place that says which key a law offers:
// p_N0 and λ for the exponential normal law (g_c when it has a cutoff), k_N for the linear one,
// μ unless frictionless, the exponent n only for Gaul–Mayer, the stiffness ratio or k_T0 as the
// stiffness model has it.
struct LawValues {
  contact::ContactPointOptions options;
  double exponent = 0.0;
  std::string law_name;

  explicit LawValues(const contact::ContactPoint& law)
      : options(law.options()), exponent(law_exponent(law)), law_name(law.law().name()) {}

  /// The value of `key`, or nullptr when the law has no such value.
  double* slot(std::string_view key) {
    const bool proportional = options.stiffness_model == contact::TangentialStiffnessModel::proportional;
    const bool exponential = options.normal.kind == contact::NormalLawKind::exponential;
    if (key == "pressure") return exponential ? &options.normal.reference_pressure : nullptr;
    if (key == "decay") return exponential ? &options.normal.decay : nullptr;
    if (key == "cutoff_gap") return exponential && std::isfinite(options.normal.cutoff_gap) ? &options.normal.cutoff_gap : nullptr;
    if (key == "normal_stiffness") return exponential ? nullptr : &options.normal.penalty_stiffness;
    if (key == "mu") return options.friction_coefficient > 0.0 ? &options.friction_coefficient : nullptr;
    if (key == "n") return law_name == "gaul-mayer" ? &exponent : nullptr;
    if (key == "stiffness_ratio") return proportional ? &options.stiffness_ratio : nullptr;
    if (key == "kt") return proportional ? nullptr : &options.tangential_stiffness;
    return nullptr;
  }
};

// The law of an interface with one value changed. Throws std::invalid_argument naming the
// parameter and the violated constraint.
contact::ContactPoint with_value(const contact::ContactPoint& law, const std::string& key, double value,
                                 const std::string& full) {
  LawValues v(law);
  double* slot = v.slot(key);
  if (slot == nullptr) unknown(full);
  *slot = value;
  if (!std::isfinite(value)) throw std::invalid_argument(fmt::format("parameter '{}': must be finite, got {}", full, value));
  if (const std::string e = v.options.validate(); !e.empty())
    throw std::invalid_argument(fmt::format("parameter '{}' = {}: {}", full, value, e));
  try {
    return contact::ContactPoint(v.options, contact::make_tangential_law(v.law_name, v.exponent));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("parameter '{}' = {}: {}", full, value, e.what()));
  }
}

}  // namespace

std::vector<std::string> fe_parameter_names(const FeModel& model, const FeAnalysis& analysis) {
  std::vector<std::string> names;
  for (const auto& ci : model.interfaces) {
    LawValues v(ci.law);
    for (const char* key : kLawKeys)
      if (v.slot(key) != nullptr) names.push_back(fmt::format("interfaces.{}.{}", ci.geometry.name, key));
  }
  for (const preload::Bolt& b : model.bolts) names.push_back(fmt::format("bolts.{}.preload", b.name));
  if (const auto& d = analysis.dynamics) {
    if (d->damping_ratio > 0.0) {
      names.emplace_back("damping.ratio");
    } else if (d->rayleigh_mass > 0.0 || d->rayleigh_stiffness > 0.0) {
      names.emplace_back("damping.rayleigh.alpha");
      names.emplace_back("damping.rayleigh.beta");
    }
  }
  return names;
}

double FePipeline::parameter(const std::string& name) const {
  const Name n = split(name);
  if (n.group == "interfaces") {
    const std::size_t i = index_of(model_.interfaces, n.item, [](const auto& ci) { return ci.geometry.name; }, name);
    LawValues v(dynamic_laws_[i] ? *dynamic_laws_[i] : model_.interfaces[i].law);
    if (const double* slot = v.slot(n.key)) return *slot;
  } else if (n.group == "bolts" && n.key == "preload") {
    return model_.bolts[index_of(model_.bolts, n.item, [](const auto& b) { return b.name; }, name)].preload;
  } else if (analysis_.dynamics && name == "damping.ratio") {
    return analysis_.dynamics->damping_ratio;
  } else if (analysis_.dynamics && name == "damping.rayleigh.alpha") {
    return analysis_.dynamics->rayleigh_mass;
  } else if (analysis_.dynamics && name == "damping.rayleigh.beta") {
    return analysis_.dynamics->rayleigh_stiffness;
  }
  unknown(name);
}

void FePipeline::set_parameter(const std::string& name, double value, ParameterScope scope) {
  const Name n = split(name);
  if (n.group == "interfaces") {
    const std::size_t i = index_of(model_.interfaces, n.item, [](const auto& ci) { return ci.geometry.name; }, name);
    const bool friction = n.key == "mu" || n.key == "n";
    if (scope == ParameterScope::dynamics) {
      if (!friction)
        throw std::invalid_argument(fmt::format("parameter '{}': only mu and n can be set for the dynamics only", name));
      const contact::ContactPoint& base = dynamic_laws_[i] ? *dynamic_laws_[i] : model_.interfaces[i].law;
      dynamic_laws_[i] = with_value(base, n.key, value, name);
      if (interface_) refresh_dynamics(*interface_);
      return;
    }
    contact::ContactPoint law = with_value(model_.interfaces[i].law, n.key, value, name);
    if (dynamic_laws_[i]) dynamic_laws_[i] = with_value(*dynamic_laws_[i], n.key, value, name);
    model_.interfaces[i].law = law;
    if (structure_) structure_->interfaces[i].law = law;  // the assembled K_s does not depend on it
    keys_.reset();
    return;
  }
  if (n.group == "bolts" && n.key == "preload") {
    const std::size_t j = index_of(model_.bolts, n.item, [](const auto& b) { return b.name; }, name);
    if (!std::isfinite(value) || value < 0.0)
      throw std::invalid_argument(fmt::format("parameter '{}' = {}: a bolt preload must be finite and >= 0", name, value));
    model_.bolts[j].preload = value;
    if (structure_) structure_->bolts[j].preload = value;  // K_s holds k_b b bᵀ, not P
    keys_.reset();
    return;
  }
  if (analysis_.dynamics && (name == "damping.ratio" || name == "damping.rayleigh.alpha" || name == "damping.rayleigh.beta")) {
    const bool ratio = name == "damping.ratio";
    if (!std::isfinite(value) || value < 0.0 || (ratio && (value == 0.0 || value >= 1.0)))
      throw std::invalid_argument(fmt::format("parameter '{}' = {}: must be {}", name, value,
                                              ratio ? "in (0, 1)" : "finite and >= 0"));
    FeDynamicsSpec& d = *analysis_.dynamics;
    (name == "damping.ratio" ? d.damping_ratio : name == "damping.rayleigh.alpha" ? d.rayleigh_mass : d.rayleigh_stiffness) =
        value;
    // No stage key holds the damping: the kept interface model gets the new coefficients when
    // next asked for (interface_stage resolves them again).
    return;
  }
  unknown(name);
}

}  // namespace jointhb::pipeline
