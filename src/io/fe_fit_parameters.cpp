// Identification parameters of a finite-element case (fe_fit_parameters.hpp).
#include "jointhb/io/fe_fit_parameters.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>

namespace jointhb::io {
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

// The element of a YAML list whose `name` is `item` (or, without names, "<prefix><index+1>").
YAML::Node named(const YAML::Node& list, const std::string& item, const std::string& prefix) {
  if (!list || !list.IsSequence()) return {};
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node n = list[i]["name"];
    const std::string label = n ? n.as<std::string>() : fmt::format("{}{}", prefix, i + 1);
    if (label == item) return list[i];
  }
  return {};
}

}  // namespace

std::vector<std::string> fe_fit_parameter_names(const FeCase& c) {
  std::vector<std::string> names;
  for (const FeInterfaceSpec& s : c.interface_specs) {
    for (const char* key : {"pressure", "decay", "mu"}) names.push_back(fmt::format("interfaces.{}.{}", s.name, key));
    if (s.law == "gaul-mayer") names.push_back(fmt::format("interfaces.{}.n", s.name));
    if (s.stiffness_ratio > 0.0) names.push_back(fmt::format("interfaces.{}.stiffness_ratio", s.name));
    if (s.tangential_stiffness > 0.0) names.push_back(fmt::format("interfaces.{}.kt", s.name));
  }
  for (const preload::Bolt& b : c.bolts) names.push_back(fmt::format("bolts.{}.preload", b.name));
  if (c.dynamics && c.dynamics->damping_ratio > 0.0) names.emplace_back("damping.ratio");
  if (c.dynamics && c.dynamics->damping_ratio == 0.0 &&
      (c.dynamics->rayleigh_mass > 0.0 || c.dynamics->rayleigh_stiffness > 0.0)) {
    names.emplace_back("damping.rayleigh.alpha");
    names.emplace_back("damping.rayleigh.beta");
  }
  return names;
}

std::string set_fe_fit_parameters(const std::string& case_text, const std::vector<std::string>& names,
                                  const std::vector<double>& values) {
  if (names.size() != values.size())
    throw std::invalid_argument(fmt::format("fit: {} names for {} values", names.size(), values.size()));
  YAML::Node root = YAML::Load(case_text);
  for (std::size_t k = 0; k < names.size(); ++k) try {
    const Name n = split(names[k]);
    YAML::Node target;
    std::string key = n.key;
    if (names[k] == "damping.ratio") {
      target = root["analysis"]["damping"];
      key = "ratio";
    } else if (n.group == "damping" && n.item == "rayleigh") {
      target = root["analysis"]["damping"]["rayleigh"];
    } else if (n.group == "interfaces") {
      if (const YAML::Node iface = named(root["model"]["interfaces"], n.item, "interface")) target = iface["contact"];
    } else if (n.group == "bolts" && n.key == "preload") {
      target = named(root["model"]["bolts"], n.item, "bolt");
    }
    // a contact key the file leaves at its default (e.g. stiffness_ratio) is written out
    const bool may_add = n.group == "interfaces";
    if (!target || !target.IsMap() || (!may_add && !target[key]))
      throw std::invalid_argument(fmt::format("fit: parameter '{}' does not address a value of this case", names[k]));
    target[key] = fmt::format("{:.17g}", values[k]);
  } catch (const YAML::Exception&) {  // a node of another shape than the case reader allows
    throw std::invalid_argument(fmt::format("fit: parameter '{}' does not address a value of this case", names[k]));
  }
  root.remove("fit");
  YAML::Emitter out;
  out << root;
  return out.c_str();
}

}  // namespace jointhb::io
