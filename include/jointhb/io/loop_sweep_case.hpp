#pragma once
// The loop-sweep case: one contact point driven by g_T = a cos ωt at amplitudes a = r g_max,
// r log-spaced over [r_min, r_max], with W_D compared against the closed forms (eq. 11/12 and the
// general-n formula). It is the built-in default case of `jointhb run` and the only analysis a
// case file can ask for so far. Schema and error format: docs/case-files.md.
//
//   analysis:
//     loop_sweep:
//       law: gaul-mayer          # or jenkins
//       n: 0.3333333333          # (0, 1)
//       mu: 0.3                  # > 0
//       normal_force: 100.0      # N, > 0
//       kt0: 1.0e6               # N/m, > 0
//       amplitude_over_gmax: [1.0e-6, 10.0]
//       points: 41               # >= 2
//       time_samples: 256        # >= 4

#include <filesystem>
#include <string>
#include <vector>

namespace jointhb::io {

struct LoopSweepCase {
  std::string law = "gaul-mayer";     ///< "gaul-mayer" or "jenkins"
  double exponent = 1.0 / 3.0;        ///< n ∈ (0, 1) (Mindlin's sphere by default)
  double friction_coefficient = 0.3;  ///< μ [-], > 0
  double normal_force = 100.0;        ///< F_N [N], > 0
  double stiffness = 1.0e6;           ///< k_T0 [N/m], > 0
  double ratio_min = 1.0e-6;          ///< smallest a/g_max, > 0
  double ratio_max = 10.0;            ///< largest a/g_max, > ratio_min
  int points = 25;                    ///< amplitudes in the sweep, [2, max_sweep_points]
  int time_samples = 256;             ///< samples per period, [4, max_time_samples]
  std::string source = "built-in";    ///< the case file it was read from, or "built-in"

  /// g_max [m]: μF_N/((1-n)k_T0) for gaul-mayer (slip to full slip on the virgin curve), μF_N/k_T0
  /// for jenkins (slip at which the slider first moves); the same values as LoopResult.
  /// A symmetric loop reaches gross slip at a = (g_max + μF_N/k_T0)/2: a/g_max = (2-n)/2 for
  /// gaul-mayer (its loading branch starts from F = 0, not from -F̂), 1 for jenkins.
  [[nodiscard]] double full_slip_span() const;
  /// r_i = r_min (r_max/r_min)^(i/(points-1)), i = 0..points-1; the ends are exact.
  [[nodiscard]] std::vector<double> amplitude_ratios() const;
};

/// The built-in default case (the defaults above).
LoopSweepCase default_loop_sweep_case();

/// Reads a case file. Throws InputError naming file, line, column, key path and constraint for an
/// unreadable file, YAML syntax errors, unknown or duplicate keys, wrong types, non-finite or
/// non-physical values. Keys left out take the built-in default value.
LoopSweepCase read_loop_sweep_case(const std::filesystem::path& file);

/// As read_loop_sweep_case, from text; `file_name` is what the errors call the file.
LoopSweepCase parse_loop_sweep_case(const std::string& text, const std::string& file_name);

}  // namespace jointhb::io
