#pragma once
// What an identification is fitted to, and the residuals of a model prediction against it,
// independent of the model type (discrete now, finite elements later):
//   backbone  amplitude-dependent frequency and damping of one mode: q → f [Hz], ζ
//   frf       a frequency response at one force level: f [Hz] → |x̂₁| (fundamental amplitude)
//   modal     modal values: mode k → f_k [Hz], ζ_k of the linearised (stuck) system
// Each measured value is one target point with its weight w_i and scale s_i; the residual is
//   r_i = w_i (y_i^pred − y_i^meas) / s_i,   s_i = σ_i when given, else |y_i^meas| (relative),
// and the objective is S = Σ r_i² (docs/identification.md §1). A model returns its curves
// (ModelPrediction); residuals() interpolates them at the measured abscissae, linearly in
// log10 q for backbones, in f for FRFs (the largest amplitude where a fold gives several). A
// measured abscissa outside a predicted curve's range is a failed evaluation (the penalty), not
// an extrapolation. A model may instead return its values at the measured abscissae directly
// (PredictedCurve::at_points), as the discrete adapter does after correcting each point onto the
// curve (pipeline/discrete_fit_model.hpp).

#include <string>
#include <vector>

namespace jointhb::fit {

enum class TargetKind { backbone, frf, modal };
enum class Quantity { frequency_hz, damping_ratio, amplitude };

[[nodiscard]] const char* to_string(TargetKind kind);
[[nodiscard]] const char* to_string(Quantity quantity);

struct TargetPoint {
  double abscissa = 0.0;  ///< backbone: modal amplitude q; frf: frequency [Hz]; modal: mode (≥ 1)
  Quantity quantity = Quantity::frequency_hz;
  double measured = 0.0;
  double weight = 1.0;  ///< w_i ≥ 0 (the target's weight times the row's)
  double sigma = 0.0;   ///< s_i when > 0; 0: relative residual (s_i = |measured|)
  int line = 0;         ///< line of the CSV file it came from (reports), 0 if none
  [[nodiscard]] double scale() const;
};

struct Target {
  std::string name;  ///< e.g. "targets[0]" (reports)
  TargetKind kind = TargetKind::backbone;
  int mode = 1;      ///< backbone: the mode followed (≥ 1)
  int level = 0;     ///< frf: the excitation level (≥ 0)
  std::string file;  ///< the CSV it was read from (reports)
  std::vector<TargetPoint> points;
  /// Empty when valid, else "NAME.field: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

/// One model curve per target: abscissae and the predicted quantities along them.
struct PredictedCurve {
  bool ok = true;
  std::string message;                ///< why not, when !ok
  std::vector<double> abscissa;       ///< q (backbone), f [Hz] (frf), mode numbers (modal)
  std::vector<double> frequency_hz;   ///< backbone, modal
  std::vector<double> damping_ratio;  ///< backbone, modal
  std::vector<double> amplitude;      ///< frf
  /// Optional: the predicted value at each target point, in the target's order (overrides the
  /// interpolation when its size equals the number of points).
  std::vector<double> at_points;
};

struct ModelPrediction {
  std::vector<PredictedCurve> curves;  ///< one per target, same order
  bool ok = true;
  std::string message;
};

struct ResidualEvaluation {
  bool ok = true;
  std::string message;
  std::vector<double> predicted;  ///< per target point, in order over the targets
  std::vector<double> residuals;  ///< r_i, same order
};

/// Residuals of `prediction` against all target points, in order (targets, then points).
ResidualEvaluation residuals(const std::vector<Target>& targets, const ModelPrediction& prediction);

/// Linear interpolation of y(x) at `at` over the segments of the polyline (x_k, y_k) that
/// contain it (x in log10 when `log_x`); with several (a fold), the largest y when `largest`,
/// else the first. nullopt-like: returns false when no segment contains `at`.
bool interpolate(const std::vector<double>& x, const std::vector<double>& y, double at, bool log_x,
                 bool largest, double& value);

/// Total number of target points.
std::size_t point_count(const std::vector<Target>& targets);

}  // namespace jointhb::fit
