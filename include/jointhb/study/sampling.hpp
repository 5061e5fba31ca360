#pragma once
// The samples of a parameter study (docs/studies.md §2): which parameter vectors a study
// evaluates. Four designs:
//   list             sample i takes the i-th entry of every parameter's `values` (equal lengths)
//   grid             the tensor product of the parameters' `values`, the first parameter varying
//                    slowest (row-major order, as nested loops written in parameter order)
//   latin_hypercube  `samples` points, one per stratum of width 1/n in every coordinate of the
//                    unit box (M. D. McKay, R. J. Beckman, W. J. Conover, Technometrics 21 (1979)
//                    239–245), seeded and deterministic (fit::latin_hypercube's generator)
//   sobol            the first `samples` points of Sobol's sequence (I. M. Sobol', USSR Comput.
//                    Math. Math. Phys. 7 (1967) 86–112) with the Joe–Kuo direction numbers
//                    (S. Joe, F. Y. Kuo, SIAM J. Sci. Comput. 30 (2008) 2635–2654) of
//                    boost::random::sobol, from (1/2, ..., 1/2) (the all-zero point left out)
// The unit-box designs map u ∈ [0, 1] to a parameter as the identification does
// (fit/parameters.hpp): linearly between lower and upper, or in log10 with log_scale.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace jointhb::study {

enum class SamplingKind { list, grid, latin_hypercube, sobol };

[[nodiscard]] const char* to_string(SamplingKind kind);
/// The kind named `name` ("list", "grid", "latin_hypercube", "sobol"), or nullopt.
[[nodiscard]] std::optional<SamplingKind> sampling_kind(std::string_view name);

struct StudyParameter {
  std::string name;            ///< a parameter the case offers (as in a fit section)
  std::vector<double> values;  ///< list and grid: the values taken
  double lower = 0.0;          ///< latin_hypercube and sobol: the range (> 0 with log_scale)
  double upper = 1.0;
  bool log_scale = false;      ///< latin_hypercube and sobol: uniform in log10 of the value
};

struct Sampling {
  SamplingKind kind = SamplingKind::list;
  std::vector<StudyParameter> parameters;
  int samples = 0;    ///< latin_hypercube and sobol: how many (≥ 1)
  unsigned seed = 1;  ///< latin_hypercube
  /// Empty when valid, else "FIELD: constraint, got value".
  [[nodiscard]] std::string validate() const;
  /// How many samples the design has.
  [[nodiscard]] std::size_t count() const;
};

/// The samples in order: one vector of values (parameter order) per sample. Throws
/// std::invalid_argument when the design is invalid (Sampling::validate).
[[nodiscard]] std::vector<std::vector<double>> sample_points(const Sampling& sampling);

/// The first `count` points of the Sobol sequence in [0, 1)^dimensions, from (1/2, ..., 1/2).
[[nodiscard]] std::vector<std::vector<double>> sobol_points(int count, int dimensions);

}  // namespace jointhb::study
