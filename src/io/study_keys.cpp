// The `study:` section of a case (study_keys.hpp).
#include "study_keys.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "jointhb/io/value_checks.hpp"

namespace jointhb::io {
namespace {

using yaml::child_path;
using yaml::Fields;
using yaml::item_path;

// The largest number of samples a latin_hypercube or sobol design may ask for.
constexpr long long kMaxSamples = 10'000'000;

std::string name_list(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// A non-empty list of finite numbers.
std::vector<double> numbers(const yaml::Reader& reader, const YAML::Node& node, const std::string& path) {
  if (!node.IsSequence() || node.size() == 0) reader.fail(node, path, "must be a non-empty list of numbers, got " + yaml::Reader::describe(node));
  std::vector<double> v;
  for (std::size_t i = 0; i < node.size(); ++i) v.push_back(reader.finite_number(node[i], item_path(path, i)));
  return v;
}

study::StudyParameter read_parameter(const yaml::Reader& reader, const YAML::Node& node, const std::string& path,
                                     study::SamplingKind kind, const std::vector<std::string>& valid) {
  const bool by_values = kind == study::SamplingKind::list || kind == study::SamplingKind::grid;
  const Fields f = reader.fields(node, path, {"name", "values", "lower", "upper", "log_scale"});
  study::StudyParameter p;
  const auto* name = f.find("name");
  if (!name) reader.fail(node, f.path_of("name"), "required");
  p.name = reader.text(name->value, f.path_of("name"));
  if (std::find(valid.begin(), valid.end(), p.name) == valid.end())
    reader.fail(name->value, f.path_of("name"), fmt::format("unknown parameter '{}'; this case has: {}", p.name, name_list(valid)));
  const char* needed[] = {"lower", "upper"};
  if (by_values) {
    for (const char* key : {"lower", "upper", "log_scale"}) {
      if (const auto* e = f.find(key))
        reader.fail(e->key, f.path_of(key), fmt::format("not used by {} sampling (it takes values)", study::to_string(kind)));
    }
    const auto* values = f.find("values");
    if (!values) reader.fail(node, f.path_of("values"), fmt::format("required by {} sampling", study::to_string(kind)));
    p.values = numbers(reader, values->value, f.path_of("values"));
    return p;
  }
  if (const auto* e = f.find("values"))
    reader.fail(e->key, f.path_of("values"), fmt::format("not used by {} sampling (it takes lower and upper)", study::to_string(kind)));
  for (const char* key : needed) {
    if (!f.has(key)) reader.fail(node, f.path_of(key), fmt::format("required by {} sampling", study::to_string(kind)));
  }
  reader.flag(f, "log_scale", p.log_scale);
  const YAML::Node lower = f.find("lower")->value, upper = f.find("upper")->value;
  p.lower = reader.finite_number(lower, f.path_of("lower"));
  p.upper = reader.finite_number(upper, f.path_of("upper"));
  if (p.log_scale && !(p.lower > 0.0))
    reader.fail(lower, f.path_of("lower"), fmt::format("must be > 0 with log_scale true, got {}", format_number(p.lower)));
  if (!(p.upper > p.lower))
    reader.fail(upper, f.path_of("upper"),
                fmt::format("must be > lower = {}, got {}", format_number(p.lower), format_number(p.upper)));
  return p;
}

// Integers from a list, each in [lo, hi] and distinct.
std::vector<int> indices(const yaml::Reader& reader, const YAML::Node& node, const std::string& path, long long lo, long long hi,
                         const std::vector<int>& allowed) {
  if (!node.IsSequence() || node.size() == 0) reader.fail(node, path, "must be a non-empty list of integers, got " + yaml::Reader::describe(node));
  std::vector<int> out;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string at = item_path(path, i);
    const long long v = reader.integer(node[i], at);
    reader.check(node[i], at, check_in_range(v, lo, hi));
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), static_cast<int>(v)) == allowed.end())
      reader.fail(node[i], at, fmt::format("the case has no damping curve of mode {} (analysis.nonlinear_modes)", v));
    if (std::find(out.begin(), out.end(), static_cast<int>(v)) != out.end()) reader.fail(node[i], at, fmt::format("{} is listed twice", v));
    out.push_back(static_cast<int>(v));
  }
  return out;
}

