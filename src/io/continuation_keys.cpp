// The `continuation:` keys of an analysis (continuation_keys.hpp).
#include "continuation_keys.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "jointhb/io/value_checks.hpp"

namespace jointhb::io {

using yaml::Fields;

void read_continuation_keys(const yaml::Reader& reader_, const YAML::Node& node,
                            const std::string& path, continuation::Options& o) {
  const Fields f = reader_.fields(
      node, path, {"initial_step", "min_step", "max_step", "max_points", "residual_tolerance"});
  const auto positive = [&](const char* name, double& target) {
    if (const auto* entry = f.find(name)) {
      target = reader_.number(entry->value, f.path_of(name));
      reader_.check(entry->value, f.path_of(name), check_positive(target));
    }
  };
  positive("initial_step", o.initial_step);
  positive("min_step", o.min_step);
  positive("max_step", o.max_step);
  if (const auto* points = f.find("max_points")) {
    const long long count = reader_.integer(points->value, f.path_of("max_points"));
    reader_.check(points->value, f.path_of("max_points"),
                  check_in_range(count, 1, max_sweep_points));
    o.max_points = static_cast<int>(count);
  }
  if (const auto* tolerance = f.find("residual_tolerance")) {
    o.residual_tolerance = reader_.number(tolerance->value, f.path_of("residual_tolerance"));
    reader_.check(tolerance->value, f.path_of("residual_tolerance"),
                  check_open_unit(o.residual_tolerance));
  }

  // min_step <= initial_step <= max_step, blaming a value the file gives (initial_step first).
  const auto value_of = [&](const char* name, double value) {
    return fmt::format("{} = {}{}", name, value, f.has(name) ? "" : " (the default)");
  };
  const auto* initial = f.find("initial_step");
  if (o.min_step > o.initial_step) {
    if (initial) {
      reader_.fail(
          initial->value, f.path_of("initial_step"),
          fmt::format("must be >= {}, got {}", value_of("min_step", o.min_step), o.initial_step));
    }
    reader_.fail(f.find("min_step")->value, f.path_of("min_step"),
                 fmt::format("must be <= {}, got {}", value_of("initial_step", o.initial_step),
                             o.min_step));
  }
  if (o.initial_step > o.max_step) {
    if (initial) {
      reader_.fail(
          initial->value, f.path_of("initial_step"),
          fmt::format("must be <= {}, got {}", value_of("max_step", o.max_step), o.initial_step));
    }
    reader_.fail(f.find("max_step")->value, f.path_of("max_step"),
                 fmt::format("must be >= {}, got {}", value_of("initial_step", o.initial_step),
                             o.max_step));
  }
}

void read_accuracy_keys(const yaml::Reader& reader_, const YAML::Node& node, const std::string& path,
                        int harmonics, int time_samples, bool frf, continuation::Accuracy& a) {
  const Fields f = frf ? reader_.fields(node, path, {"amplitude", "min_harmonics", "max_harmonics", "max_time_samples"})
                       : reader_.fields(node, path,
                                        {"frequency", "damping", "min_harmonics", "max_harmonics", "max_time_samples"});
  const auto tolerance = [&](const char* name, double& target) {
    if (const auto* e = f.find(name)) {
      target = reader_.number(e->value, f.path_of(name));
      if (!std::isfinite(target)) reader_.fail(e->value, f.path_of(name), "must be a finite relative tolerance in [0, 1)");
      if (!(target >= 0.0 && target < 1.0))
        reader_.fail(e->value, f.path_of(name), fmt::format("must be a relative tolerance in [0, 1), got {}", target));
    }
  };
  tolerance("frequency", a.frequency);
  tolerance("damping", a.damping);
  tolerance("amplitude", a.amplitude);
  if (!a.active())
    reader_.fail(node, path, frf ? "give amplitude > 0 (relative tolerance per point)"
                                 : "give frequency or damping > 0 (relative tolerances per point)");
  const auto count = [&](const char* name, int& target, long long lo, long long hi) {
    if (const auto* e = f.find(name)) {
      const long long v = reader_.integer(e->value, f.path_of(name));
      reader_.check(e->value, f.path_of(name), check_in_range(v, lo, hi));
      target = static_cast<int>(v);
    }
  };
  count("min_harmonics", a.min_harmonics, 1, 99);
  count("max_harmonics", a.max_harmonics, 1, 99);
  count("max_time_samples", a.max_time_samples, 4, 1 << 16);
  if (a.max_harmonics < a.min_harmonics)
    reader_.fail(node, f.path_of(f.has("max_harmonics") ? "max_harmonics" : "min_harmonics"),
                 fmt::format("max_harmonics = {} must be >= min_harmonics = {}", a.max_harmonics, a.min_harmonics));
  if (a.max_time_samples < 2 * a.max_harmonics + 2)
    reader_.fail(node, f.path_of("max_time_samples"),
                 fmt::format("must be >= 2 max_harmonics + 2 = {}, got {}", 2 * a.max_harmonics + 2, a.max_time_samples));
  a.min_time_samples = std::min(a.min_time_samples, time_samples);
  if (harmonics < a.min_harmonics || harmonics > a.max_harmonics)
    reader_.fail(node, path,
                 fmt::format("the starting harmonics = {} must lie in [min_harmonics, max_harmonics] = [{}, {}]",
                             harmonics, a.min_harmonics, a.max_harmonics));
  if (time_samples > a.max_time_samples)
    reader_.fail(node, f.path_of("max_time_samples"),
                 fmt::format("must be >= the starting time_samples = {}, got {}", time_samples, a.max_time_samples));
}

continuation::Stability read_stability_key(const yaml::Reader& reader, const YAML::Node& value,
                                           const std::string& key) {
  const std::string text = reader.text(value, key);
  reader.check(value, key, check_one_of(text, {"auto", "true", "false"}));
  return text == "auto"   ? continuation::Stability::automatic
         : text == "true" ? continuation::Stability::always
                          : continuation::Stability::never;
}

continuation::StabilityMethod read_stability_method_key(const yaml::Reader& reader,
                                                        const YAML::Node& value, const std::string& key) {
  const std::string text = reader.text(value, key);
  reader.check(value, key, check_one_of(text, {"monodromy", "hill"}));
  return text == "hill" ? continuation::StabilityMethod::hill : continuation::StabilityMethod::monodromy;
}

}  // namespace jointhb::io
