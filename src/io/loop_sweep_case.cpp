#include "jointhb/io/loop_sweep_case.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "jointhb/io/input_error.hpp"
#include "jointhb/io/value_checks.hpp"

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

// Reads one document, reporting every problem at the node it concerns.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const YAML::Node& at, const std::string& key,
                         const std::string& constraint) const {
    fail(at.Mark(), key, constraint);
  }
  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& key,
                         const std::string& constraint) const {
    // yaml-cpp marks are 0-based and -1 when there is no position (an empty document).
    throw InputError(file_, mark.line + 1, mark.column + 1, key, constraint);
  }

  /// Calls `read(key, value)` for each entry of a mapping, rejecting duplicate and unknown keys.
  void for_each_entry(const YAML::Node& map, const std::string& path,
                      const std::set<std::string>& allowed,
                      const std::function<void(const std::string&, const YAML::Node&)>& read) {
    if (!map.IsMap()) fail(map, path, "must be a mapping, got " + describe(map));
    std::set<std::string> seen;
    for (auto it = map.begin(); it != map.end(); ++it) {
      // Copies: the iterator's operator-> returns a proxy that dies at the end of the statement.
      const YAML::Node key_node = it->first;
      const YAML::Node value = it->second;
      if (!key_node.IsScalar()) fail(key_node, path, "keys must be plain names");
      const std::string& key = key_node.Scalar();
      const std::string key_path = path.empty() ? key : path + '.' + key;
      if (!allowed.count(key)) fail(key_node, key_path, "unknown key; allowed: " + list(allowed));
      if (!seen.insert(key).second) fail(key_node, key_path, "duplicate key");
      read(key_path, value);
    }
  }

  [[nodiscard]] double number(const YAML::Node& node, const std::string& path) const {
    if (!is_plain_scalar(node)) fail(node, path, "must be a number, got " + describe(node));
    const auto value = parse_number(node.Scalar());
    if (!value) fail(node, path, "must be a number, got " + describe(node));
    return *value;
  }

  [[nodiscard]] long long integer(const YAML::Node& node, const std::string& path) const {
    if (!is_plain_scalar(node)) fail(node, path, "must be an integer, got " + describe(node));
    const auto value = parse_integer(node.Scalar());
    if (!value) fail(node, path, "must be an integer, got " + describe(node));
    return *value;
  }

  [[nodiscard]] std::string text(const YAML::Node& node, const std::string& path) const {
    if (!node.IsScalar()) fail(node, path, "must be a string, got " + describe(node));
    return node.Scalar();
  }

  void check(const YAML::Node& node, const std::string& path, const std::string& error) const {
    if (!error.empty()) fail(node, path, error);
  }

 private:
  // A quoted "0.3" is a string in YAML: a number is expected unquoted.
  static bool is_plain_scalar(const YAML::Node& node) {
    return node.IsScalar() && node.Tag() != "!";
  }

  static std::string describe(const YAML::Node& node) {
    switch (node.Type()) {
      case YAML::NodeType::Null:
      case YAML::NodeType::Undefined:
        return "nothing";
      case YAML::NodeType::Sequence:
        return "a sequence";
      case YAML::NodeType::Map:
        return "a mapping";
      case YAML::NodeType::Scalar:
        break;
    }
    return (node.Tag() == "!" ? "string '" : "'") + node.Scalar() + "'";
  }

  static std::string list(const std::set<std::string>& names) {
    std::string text;
    for (const auto& name : names) text += (text.empty() ? "" : ", ") + name;
    return text;
  }

  std::string file_;
};

void read_loop_sweep(Reader& reader, const YAML::Node& node, const std::string& path,
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
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(file_name, e.mark.line + 1, e.mark.column + 1, "", "invalid YAML: " + e.msg);
  }
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
  std::error_code ignored;
  if (std::filesystem::is_directory(file, ignored)) {
    throw InputError(file.string(), 0, 0, "", "cannot open case file: it is a directory");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw InputError(file.string(), 0, 0, "",
                     std::string("cannot open case file: ") + std::strerror(errno));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    throw InputError(file.string(), 0, 0, "", "cannot read case file");
  }
  return parse_loop_sweep_case(text.str(), file.string());
}

}  // namespace jointhb::io
