// The samples of a parameter study (study/sampling.hpp).
#include "jointhb/study/sampling.hpp"

#include <fmt/format.h>

#include <boost/random/sobol.hpp>
#include <cmath>
#include <set>
#include <stdexcept>

#include "jointhb/fit/fitter.hpp"
#include "jointhb/fit/parameters.hpp"

namespace jointhb::study {
namespace {

// The largest design a study accepts (a grid's product included): far beyond what a machine
// evaluates, small enough that the sample list fits in memory.
constexpr std::size_t kMaxSamples = 10'000'000;
// boost::random::sobol's table: the Joe–Kuo direction numbers up to this dimension.
constexpr std::size_t kMaxSobolDimensions = 3667;

bool uses_values(SamplingKind kind) { return kind == SamplingKind::list || kind == SamplingKind::grid; }

fit::FitParameter as_range(const StudyParameter& p) {
  fit::FitParameter f;
  f.name = p.name;
  f.lower = p.lower;
  f.upper = p.upper;
  f.start = p.lower;
  f.log_scale = p.log_scale;
  return f;
}

}  // namespace

const char* to_string(SamplingKind kind) {
  switch (kind) {
    case SamplingKind::list: return "list";
    case SamplingKind::grid: return "grid";
    case SamplingKind::latin_hypercube: return "latin_hypercube";
    case SamplingKind::sobol: return "sobol";
  }
  return "list";
}

std::optional<SamplingKind> sampling_kind(std::string_view name) {
  for (SamplingKind k : {SamplingKind::list, SamplingKind::grid, SamplingKind::latin_hypercube, SamplingKind::sobol}) {
    if (name == to_string(k)) return k;
  }
  return std::nullopt;
}

std::string Sampling::validate() const {
  if (parameters.empty()) return "parameters: must name at least one parameter";
  std::set<std::string> seen;
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const StudyParameter& p = parameters[i];
    const std::string at = fmt::format("parameters[{}]", i);
    if (p.name.empty()) return at + ".name: must not be empty";
    if (!seen.insert(p.name).second) return fmt::format("{}.name: '{}' is listed twice", at, p.name);
    if (uses_values(kind)) {
      if (p.values.empty()) return fmt::format("{}.values: must hold at least one value ({} sampling)", at, to_string(kind));
      for (double v : p.values) {
        if (!std::isfinite(v)) return fmt::format("{}.values: must be finite numbers", at);
      }
      if (kind == SamplingKind::list && p.values.size() != parameters.front().values.size()) {
        return fmt::format("{}.values: a list study needs as many values for every parameter ({} for {}), got {}", at,
                           parameters.front().values.size(), parameters.front().name, p.values.size());
      }
    } else {
      if (const std::string e = as_range(p).validate(); !e.empty()) return e;
    }
  }
  if (!uses_values(kind)) {
    if (samples < 1) return fmt::format("samples: must be >= 1 ({} sampling), got {}", to_string(kind), samples);
    if (static_cast<std::size_t>(samples) > kMaxSamples) return fmt::format("samples: must be <= {}, got {}", kMaxSamples, samples);
    if (kind == SamplingKind::sobol && parameters.size() > kMaxSobolDimensions)
      return fmt::format("parameters: sobol sampling takes at most {} parameters, got {}", kMaxSobolDimensions, parameters.size());
  }
  if (kind == SamplingKind::grid) {
    double product = 1.0;
    for (const auto& p : parameters) product *= static_cast<double>(p.values.size());
    if (product > static_cast<double>(kMaxSamples))
      return fmt::format("parameters: the grid has {:.3g} samples, at most {} are accepted", product, kMaxSamples);
  }
  return "";
}

std::size_t Sampling::count() const {
  switch (kind) {
    case SamplingKind::list: return parameters.empty() ? 0 : parameters.front().values.size();
    case SamplingKind::grid: {
      std::size_t n = parameters.empty() ? 0 : 1;
      for (const auto& p : parameters) n *= p.values.size();
      return n;
    }
    case SamplingKind::latin_hypercube:
    case SamplingKind::sobol: return samples > 0 ? static_cast<std::size_t>(samples) : 0;
  }
  return 0;
}

std::vector<std::vector<double>> sobol_points(int count, int dimensions) {
  std::vector<std::vector<double>> points;
  if (count <= 0 || dimensions <= 0) return points;
  boost::random::sobol engine(static_cast<std::size_t>(dimensions));
  // The engine returns integers of 64 bits per coordinate: u = x 2^-64 (rounded to a double).
  // Boost's sequence already leaves out the all-zero point on the box's corner: its first point
  // is (1/2, ..., 1/2), then (3/4, 1/4, ...), (1/4, 3/4, ...).
  constexpr double kScale = 0x1.0p-64;
  points.assign(static_cast<std::size_t>(count), std::vector<double>(static_cast<std::size_t>(dimensions)));
  for (auto& point : points) {
    for (auto& u : point) u = static_cast<double>(engine()) * kScale;
  }
  return points;
}

std::vector<std::vector<double>> sample_points(const Sampling& sampling) {
  if (const std::string e = sampling.validate(); !e.empty()) throw std::invalid_argument("study: " + e);
  const auto& ps = sampling.parameters;
  const std::size_t n = sampling.count();
  std::vector<std::vector<double>> out(n, std::vector<double>(ps.size()));
  switch (sampling.kind) {
    case SamplingKind::list:
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t d = 0; d < ps.size(); ++d) out[i][d] = ps[d].values[i];
      }
      break;
    case SamplingKind::grid:
      for (std::size_t i = 0; i < n; ++i) {
        std::size_t rest = i;  // mixed-radix digits, the last parameter fastest
        for (std::size_t d = ps.size(); d-- > 0;) {
          out[i][d] = ps[d].values[rest % ps[d].values.size()];
          rest /= ps[d].values.size();
        }
      }
      break;
    case SamplingKind::latin_hypercube:
    case SamplingKind::sobol: {
      const int dims = static_cast<int>(ps.size());
      // fit::latin_hypercube gives count − 1 points (its point 0 is a fit's own start).
      const auto unit = sampling.kind == SamplingKind::sobol
                            ? sobol_points(sampling.samples, dims)
                            : fit::latin_hypercube(sampling.samples + 1, dims, sampling.seed);
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t d = 0; d < ps.size(); ++d) out[i][d] = as_range(ps[d]).from_unit(unit[i][d]);
      }
      break;
    }
  }
  return out;
}

}  // namespace jointhb::study
