// Parameter studies: outputs, one sample's evaluation, statistics, the sample record
// (study/study.hpp).
#include "jointhb/study/study.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "../support/stopwatch.hpp"

namespace jointhb::study {
namespace {

using Json = nlohmann::json;

const char* quantity_name(fit::Quantity q) { return fit::to_string(q); }

// The first non-empty reason among a sample's curves.
std::string first_reason(const fit::ModelPrediction& p) {
  if (!p.ok && !p.message.empty()) return p.message;
  for (const auto& c : p.curves) {
    if (!c.message.empty()) return c.message;
  }
  return "";
}

std::optional<Termination> termination_named(const std::string& name) {
  for (Termination t : {Termination::converged, Termination::reached_end, Termination::stopped_by_user,
                        Termination::no_convergence, Termination::failed}) {
    if (name == to_string(t)) return t;
  }
  return std::nullopt;
}

Json number_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }
double number_or_nan(const Json& j) { return j.is_null() ? std::nan("") : j.get<double>(); }

Json array_of(const std::vector<double>& v) {
  Json a = Json::array();
  for (double x : v) a.push_back(number_or_null(x));
  return a;
}
std::vector<double> doubles_of(const Json& a) {
  std::vector<double> v;
  for (const auto& x : a) v.push_back(number_or_nan(x));
  return v;
}

}  // namespace

std::string StudySpec::validate() const {
  if (std::string e = sampling.validate(); !e.empty()) return e;
  if (outputs.modes.empty() && outputs.levels.empty())
    return "outputs: the case has neither damping curves (analysis.nonlinear_modes) nor FRFs (analysis.frf) to report";
  if (!outputs.modes.empty() && outputs.amplitudes.empty()) return "outputs.amplitudes: must hold at least one amplitude";
  for (double q : outputs.amplitudes) {
    if (!(q > 0.0) || !std::isfinite(q)) return fmt::format("outputs.amplitudes: must be finite and > 0, got {}", q);
  }
  for (double f : outputs.frequencies_hz) {
    if (!(f > 0.0) || !std::isfinite(f)) return fmt::format("outputs.frequencies_hz: must be finite and > 0, got {}", f);
  }
  for (std::size_t i = 0; i < quantiles.size(); ++i) {
    if (!(quantiles[i] >= 0.0 && quantiles[i] <= 1.0)) return fmt::format("quantiles: must lie in [0, 1], got {}", quantiles[i]);
    if (i > 0 && !(quantiles[i] > quantiles[i - 1])) return "quantiles: must be ascending without repeats";
  }
  return "";
}

std::string OutputKey::label() const {
  const std::string curve_name = fmt::format("{} {}", curve == fit::TargetKind::backbone ? "mode" : "level", index);
  if (quantity.rfind("peak_", 0) == 0) return curve_name + " " + quantity;
  return fmt::format("{} {} at {} = {:.6g}", curve_name, quantity, curve == fit::TargetKind::backbone ? "q" : "f [Hz]",
                     abscissa);
}

std::vector<OutputKey> output_keys(const StudyOutputs& outputs) {
  std::vector<OutputKey> keys;
  for (int mode : outputs.modes) {
    for (double q : outputs.amplitudes) {
      keys.push_back({fit::TargetKind::backbone, mode, quantity_name(fit::Quantity::frequency_hz), q});
      keys.push_back({fit::TargetKind::backbone, mode, quantity_name(fit::Quantity::damping_ratio), q});
    }
  }
  for (int level : outputs.levels) {
    for (double f : outputs.frequencies_hz) keys.push_back({fit::TargetKind::frf, level, quantity_name(fit::Quantity::amplitude), f});
    keys.push_back({fit::TargetKind::frf, level, "peak_amplitude", 0.0});
    keys.push_back({fit::TargetKind::frf, level, "peak_frequency_hz", 0.0});
  }
  return keys;
}

