#include "jointhb/io/case_file.hpp"

#include "default_case_text.hpp"

#include <yaml-cpp/yaml.h>

#include "jointhb/io/value_checks.hpp"
#include "yaml_support.hpp"

namespace jointhb::io {
namespace {

/// Without `model:` only the loop sweep can run; what asks for a model is reported as its absence
/// rather than as an unknown key of the loop-sweep schema.
void check_needs_no_model(const YAML::Node& root, const yaml::Reader& reader) {
  for (auto it = root.begin(); it != root.end(); ++it) {
    const YAML::Node key = it->first;
    const YAML::Node value = it->second;
    if (!key.IsScalar()) continue;
    const std::string& name = key.Scalar();
    if (name == "contacts" || name == "excitation") {
      reader.fail(key, "model",
                  "required with " + name +
                      " (a case without model: can only run "
                      "analysis.loop_sweep)");
    }
    if (name != "analysis" || !value.IsMap()) continue;
    for (auto a = value.begin(); a != value.end(); ++a) {
      const YAML::Node analysis = a->first;
      if (!analysis.IsScalar()) continue;
      if (analysis.Scalar() == "frf" || analysis.Scalar() == "nonlinear_modes") {
        reader.fail(analysis, "model",
                    "required by analysis." + analysis.Scalar() +
                        " (a case without model: can only run analysis.loop_sweep)");
      }
    }
  }
}

}  // namespace

CaseFile parse_case_file(const std::string& text, const std::string& file_name) {
  const YAML::Node root = yaml::load(text, file_name);
  if (root.IsMap()) {
    for (auto it = root.begin(); it != root.end(); ++it) {
      const YAML::Node key = it->first;
      if (key.IsScalar() && key.Scalar() == "model") {
        const YAML::Node type = it->second.IsMap() ? it->second["type"] : YAML::Node();
        // The type decides which reader reads the rest: a wrong one is named here, before either
        // reader would report the other kind's keys as unknown.
        if (type) {
          const yaml::Reader reader(file_name);
          const std::string name = type.IsScalar() ? type.Scalar() : std::string("a non-scalar value");
          reader.check(type, "model.type", check_one_of(name, {"discrete", "fe"}));
        }
        if (type && type.IsScalar() && type.Scalar() == "fe") return parse_fe_case(text, file_name);
        return parse_discrete_case(text, file_name);
      }
    }
    check_needs_no_model(root, yaml::Reader(file_name));
  }
  return parse_loop_sweep_case(text, file_name);
}

CaseFile read_case_file(const std::filesystem::path& file) {
  return parse_case_file(yaml::read_text_file(file), file.string());
}

const std::string& default_case_text() {
  // cases/08-lap-damping/case.yaml, embedded at configure time (default_case_text.hpp.in).
  static const std::string text = kDefaultCaseText;
  return text;
}

}  // namespace jointhb::io
