#pragma once
// The constraints that case files and command-line options share, phrased once so that both report
// a broken constraint in the same words ("must be > 0, got -1"). Each check returns an empty
// string when the value is valid, otherwise the constraint and the offending value; the caller adds
// where the value came from (file:line:column and key path, or the option name).

#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

namespace jointhb::io {

/// Upper bounds that keep a mistyped count from allocating gigabytes or running for days.
inline constexpr long long max_time_samples = 1 << 20;
inline constexpr long long max_sweep_points = 100000;

/// Shortest text that reads back to the same double ("-1", "0.3", "not-a-number", "inf").
std::string format_number(double value);

/// The magnitudes a physical input of a discrete case may have: 0, or |v| in [1e-100, 1e100]
/// (jointhb computes in SI doubles; products of three such inputs stay representable).
inline constexpr double kMinMagnitude = 1e-100;
inline constexpr double kMaxMagnitude = 1e100;
/// Empty when `value` is finite and 0 or of a magnitude in [kMinMagnitude, kMaxMagnitude].
std::string check_magnitude(double value);

/// The whole text as a number. Accepts what strtod accepts (including "nan" and "inf", so that the
/// check below can name them) and the YAML spellings .nan/.inf/-.inf; nullopt for anything else.
std::optional<double> parse_number(std::string_view text);
/// The whole text as a decimal integer; nullopt for anything else ("41.0", "4e1", overflow).
std::optional<long long> parse_integer(std::string_view text);

std::string check_finite(double value);
std::string check_positive(double value);      ///< finite and > 0
std::string check_non_negative(double value);  ///< finite and ≥ 0
std::string check_open_unit(double value);     ///< finite and in (0, 1)
std::string check_in_range(long long value, long long min, long long max);  ///< in [min, max]
std::string check_one_of(std::string_view value, std::initializer_list<std::string_view> allowed);

}  // namespace jointhb::io
