#pragma once
// The parameters of an identification and their search coordinates. NLopt searches the unit box
// u ∈ [0, 1]^p; each parameter θ maps to it linearly or, with log_scale, in log10:
//   u = (θ − lower) / (upper − lower)                                   (linear)
//   u = (log10 θ − log10 lower) / (log10 upper − log10 lower)           (log_scale, lower > 0)
// so that every coordinate has the same range, the derivative-free searches take comparable
// steps in all of them, and a parameter known only to a decade is searched over decades.
// docs/identification.md §2.

#include <string>
#include <vector>

namespace jointhb::fit {

struct FitParameter {
  std::string name;        ///< what the model adapter understands (e.g. "contacts[0].kt0")
  double lower = 0.0;      ///< bound, finite, < upper (> 0 with log_scale)
  double upper = 1.0;      ///< bound, finite
  double start = 0.5;      ///< first guess, in [lower, upper]
  bool log_scale = false;  ///< search in log10 θ

  /// Empty when valid, else "NAME.field: constraint, got value".
  [[nodiscard]] std::string validate() const;
  /// u ∈ [0, 1] of θ (clamped to the box).
  [[nodiscard]] double to_unit(double value) const;
  /// θ of u (u clamped to [0, 1]; the bounds are returned exactly at u = 0 and u = 1).
  [[nodiscard]] double from_unit(double u) const;
  /// dθ/du at u: (upper − lower), or θ ln 10 (log10 upper − log10 lower).
  [[nodiscard]] double derivative(double u) const;
};

/// Empty when every parameter is valid and the names are distinct.
std::string validate(const std::vector<FitParameter>& parameters);

std::vector<double> to_unit(const std::vector<FitParameter>& parameters,
                            const std::vector<double>& values);
std::vector<double> from_unit(const std::vector<FitParameter>& parameters,
                              const std::vector<double>& unit);

}  // namespace jointhb::fit