std::vector<fit::Target> study_targets(const StudyOutputs& outputs) {
  std::vector<fit::Target> targets;
  for (int mode : outputs.modes) {
    fit::Target t;
    t.name = fmt::format("mode {}", mode);
    t.kind = fit::TargetKind::backbone;
    t.mode = mode;
    for (double q : outputs.amplitudes) {
      // The measured value is a placeholder: a study reads predictions, not residuals.
      t.points.push_back({q, fit::Quantity::frequency_hz, 1.0, 1.0, 0.0, 0});
      t.points.push_back({q, fit::Quantity::damping_ratio, 1.0, 1.0, 0.0, 0});
    }
    targets.push_back(std::move(t));
  }
  for (int level : outputs.levels) {
    fit::Target t;
    t.name = fmt::format("level {}", level);
    t.kind = fit::TargetKind::frf;
    t.level = level;
    for (double f : outputs.frequencies_hz) t.points.push_back({f, fit::Quantity::amplitude, 1.0, 1.0, 0.0, 0});
    targets.push_back(std::move(t));
  }
  return targets;
}

SampleResult evaluate_sample(const SampleModel& model, const StudyOutputs& outputs, std::size_t sample,
                             const std::vector<double>& values) {
  const auto start = support::Clock::now();
  SampleResult r;
  r.sample = sample;
  r.values = values;
  const std::vector<fit::Target> targets = study_targets(outputs);
  const std::size_t n_keys = output_keys(outputs).size();
  fit::ModelPrediction p;
  try {
    p = model(values);
  } catch (const std::exception& e) {
    p.ok = false;
    p.message = e.what();
  }
  std::string missing;  // the first output not reached
  for (std::size_t t = 0; t < targets.size(); ++t) {
    const fit::Target& target = targets[t];
    fit::PredictedCurve curve;
    if (t < p.curves.size()) {
      curve = p.curves[t];
    } else {  // the model failed before this curve
      curve.ok = false;
      curve.message = p.message;
    }
    const bool corrected = curve.ok && curve.at_points.size() == target.points.size();
    const bool backbone = target.kind == fit::TargetKind::backbone;
    for (std::size_t i = 0; i < target.points.size(); ++i) {
      const fit::TargetPoint& point = target.points[i];
      std::optional<double> value;
      if (corrected) {
        value = curve.at_points[i];
      } else {
        const auto& y = point.quantity == fit::Quantity::frequency_hz    ? curve.frequency_hz
                        : point.quantity == fit::Quantity::damping_ratio ? curve.damping_ratio
                                                                         : curve.amplitude;
        double v = 0.0;
        if (y.size() == curve.abscissa.size() && fit::interpolate(curve.abscissa, y, point.abscissa, backbone, !backbone, v))
          value = v;
      }
      if (value && !std::isfinite(*value)) value.reset();
      if (!value && missing.empty())
        missing = fmt::format("{}: {} at {:.6g} not reached", target.name, quantity_name(point.quantity), point.abscissa);
      r.outputs.push_back(value);
    }
    if (!backbone) {  // the peak of the whole curve
      std::optional<double> peak, at;
      for (std::size_t k = 0; k < curve.amplitude.size() && k < curve.abscissa.size(); ++k) {
        if (std::isfinite(curve.amplitude[k]) && (!peak || curve.amplitude[k] > *peak)) {
          peak = curve.amplitude[k];
          at = curve.abscissa[k];
        }
      }
      if (!peak && missing.empty()) missing = target.name + ": no FRF point";
      r.outputs.push_back(peak);
      r.outputs.push_back(at);
    }
    r.curves.push_back(curve);
  }
  r.outputs.resize(n_keys);
  const std::string reason = first_reason(p);
  if (p.ok && missing.empty()) {
    r.status = {Termination::converged, ""};
  } else {
    r.status = {Termination::failed, missing.empty() ? reason : (reason.empty() ? missing : missing + " (" + reason + ")")};
  }
  r.seconds = support::seconds_since(start);
  return r;
}

double quantile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) throw std::invalid_argument("quantile of no values");
  const double h = static_cast<double>(sorted.size() - 1) * p;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted.back();
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[lo + 1] - sorted[lo]);
}

