#include "fit_keys.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include "jointhb/pipeline/discrete_fit_model.hpp"
#include "jointhb/io/input_error.hpp"
#include "jointhb/io/value_checks.hpp"

namespace jointhb::io {
namespace {

using yaml::child_path;
using yaml::Fields;
using yaml::item_path;

constexpr long long max_evaluations_limit = 1000000;
constexpr long long max_starts = 1000;

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

fit::FitParameter read_parameter(const yaml::Reader& reader, const YAML::Node& node,
                                 const std::string& path, const std::vector<std::string>& valid) {
  const Fields f = reader.fields(node, path, {"name", "lower", "upper", "start", "log_scale"});
  for (const char* name : {"name", "lower", "upper", "start"}) {
    if (!f.has(name)) reader.fail(node, f.path_of(name), "required");
  }
  fit::FitParameter p;
  const YAML::Node name = f.find("name")->value;
  p.name = reader.text(name, f.path_of("name"));
  if (std::find(valid.begin(), valid.end(), p.name) == valid.end()) {
    reader.fail(name, f.path_of("name"),
                fmt::format("unknown parameter '{}'; this case has: {}", p.name, join(valid)));
  }
  if (const auto* log = f.find("log_scale")) {
    p.log_scale = reader.boolean(log->value, f.path_of("log_scale"));
  }
  const YAML::Node lower = f.find("lower")->value;
  const YAML::Node upper = f.find("upper")->value;
  const YAML::Node start = f.find("start")->value;
  p.lower = reader.finite_number(lower, f.path_of("lower"));
  p.upper = reader.finite_number(upper, f.path_of("upper"));
  p.start = reader.finite_number(start, f.path_of("start"));
  if (p.log_scale && !(p.lower > 0.0)) {
    reader.fail(lower, f.path_of("lower"),
                fmt::format("must be > 0 with log_scale true, got {}", format_number(p.lower)));
  }
  if (!(p.upper > p.lower)) {
    reader.fail(upper, f.path_of("upper"),
                fmt::format("must be > lower = {}, got {}", format_number(p.lower),
                            format_number(p.upper)));
  }
  if (p.start < p.lower || p.start > p.upper) {
    reader.fail(start, f.path_of("start"),
                fmt::format("must be in [lower, upper] = [{}, {}], got {}", format_number(p.lower),
                            format_number(p.upper), format_number(p.start)));
  }
  return p;
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream s(line);
  while (std::getline(s, cell, ',')) {
    const auto b = cell.find_first_not_of(" \t");
    const auto e = cell.find_last_not_of(" \t");
    cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// At most the first 80 bytes of a line echoed in a message: the "header" of a binary file may be
// kilobytes long (InputError escapes its control bytes).
std::string excerpt(const std::string& line) {
  constexpr std::size_t kMax = 80;
  return line.size() <= kMax ? line : line.substr(0, kMax) + "...";
}

// Columns of each target type: the abscissa, the measured quantities (any subset may be used).
struct Layout {
  std::string abscissa;
  std::vector<std::pair<std::string, fit::Quantity>> quantities;
};

Layout layout_of(fit::TargetKind kind) {
  switch (kind) {
    case fit::TargetKind::backbone:
      return {"amplitude",
              {{"frequency_hz", fit::Quantity::frequency_hz},
               {"damping_ratio", fit::Quantity::damping_ratio}}};
    case fit::TargetKind::frf:
      return {"frequency_hz", {{"amplitude", fit::Quantity::amplitude}}};
    case fit::TargetKind::modal:
      return {"mode",
              {{"frequency_hz", fit::Quantity::frequency_hz},
               {"damping_ratio", fit::Quantity::damping_ratio}}};
  }
  return {};
}

// Reads the points of a target CSV: a header naming the columns, '#' comment lines, one row per
// measurement. Optional columns: weight (per row), sigma_<quantity> (absolute scale).
// The abscissae the model can predict: [lo, hi] of the analysis the target uses, and what to
// call that range in an error.
struct Range {
  double lo = 0.0;
  double hi = 0.0;
  std::string what;  ///< empty: no range check
};

void read_points(const std::filesystem::path& file, const std::string& key, fit::Target& t,
                 const std::vector<fit::Quantity>& use, double weight, int modes,
                 const Range& range) {
  std::ifstream in(file);
  const std::string name = file.string();
  if (!in) throw InputError(name, 0, 0, key, "cannot read the target file");
  const Layout layout = layout_of(t.kind);
  std::vector<std::string> header;
  std::map<std::string, std::size_t> column;
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto cells = split_csv(line);
    if (header.empty()) {
      header = cells;
      for (std::size_t i = 0; i < header.size(); ++i) {
        if (column.count(header[i])) {
          throw InputError(name, line_number, 1, key,
                           fmt::format("column '{}' appears twice in the header", header[i]));
        }
        column[header[i]] = i;
      }
      std::vector<std::string> needed = {layout.abscissa};
      for (const auto& [qname, q] : layout.quantities) {
        if (std::find(use.begin(), use.end(), q) != use.end()) needed.push_back(qname);
      }
      for (const auto& n : needed) {
        if (!column.count(n)) {
          throw InputError(name, line_number, 1, key,
                           fmt::format("the header must name the columns {} (a {} target), got "
                                       "'{}'",
                                       join(needed), fit::to_string(t.kind), excerpt(line)));
        }
      }
      continue;
    }
    if (cells.size() != header.size()) {
      throw InputError(
          name, line_number, 1, key,
          fmt::format("{} cells, the header has {} columns", cells.size(), header.size()));
    }
    const auto value = [&](const std::string& col, double& out) {
      const auto it = column.find(col);
      if (it == column.end()) return false;
      const std::string& text = cells[it->second];
      const auto v = parse_number(text);
      int col_pos = 1;
      for (std::size_t i = 0; i < it->second; ++i) col_pos += static_cast<int>(cells[i].size()) + 1;
      if (!v || !std::isfinite(*v)) {
        const std::string got = v && std::isnan(*v) ? std::string("not-a-number") : "'" + text + "'";
        throw InputError(name, line_number, col_pos, key,
                         fmt::format("column '{}' must be a finite number, got {}", col, got));
      }
      out = *v;
      return true;
    };
    double x = 0.0;
    value(layout.abscissa, x);
    if (t.kind != fit::TargetKind::modal && !(x > 0.0)) {
      throw InputError(name, line_number, 1, key,
                       fmt::format("{} must be > 0, got {}", layout.abscissa, format_number(x)));
    }
    if (t.kind == fit::TargetKind::modal &&
        (x != std::floor(x) || x < 1 || x > static_cast<double>(modes))) {
      throw InputError(
          name, line_number, 1, key,
          fmt::format("mode must be an integer in [1, {}], got {}", modes, format_number(x)));
    }
    // (1e-12: the range was converted from log10 or rad/s, the value may sit on its end)
    if (!range.what.empty() && (x < range.lo * (1 - 1e-12) || x > range.hi * (1 + 1e-12))) {
      throw InputError(name, line_number, 1, key,
                       fmt::format("{} {} lies outside {}: the model cannot predict it",
                                   layout.abscissa, format_number(x), range.what));
    }
    double row_weight = 1.0;
    if (value("weight", row_weight) && row_weight < 0.0) {
      throw InputError(name, line_number, 1, key,
                       fmt::format("weight must be >= 0, got {}", format_number(row_weight)));
    }
    for (const auto& [qname, q] : layout.quantities) {
      if (std::find(use.begin(), use.end(), q) == use.end()) continue;
      fit::TargetPoint p;
      p.abscissa = x;
      p.quantity = q;
      p.line = line_number;
      value(qname, p.measured);
      // Frequencies and amplitudes are positive, damping ratios not negative.
      if (p.measured < 0.0 || (p.measured == 0.0 && q != fit::Quantity::damping_ratio)) {
        throw InputError(name, line_number, 1, key,
                         fmt::format("{} must be {}, got {}", qname,
                                     q == fit::Quantity::damping_ratio ? ">= 0" : "> 0",
                                     format_number(p.measured)));
      }
      p.weight = weight * row_weight;
      double sigma = 0.0;
      if (value("sigma_" + qname, sigma) && !(sigma > 0.0)) {
        throw InputError(name, line_number, 1, key,
                         fmt::format("sigma_{} must be > 0, got {}", qname, format_number(sigma)));
      }
      p.sigma = sigma;
      if (p.sigma == 0.0 && p.measured == 0.0) {
        throw InputError(name, line_number, 1, key,
                         fmt::format("{} is 0: a relative residual needs a value != 0 (or give "
                                     "a sigma_{} column)",
                                     qname, qname));
      }
      t.points.push_back(p);
    }
  }
  if (header.empty()) throw InputError(name, 0, 0, key, "the target file is empty");
  if (t.points.empty()) throw InputError(name, 0, 0, key, "the target file has no data rows");
}

fit::Target read_target(const yaml::Reader& reader, const YAML::Node& node, const std::string& path,
                        const FitContext& c, const std::filesystem::path& case_dir) {
  const Fields f = reader.fields(node, path, {"type", "file", "mode", "level", "weight", "use"});
  for (const char* name : {"type", "file"}) {
    if (!f.has(name)) reader.fail(node, f.path_of(name), "required");
  }
  fit::Target t;
  t.name = path;
  const YAML::Node type = f.find("type")->value;
  const std::string kind = reader.text(type, f.path_of("type"));
  reader.check(type, f.path_of("type"), check_one_of(kind, {"backbone", "frf", "modal"}));
  t.kind = kind == "backbone" ? fit::TargetKind::backbone
           : kind == "frf"    ? fit::TargetKind::frf
                              : fit::TargetKind::modal;
  const int n = c.modes;
  if (const auto* mode = f.find("mode")) {
    if (t.kind != fit::TargetKind::backbone) {
      reader.fail(mode->key, f.path_of("mode"), "only for type backbone");
    }
    const long long k = reader.integer(mode->value, f.path_of("mode"));
    reader.check(mode->value, f.path_of("mode"), check_in_range(k, 1, n));
    t.mode = static_cast<int>(k);
  }
  if (const auto* level = f.find("level")) {
    if (t.kind != fit::TargetKind::frf) {
      reader.fail(level->key, f.path_of("level"), "only for type frf");
    }
    const long long l = reader.integer(level->value, f.path_of("level"));
    reader.check(level->value, f.path_of("level"),
                 check_in_range(l, 0, static_cast<long long>(c.levels) - 1));
    t.level = static_cast<int>(l);
  }
  if (t.kind == fit::TargetKind::backbone && !c.backbone) {
    reader.fail(type, f.path_of("type"),
                "a backbone target needs analysis.nonlinear_modes (its harmonics, amplitude "
                "range and continuation settings are used)");
  }
  if (t.kind == fit::TargetKind::backbone && !c.backbone_modes.empty() &&
      std::find(c.backbone_modes.begin(), c.backbone_modes.end(), t.mode) == c.backbone_modes.end()) {
    reader.fail(type, f.path_of("type"),
                fmt::format("a backbone target of mode {} needs that mode in analysis.nonlinear_modes.mode", t.mode));
  }
  if (t.kind == fit::TargetKind::frf && !c.frf) {
    reader.fail(type, f.path_of("type"),
                "an frf target needs analysis.frf (its frequency range, harmonics and "
                "output are used)");
  }
  double weight = 1.0;
  if (const auto* w = f.find("weight")) {
    weight = reader.number(w->value, f.path_of("weight"));
    reader.check(w->value, f.path_of("weight"), check_positive(weight));
  }
  const Layout layout = layout_of(t.kind);
  std::vector<fit::Quantity> use;
  if (const auto* u = f.find("use")) {
    const std::string key = f.path_of("use");
    if (!u->value.IsSequence() || u->value.size() == 0) {
      reader.fail(u->value, key, "must be a non-empty list of measured columns");
    }
    for (std::size_t i = 0; i < u->value.size(); ++i) {
      const std::string q = reader.text(u->value[i], item_path(key, i));
      bool found = false;
      for (const auto& [qname, quantity] : layout.quantities) {
        if (qname == q) {
          if (std::find(use.begin(), use.end(), quantity) != use.end()) {
            reader.fail(u->value[i], item_path(key, i), "listed twice");
          }
          use.push_back(quantity);
          found = true;
        }
      }
      if (!found) {
        std::vector<std::string> names;
        for (const auto& [qname, quantity] : layout.quantities) names.push_back(qname);
        reader.fail(
            u->value[i], item_path(key, i),
            fmt::format("must be one of {} for a {} target, got '{}'", join(names), kind, q));
      }
    }
  } else {
    for (const auto& [qname, quantity] : layout.quantities) use.push_back(quantity);
  }
  const YAML::Node file = f.find("file")->value;
  const std::string file_text = reader.text(file, f.path_of("file"));
  std::filesystem::path target_file(file_text);
  if (target_file.is_relative()) target_file = case_dir / target_file;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(target_file, ec)) {
    reader.fail(file, f.path_of("file"),
                fmt::format("cannot read '{}' (relative paths start at the case file's folder)",
                            target_file.string()));
  }
  t.file = target_file.string();
  Range range;
  if (t.kind == fit::TargetKind::backbone) {
    const double a = c.backbone->first, b = c.backbone->second;
    range = {std::pow(10.0, std::min(a, b)), std::pow(10.0, std::max(a, b)),
             fmt::format("analysis.nonlinear_modes.log10_amplitude [{}, {}]", format_number(a),
                         format_number(b))};
  } else if (t.kind == fit::TargetKind::frf) {
    const double a = c.frf->first, b = c.frf->second;
    range = {std::min(a, b), std::max(a, b),
             fmt::format("the range of analysis.frf [{:.6g}, {:.6g}] Hz", a, b)};
  }
  read_points(target_file, f.path_of("file"), t, use, weight, n, range);
  return t;
}

}  // namespace

FitContext fit_context(const DiscreteCase& c) {
  FitContext x;
  x.names = pipeline::discrete_parameter_names(c);
  x.modes = c.system.dofs();
  x.levels = static_cast<int>(c.levels.size());
  if (c.nonlinear_modes)
    x.backbone = std::pair(c.nonlinear_modes->log10_amplitude_start, c.nonlinear_modes->log10_amplitude_end);
  if (c.frf)
    x.frf = std::pair(c.frf->omega_start / (2.0 * std::numbers::pi), c.frf->omega_end / (2.0 * std::numbers::pi));
  return x;
}

FitSection read_fit_section(const yaml::Reader& reader, const YAML::Node& node,
                            const std::string& path, const FitContext& c,
                            const std::filesystem::path& case_dir) {
  const Fields f =
      reader.fields(node, path,
                    {"parameters", "targets", "algorithm", "local_algorithm", "xtol", "ftol_rel",
                     "max_evaluations", "multistart", "penalty", "initial_step", "jacobian_step",
                     "friction_in_dynamics_only"});
  FitSection s;
  const auto* parameters = f.find("parameters");
  if (!parameters) reader.fail(node, f.path_of("parameters"), "required: a list of parameters");
  const std::string ppath = f.path_of("parameters");
  if (!parameters->value.IsSequence() || parameters->value.size() == 0) {
    reader.fail(parameters->value, ppath,
                "must be a non-empty list of {name, lower, upper, start[, log_scale]}");
  }
  const std::vector<std::string>& valid = c.names;
  for (std::size_t i = 0; i < parameters->value.size(); ++i) {
    const std::string item = item_path(ppath, i);
    s.parameters.push_back(read_parameter(reader, parameters->value[i], item, valid));
    for (std::size_t k = 0; k + 1 < s.parameters.size(); ++k) {
      if (s.parameters[k].name == s.parameters.back().name) {
        reader.fail(parameters->value[i]["name"], child_path(item, "name"),
                    fmt::format("'{}' is already {}[{}]", s.parameters.back().name, ppath, k));
      }
    }
  }
  const auto* targets = f.find("targets");
  if (!targets) reader.fail(node, f.path_of("targets"), "required: a list of measured targets");
  const std::string tpath = f.path_of("targets");
  if (!targets->value.IsSequence() || targets->value.size() == 0) {
    reader.fail(targets->value, tpath, "must be a non-empty list of {type, file, ...}");
  }
  for (std::size_t i = 0; i < targets->value.size(); ++i) {
    s.targets.push_back(read_target(reader, targets->value[i], item_path(tpath, i), c, case_dir));
  }

  fit::FitOptions& o = s.options;
  const auto text_of = [&](const char* key, std::string& out,
                           std::initializer_list<std::string_view> allowed) {
    if (const auto* e = f.find(key)) {
      out = reader.text(e->value, f.path_of(key));
      reader.check(e->value, f.path_of(key), check_one_of(out, allowed));
    }
  };
  text_of("algorithm", o.algorithm, {"bobyqa", "neldermead", "cobyla", "direct", "mlsl"});
  text_of("local_algorithm", o.local_algorithm, {"bobyqa", "neldermead"});
  const auto number_in = [&](const char* key, double& out, double lo, double hi, bool open_lo) {
    if (const auto* e = f.find(key)) {
      out = reader.number(e->value, f.path_of(key));
      if (!std::isfinite(out) || (open_lo ? out <= lo : out < lo) || out > hi) {
        reader.fail(e->value, f.path_of(key),
                    fmt::format("must be in {}{}, {}], got {}", open_lo ? "(" : "[", lo, hi,
                                format_number(out)));
      }
    }
  };
  number_in("xtol", o.xtol, 0.0, 0.1, true);
  number_in("ftol_rel", o.ftol_rel, 0.0, 0.1, false);
  number_in("initial_step", o.initial_step, 0.0, 0.5, true);
  number_in("jacobian_step", o.jacobian_step, 0.0, 0.1, true);
  if (const auto* e = f.find("friction_in_dynamics_only")) {
    if (!c.finite_element) reader.fail(e->key, f.path_of("friction_in_dynamics_only"), "only for finite-element cases");
    s.friction_in_dynamics_only = reader.boolean(e->value, f.path_of("friction_in_dynamics_only"));
  }
  if (const auto* e = f.find("penalty")) {
    o.penalty = reader.number(e->value, f.path_of("penalty"));
    reader.check(e->value, f.path_of("penalty"), check_non_negative(o.penalty));
  }
  if (const auto* e = f.find("max_evaluations")) {
    const long long v = reader.integer(e->value, f.path_of("max_evaluations"));
    reader.check(e->value, f.path_of("max_evaluations"),
                 check_in_range(v, 1, max_evaluations_limit));
    o.max_evaluations = static_cast<int>(v);
  }
  if (const auto* e = f.find("multistart")) {
    const Fields m = reader.fields(e->value, f.path_of("multistart"), {"starts", "seed"});
    if (const auto* starts = m.find("starts")) {
      const long long v = reader.integer(starts->value, m.path_of("starts"));
      reader.check(starts->value, m.path_of("starts"), check_in_range(v, 1, max_starts));
      o.starts = static_cast<int>(v);
    }
    if (const auto* seed = m.find("seed")) {
      const long long v = reader.integer(seed->value, m.path_of("seed"));
      reader.check(seed->value, m.path_of("seed"), check_in_range(v, 0, 4294967295LL));
      o.seed = static_cast<unsigned>(v);
    }
  }
  return s;
}

}  // namespace jointhb::io
