#include "jointhb/io/loop_sweep_case.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "jointhb/io/input_error.hpp"
#include "jointhb/io/value_checks.hpp"
#include "yaml_support.hpp"

namespace jointhb::io {

double LoopSweepCase::full_slip_span() const {
  const double slip_limit = friction_coefficient * normal_force;
  if (law == "jenkins") return slip_limit / stiffness;
  return slip_limit / ((1.0 - exponent) * stiffness);
}

std::vector<double> LoopSweepCase::amplitude_ratios() const {
  std::vector<double> ratios(static_cast<std::size_t>(points));
  const double log_min = std::log(ratio_min);
  const double log_span = std::log(ratio_max) - log_min;
  for (int i = 0; i < points; ++i) {
    ratios[static_cast<std::size_t>(i)] =
        std::exp(log_min + log_span * static_cast<double>(i) / static_cast<double>(points - 1));
  }
  // exp(log(x)) need not return x: keep the ends the user wrote.
  ratios.front() = ratio_min;
  ratios.back() = ratio_max;
  return ratios;
}

LoopSweepCase default_loop_sweep_case() { return LoopSweepCase{}; }

namespace {

using yaml::Reader;

void read_loop_sweep(const Reader& reader, const YAML::Node& node, const std::string& path,
                     LoopSweepCase& c) {
  const std::set<std::string> keys = {
      "law", "n", "mu", "normal_force", "kt0", "amplitude_over_gmax", "points", "time_samples"};
  reader.for_each_entry(node, path, keys, [&](const std::string& key, const YAML::Node& value) {
    const std::string name = key.substr(path.size() + 1);
    if (name == "law") {
      c.law = reader.text(value, key);
      reader.check(value, key, check_one_of(c.law, {"gaul-mayer", "jenkins"}));
    } else if (name == "n") {
      c.exponent = reader.number(value, key);
      reader.check(value, key, check_open_unit(c.exponent));
    } else if (name == "mu") {
      c.friction_coefficient = reader.number(value, key);
      reader.check(value, key, check_positive(c.friction_coefficient));
    } else if (name == "normal_force") {
      c.normal_force = reader.number(value, key);
      reader.check(value, key, check_positive(c.normal_force));
    } else if (name == "kt0") {
      c.stiffness = reader.number(value, key);
      reader.check(value, key, check_positive(c.stiffness));
    } else if (name == "amplitude_over_gmax") {
      if (!value.IsSequence() || value.size() != 2) {
        reader.fail(value, key, "must be a range [min, max] of two numbers");
      }
      const double bounds[2] = {reader.number(value[0], key + "[0]"),
                                reader.number(value[1], key + "[1]")};
      reader.check(value[0], key + "[0]", check_positive(bounds[0]));
      reader.check(value[1], key + "[1]", check_positive(bounds[1]));
      if (!(bounds[1] > bounds[0])) {
        reader.fail(
            value[1], key + "[1]",
            "must be > min " + format_number(bounds[0]) + ", got " + format_number(bounds[1]));
      }
      c.ratio_min = bounds[0];
      c.ratio_max = bounds[1];
    } else if (name == "points") {
      const long long points = reader.integer(value, key);
      reader.check(value, key, check_in_range(points, 2, max_sweep_points));
      c.points = static_cast<int>(points);
    } else if (name == "time_samples") {
      const long long samples = reader.integer(value, key);
      reader.check(value, key, check_in_range(samples, 4, max_time_samples));
      c.time_samples = static_cast<int>(samples);
    }
  });
}

}  // namespace

LoopSweepCase parse_loop_sweep_case(const std::string& text, const std::string& file_name) {
  const YAML::Node root = yaml::load(text, file_name);
  Reader reader(file_name);
  LoopSweepCase c = default_loop_sweep_case();
  c.source = file_name;
  if (root.IsNull()) reader.fail(root, "analysis", "required (the file is empty)");
  bool has_analysis = false;
  reader.for_each_entry(root, "", {"analysis"}, [&](const std::string& key, const YAML::Node& a) {
    has_analysis = true;
    bool has_sweep = false;
    reader.for_each_entry(a, key, {"loop_sweep"},
                          [&](const std::string& sweep_key, const YAML::Node& sweep) {
                            has_sweep = true;
                            read_loop_sweep(reader, sweep, sweep_key, c);
                          });
    if (!has_sweep) reader.fail(a, key + ".loop_sweep", "required (the only analysis so far)");
  });
  if (!has_analysis) reader.fail(root, "analysis", "required");
  return c;
}

LoopSweepCase read_loop_sweep_case(const std::filesystem::path& file) {
  return parse_loop_sweep_case(yaml::read_text_file(file), file.string());
}

}  // namespace jointhb::io
