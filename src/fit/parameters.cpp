#include "jointhb/fit/parameters.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace jointhb::fit {

std::string FitParameter::validate() const {
  if (name.empty()) return "name: must not be empty";
  if (!std::isfinite(lower)) return fmt::format("{}.lower: must be finite, got {}", name, lower);
  if (!std::isfinite(upper)) return fmt::format("{}.upper: must be finite, got {}", name, upper);
  if (!(lower < upper)) {
    return fmt::format("{}.upper: must be > lower = {}, got {}", name, lower, upper);
  }
  if (log_scale && !(lower > 0.0)) {
    return fmt::format("{}.lower: must be > 0 with log_scale, got {}", name, lower);
  }
  if (!std::isfinite(start) || start < lower || start > upper) {
    return fmt::format("{}.start: must be in [lower, upper] = [{}, {}], got {}", name, lower, upper,
                       start);
  }
  return "";
}

double FitParameter::to_unit(double value) const {
  double u = 0.0;
  if (log_scale) {
    u = (std::log10(value) - std::log10(lower)) / (std::log10(upper) - std::log10(lower));
  } else {
    u = (value - lower) / (upper - lower);
  }
  return std::clamp(u, 0.0, 1.0);
}

double FitParameter::from_unit(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  if (u == 0.0) return lower;
  if (u == 1.0) return upper;
  if (log_scale) {
    const double a = std::log10(lower);
    const double b = std::log10(upper);
    return std::pow(10.0, a + u * (b - a));
  }
  return lower + u * (upper - lower);
}

double FitParameter::derivative(double u) const {
  if (log_scale) {
    return from_unit(u) * std::log(10.0) * (std::log10(upper) - std::log10(lower));
  }
  return upper - lower;
}

std::string validate(const std::vector<FitParameter>& parameters) {
  if (parameters.empty()) return "parameters: must name at least one parameter";
  std::set<std::string> seen;
  for (const auto& p : parameters) {
    if (auto e = p.validate(); !e.empty()) return e;
    if (!seen.insert(p.name).second) return fmt::format("{}: is listed twice", p.name);
  }
  return "";
}

std::vector<double> to_unit(const std::vector<FitParameter>& parameters,
                            const std::vector<double>& values) {
  std::vector<double> u(parameters.size());
  for (std::size_t i = 0; i < parameters.size(); ++i) u[i] = parameters[i].to_unit(values[i]);
  return u;
}

std::vector<double> from_unit(const std::vector<FitParameter>& parameters,
                              const std::vector<double>& unit) {
  std::vector<double> v(parameters.size());
  for (std::size_t i = 0; i < parameters.size(); ++i) v[i] = parameters[i].from_unit(unit[i]);
  return v;
}

}  // namespace jointhb::fit