// The default amplitudes: two per decade (log10 q on the half-integers) strictly inside the
// case's damping-curve range, or its midpoint when the range holds none.
std::vector<double> default_amplitudes(double lo, double hi) {
  std::vector<double> q;
  for (double k = std::ceil(2.0 * lo); k / 2.0 < hi; k += 1.0) {
    if (k / 2.0 > lo) q.push_back(std::pow(10.0, k / 2.0));
  }
  if (q.empty()) q.push_back(std::pow(10.0, 0.5 * (lo + hi)));
  return q;
}

}  // namespace

study::StudySpec read_study_section(const yaml::Reader& reader, const YAML::Node& node, const std::string& path,
                                    const FitContext& c) {
  const Fields f = reader.fields(node, path,
                                 {"sampling", "samples", "seed", "parameters", "modes", "amplitudes", "levels",
                                  "frequencies_hz", "quantiles", "friction_in_dynamics_only"});
  study::StudySpec s;
  const auto* sampling = f.find("sampling");
  if (!sampling) reader.fail(node, f.path_of("sampling"), "required: list, grid, latin_hypercube or sobol");
  const std::string kind = reader.text(sampling->value, f.path_of("sampling"));
  reader.check(sampling->value, f.path_of("sampling"), check_one_of(kind, {"list", "grid", "latin_hypercube", "sobol"}));
  s.sampling.kind = *study::sampling_kind(kind);
  const bool by_values = s.sampling.kind == study::SamplingKind::list || s.sampling.kind == study::SamplingKind::grid;
  if (const auto* e = f.find("samples")) {
    if (by_values) reader.fail(e->key, f.path_of("samples"), fmt::format("not used by {} sampling (the values give the samples)", kind));
    const long long v = reader.integer(e->value, f.path_of("samples"));
    reader.check(e->value, f.path_of("samples"), check_in_range(v, 1, kMaxSamples));
    s.sampling.samples = static_cast<int>(v);
  } else if (!by_values) {
    reader.fail(node, f.path_of("samples"), fmt::format("required by {} sampling", kind));
  }
  if (const auto* e = f.find("seed")) {
    if (s.sampling.kind != study::SamplingKind::latin_hypercube)
      reader.fail(e->key, f.path_of("seed"), fmt::format("only latin_hypercube sampling is seeded, not {}", kind));
    const long long v = reader.integer(e->value, f.path_of("seed"));
    reader.check(e->value, f.path_of("seed"), check_in_range(v, 0, 4294967295LL));
    s.sampling.seed = static_cast<unsigned>(v);
  }
  const auto* parameters = f.find("parameters");
  if (!parameters) reader.fail(node, f.path_of("parameters"), "required: a list of parameters");
  const std::string ppath = f.path_of("parameters");
  if (!parameters->value.IsSequence() || parameters->value.size() == 0)
    reader.fail(parameters->value, ppath,
                by_values ? "must be a non-empty list of {name, values}" : "must be a non-empty list of {name, lower, upper[, log_scale]}");
  for (std::size_t i = 0; i < parameters->value.size(); ++i) {
    const std::string item = item_path(ppath, i);
    s.sampling.parameters.push_back(read_parameter(reader, parameters->value[i], item, s.sampling.kind, c.names));
    const auto& p = s.sampling.parameters.back();
    for (std::size_t k = 0; k + 1 < s.sampling.parameters.size(); ++k) {
      if (s.sampling.parameters[k].name == p.name)
        reader.fail(parameters->value[i]["name"], child_path(item, "name"), fmt::format("'{}' is already {}[{}]", p.name, ppath, k));
    }
    if (s.sampling.kind == study::SamplingKind::list && p.values.size() != s.sampling.parameters.front().values.size())
      reader.fail(parameters->value[i]["values"], child_path(item, "values"),
                  fmt::format("a list study needs as many values for every parameter: {} has {}, this one {}",
                              s.sampling.parameters.front().name, s.sampling.parameters.front().values.size(), p.values.size()));
  }
  if (s.sampling.kind == study::SamplingKind::grid) {
    double product = 1.0;
    for (const auto& p : s.sampling.parameters) product *= static_cast<double>(p.values.size());
    if (product > static_cast<double>(kMaxSamples))
      reader.fail(parameters->value, ppath, fmt::format("the grid has {:.3g} samples, at most {} are accepted", product, kMaxSamples));
  }

  // Outputs: by default every damping curve and every FRF level of the case.
  study::StudyOutputs& o = s.outputs;
  if (const auto* e = f.find("modes")) {
    if (!c.backbone) reader.fail(e->key, f.path_of("modes"), "the case has no damping curves (analysis.nonlinear_modes)");
    o.modes = indices(reader, e->value, f.path_of("modes"), 1, std::max(c.modes, 1), c.backbone_modes);
  } else if (c.backbone) {
    o.modes = c.backbone_modes.empty() ? std::vector<int>{1} : c.backbone_modes;
  }
  if (const auto* e = f.find("amplitudes")) {
    if (!c.backbone) reader.fail(e->key, f.path_of("amplitudes"), "the case has no damping curves (analysis.nonlinear_modes)");
    const std::string apath = f.path_of("amplitudes");
    o.amplitudes = numbers(reader, e->value, apath);
    const double lo = std::pow(10.0, c.backbone->first), hi = std::pow(10.0, c.backbone->second);
    for (std::size_t i = 0; i < o.amplitudes.size(); ++i) {
      const double q = o.amplitudes[i];
      // (1e-12: the range was converted from log10, the value may sit on its start)
      if (!(q >= lo * (1 - 1e-12) && q < hi))
        reader.fail(e->value[i], item_path(apath, i),
                    fmt::format("must lie in [{}, {}) (analysis.nonlinear_modes.log10_amplitude), got {}", format_number(lo),
                                format_number(hi), format_number(q)));
    }
  } else if (c.backbone) {
    o.amplitudes = default_amplitudes(c.backbone->first, c.backbone->second);
  }
  if (const auto* e = f.find("levels")) {
    if (!c.frf) reader.fail(e->key, f.path_of("levels"), "the case has no FRF (analysis.frf)");
    o.levels = indices(reader, e->value, f.path_of("levels"), 0, std::max(c.levels - 1, 0), {});
  } else if (c.frf) {
    for (int l = 0; l < c.levels; ++l) o.levels.push_back(l);
  }
  if (const auto* e = f.find("frequencies_hz")) {
    if (!c.frf) reader.fail(e->key, f.path_of("frequencies_hz"), "the case has no FRF (analysis.frf)");
    const std::string fpath = f.path_of("frequencies_hz");
    o.frequencies_hz = numbers(reader, e->value, fpath);
    for (std::size_t i = 0; i < o.frequencies_hz.size(); ++i) {
      const double x = o.frequencies_hz[i];
      if (!(x >= c.frf->first * (1 - 1e-12) && x <= c.frf->second * (1 + 1e-12)))
        reader.fail(e->value[i], item_path(fpath, i),
                    fmt::format("must lie in the FRF's range [{}, {}] Hz (analysis.frf.omega), got {}", format_number(c.frf->first),
                                format_number(c.frf->second), format_number(x)));
    }
  }
  if (o.modes.empty() && o.levels.empty())
    reader.fail(node, path, "the case has neither damping curves (analysis.nonlinear_modes) nor an FRF (analysis.frf): nothing to report");
  if (const auto* e = f.find("quantiles")) {
    const std::string qpath = f.path_of("quantiles");
    s.quantiles = numbers(reader, e->value, qpath);
    for (std::size_t i = 0; i < s.quantiles.size(); ++i) {
      const double p = s.quantiles[i];
      if (!(p >= 0.0 && p <= 1.0)) reader.fail(e->value[i], item_path(qpath, i), fmt::format("must lie in [0, 1], got {}", format_number(p)));
      if (i > 0 && !(p > s.quantiles[i - 1]))
        reader.fail(e->value[i], item_path(qpath, i), fmt::format("must be larger than the one before ({}), got {}",
                                                                  format_number(s.quantiles[i - 1]), format_number(p)));
    }
  }
  if (const auto* e = f.find("friction_in_dynamics_only")) {
    if (!c.finite_element) reader.fail(e->key, f.path_of("friction_in_dynamics_only"), "only for finite-element cases");
    s.friction_in_dynamics_only = reader.boolean(e->value, f.path_of("friction_in_dynamics_only"));
  }
  if (const std::string e = s.validate(); !e.empty()) reader.fail(node, path, e);
  return s;
}

}  // namespace jointhb::io
