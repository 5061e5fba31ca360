#include "jointhb/fit/targets.hpp"

#include <fmt/format.h>

#include <cmath>

namespace jointhb::fit {

const char* to_string(TargetKind kind) {
  switch (kind) {
    case TargetKind::backbone:
      return "backbone";
    case TargetKind::frf:
      return "frf";
    case TargetKind::modal:
      return "modal";
  }
  return "?";
}

const char* to_string(Quantity quantity) {
  switch (quantity) {
    case Quantity::frequency_hz:
      return "frequency_hz";
    case Quantity::damping_ratio:
      return "damping_ratio";
    case Quantity::amplitude:
      return "amplitude";
  }
  return "?";
}

double TargetPoint::scale() const { return sigma > 0.0 ? sigma : std::abs(measured); }

std::string Target::validate() const {
  if (points.empty()) return fmt::format("{}: has no points", name);
  if (kind == TargetKind::backbone && mode < 1) {
    return fmt::format("{}.mode: must be >= 1, got {}", name, mode);
  }
  if (kind == TargetKind::frf && level < 0) {
    return fmt::format("{}.level: must be >= 0, got {}", name, level);
  }
  for (const auto& p : points) {
    const std::string where = p.line > 0 ? fmt::format("{}:{}", file, p.line) : name;
    if (!std::isfinite(p.abscissa) || !std::isfinite(p.measured)) {
      return fmt::format("{}: values must be finite", where);
    }
    if (!(p.weight >= 0.0) || !std::isfinite(p.weight)) {
      return fmt::format("{}: weight must be >= 0, got {}", where, p.weight);
    }
    if (!(p.sigma >= 0.0) || !std::isfinite(p.sigma)) {
      return fmt::format("{}: sigma must be >= 0, got {}", where, p.sigma);
    }
    if (p.scale() == 0.0) {
      return fmt::format("{}: a relative residual needs a measured {} != 0 (or give sigma)", where,
                         to_string(p.quantity));
    }
    if (kind == TargetKind::backbone && !(p.abscissa > 0.0)) {
      return fmt::format("{}: amplitude must be > 0, got {}", where, p.abscissa);
    }
  }
  return "";
}

std::size_t point_count(const std::vector<Target>& targets) {
  std::size_t m = 0;
  for (const auto& t : targets) m += t.points.size();
  return m;
}

bool interpolate(const std::vector<double>& x, const std::vector<double>& y, double at, bool log_x,
                 bool largest, double& value) {
  const auto tr = [&](double v) { return log_x ? std::log10(v) : v; };
  if (log_x && !(at > 0.0)) return false;
  const double a = tr(at);
  bool found = false;
  for (std::size_t k = 0; k + 1 < x.size() && k + 1 < y.size(); ++k) {
    if (log_x && (!(x[k] > 0.0) || !(x[k + 1] > 0.0))) continue;
    const double x0 = tr(x[k]);
    const double x1 = tr(x[k + 1]);
    const double lo = std::min(x0, x1);
    const double hi = std::max(x0, x1);
    if (a < lo || a > hi) continue;
    const double t = hi > lo ? (a - x0) / (x1 - x0) : 0.0;
    const double v = y[k] + t * (y[k + 1] - y[k]);
    if (!found || (largest && v > value)) value = v;
    found = true;
    if (!largest) break;
  }
  return found;
}

ResidualEvaluation residuals(const std::vector<Target>& targets,
                             const ModelPrediction& prediction) {
  ResidualEvaluation out;
  const auto fail = [&](std::string message) {
    out.ok = false;
    out.message = std::move(message);
    return out;
  };
  if (!prediction.ok) return fail(prediction.message);
  if (prediction.curves.size() != targets.size()) {
    return fail(fmt::format("the model predicted {} curves for {} targets",
                            prediction.curves.size(), targets.size()));
  }
  for (std::size_t t = 0; t < targets.size(); ++t) {
    const Target& target = targets[t];
    const PredictedCurve& curve = prediction.curves[t];
    if (!curve.ok) return fail(fmt::format("{}: {}", target.name, curve.message));
    const bool direct = curve.at_points.size() == target.points.size();
    for (std::size_t i = 0; i < target.points.size(); ++i) {
      const TargetPoint& p = target.points[i];
      double predicted = 0.0;
      if (direct) {
        predicted = curve.at_points[i];
      } else {
        const std::vector<double>& y = p.quantity == Quantity::frequency_hz    ? curve.frequency_hz
                                       : p.quantity == Quantity::damping_ratio ? curve.damping_ratio
                                                                               : curve.amplitude;
        bool ok = false;
        if (target.kind == TargetKind::modal) {
          for (std::size_t k = 0; k < curve.abscissa.size() && k < y.size(); ++k) {
            if (curve.abscissa[k] == p.abscissa) {
              predicted = y[k];
              ok = true;
            }
          }
        } else {
          ok = interpolate(curve.abscissa, y, p.abscissa, target.kind == TargetKind::backbone,
                           target.kind == TargetKind::frf, predicted);
        }
        if (!ok) {
          return fail(fmt::format("{}: measured {} {} lies outside the predicted curve",
                                  target.name,
                                  target.kind == TargetKind::backbone ? "amplitude"
                                  : target.kind == TargetKind::frf    ? "frequency"
                                                                      : "mode",
                                  p.abscissa));
        }
      }
      if (!std::isfinite(predicted)) {
        return fail(fmt::format("{}: the prediction is not finite", target.name));
      }
      out.predicted.push_back(predicted);
      out.residuals.push_back(p.weight * (predicted - p.measured) / p.scale());
    }
  }
  return out;
}

}  // namespace jointhb::fit