std::vector<OutputStatistics> output_statistics(const std::vector<OutputKey>& keys, const std::vector<SampleResult>& samples,
                                                const std::vector<double>& quantiles) {
  std::vector<OutputStatistics> out;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    OutputStatistics s;
    s.key = keys[k];
    std::vector<double> v;
    for (const auto& sample : samples) {
      if (k < sample.outputs.size() && sample.outputs[k]) v.push_back(*sample.outputs[k]);
    }
    s.count = v.size();
    if (!v.empty()) {
      // Sums in sample order (the table's order), then the order statistics: the same numbers
      // whatever order the samples finished in.
      double sum = 0.0;
      for (double x : v) sum += x;
      s.mean = sum / static_cast<double>(v.size());
      double squares = 0.0;
      for (double x : v) squares += (x - s.mean) * (x - s.mean);
      s.std_dev = v.size() > 1 ? std::sqrt(squares / static_cast<double>(v.size() - 1)) : 0.0;
      std::sort(v.begin(), v.end());
      s.min = v.front();
      s.max = v.back();
      for (double p : quantiles) s.quantiles.push_back(quantile(v, p));
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::string sample_to_json(const SampleResult& s, const std::string& identity) {
  Json j;
  j["identity"] = identity;
  j["sample"] = s.sample;
  j["values"] = array_of(s.values);
  j["termination"] = std::string(to_string(s.status.termination));
  j["message"] = s.status.message;
  j["seconds"] = s.seconds;
  Json outputs = Json::array();
  for (const auto& v : s.outputs) outputs.push_back(v ? number_or_null(*v) : Json(nullptr));
  j["outputs"] = outputs;
  Json curves = Json::array();
  for (const auto& c : s.curves) {
    curves.push_back({{"ok", c.ok},
                      {"message", c.message},
                      {"abscissa", array_of(c.abscissa)},
                      {"frequency_hz", array_of(c.frequency_hz)},
                      {"damping_ratio", array_of(c.damping_ratio)},
                      {"amplitude", array_of(c.amplitude)},
                      {"at_points", array_of(c.at_points)}});
  }
  j["curves"] = curves;
  // nlohmann writes the shortest text that reads back to the same double (grisu2 with a round-trip
  // check), so a sample read back is bit-identical to the one computed.
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

SampleResult sample_from_json(const std::string& text, std::string& identity) {
  try {
    const Json j = Json::parse(text);
    SampleResult s;
    identity = j.at("identity").get<std::string>();
    s.sample = j.at("sample").get<std::size_t>();
    s.values = doubles_of(j.at("values"));
    const auto termination = termination_named(j.at("termination").get<std::string>());
    if (!termination) throw std::runtime_error("unknown termination");
    s.status = {*termination, j.at("message").get<std::string>()};
    s.seconds = j.at("seconds").get<double>();
    for (const auto& v : j.at("outputs")) s.outputs.push_back(v.is_null() ? std::nullopt : std::optional<double>(v.get<double>()));
    for (const auto& c : j.at("curves")) {
      fit::PredictedCurve pc;
      pc.ok = c.at("ok").get<bool>();
      pc.message = c.at("message").get<std::string>();
      pc.abscissa = doubles_of(c.at("abscissa"));
      pc.frequency_hz = doubles_of(c.at("frequency_hz"));
      pc.damping_ratio = doubles_of(c.at("damping_ratio"));
      pc.amplitude = doubles_of(c.at("amplitude"));
      pc.at_points = doubles_of(c.at("at_points"));
      s.curves.push_back(std::move(pc));
    }
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("not a sample record: ") + e.what());
  }
}

Status StudyResult::status() const {
  const std::size_t total = samples.size();
  if (not_run > 0) return {Termination::stopped_by_user, fmt::format("stopped with {} of {} samples not run", not_run, total)};
  if (failed == 0) return {Termination::converged, fmt::format("{} samples", total)};
  if (failed < total) return {Termination::no_convergence, fmt::format("{} of {} samples failed", failed, total)};
  return {Termination::failed, fmt::format("all {} samples failed", total)};
}

}  // namespace jointhb::study
