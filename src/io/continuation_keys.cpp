// The `continuation:` keys of an analysis (continuation_keys.hpp).
#include "continuation_keys.hpp"

#include <fmt/format.h>

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

}  // namespace jointhb::io
