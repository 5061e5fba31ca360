// The files of a parameter study (io/study_outputs.hpp).
#include "jointhb/io/study_outputs.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "jointhb/io/csv_writer.hpp"

namespace jointhb::io {
namespace {

using Json = nlohmann::ordered_json;

std::string curve_word(fit::TargetKind kind) { return kind == fit::TargetKind::backbone ? "backbone" : "frf"; }

Json number_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

void write_table(const std::filesystem::path& dir, const study::StudySpec& spec, const study::StudyResult& r) {
  std::vector<std::string> columns = {"sample"};
  for (const auto& p : spec.sampling.parameters) columns.push_back(p.name);
  for (const auto& k : r.keys) columns.push_back(study_column(k));
  columns.push_back("termination");
  CsvWriter csv(dir / "study.csv", columns);
  for (std::size_t i = 0; i < r.samples.size(); ++i) {
    const study::SampleResult& s = r.samples[i];
    std::vector<std::optional<double>> row = {static_cast<double>(i)};
    for (double v : s.values) row.emplace_back(v);
    for (std::size_t k = 0; k < r.keys.size(); ++k) row.push_back(k < s.outputs.size() ? s.outputs[k] : std::nullopt);
    const std::vector<std::string> label = {std::string(to_string(s.status.termination))};
    csv.write_row(row, label);
  }
}

void write_statistics(const std::filesystem::path& dir, const study::StudySpec& spec, const study::StudyResult& r) {
  std::vector<std::string> columns = {"mode_or_level", "abscissa", "count", "mean", "std_dev", "min", "max"};
  for (double p : spec.quantiles) columns.push_back(fmt::format("q{:g}", p));
  columns.push_back("curve");
  columns.push_back("quantity");
  CsvWriter csv(dir / "study_statistics.csv", columns);
  for (const auto& s : r.statistics) {
    std::vector<std::optional<double>> row = {static_cast<double>(s.key.index), s.key.abscissa, static_cast<double>(s.count)};
    const bool any = s.count > 0;
    for (double v : {s.mean, s.std_dev, s.min, s.max}) row.push_back(any ? std::optional<double>(v) : std::nullopt);
    for (std::size_t q = 0; q < spec.quantiles.size(); ++q)
      row.push_back(any && q < s.quantiles.size() ? std::optional<double>(s.quantiles[q]) : std::nullopt);
    const std::vector<std::string> labels = {curve_word(s.key.curve), s.key.quantity};
    csv.write_row(row, labels);
  }
}

void write_curves(const std::filesystem::path& dir, const study::StudyResult& r) {
  CsvWriter csv(dir / "study_curves.csv", {"sample", "mode_or_level", "abscissa", "frequency_hz", "damping_ratio", "amplitude", "curve"});
  // A sample's curves follow the targets' order: the modes, then the levels (study_targets).
  std::vector<std::pair<fit::TargetKind, int>> curves;
  for (const auto& k : r.keys) {
    const std::pair<fit::TargetKind, int> c(k.curve, k.index);
    if (curves.empty() || curves.back() != c) curves.push_back(c);
  }
  for (std::size_t i = 0; i < r.samples.size(); ++i) {
    const study::SampleResult& s = r.samples[i];
    if (!r.done[i]) continue;
    for (std::size_t c = 0; c < s.curves.size() && c < curves.size(); ++c) {
      const fit::PredictedCurve& pc = s.curves[c];
      const bool backbone = curves[c].first == fit::TargetKind::backbone;
      const auto at = [](const std::vector<double>& v, std::size_t k) {
        return k < v.size() && std::isfinite(v[k]) ? std::optional<double>(v[k]) : std::nullopt;
      };
      for (std::size_t k = 0; k < pc.abscissa.size(); ++k) {
        if (!std::isfinite(pc.abscissa[k])) continue;
        std::vector<std::optional<double>> row = {static_cast<double>(i), static_cast<double>(curves[c].second), pc.abscissa[k]};
        row.push_back(backbone ? at(pc.frequency_hz, k) : at(pc.abscissa, k));
        row.push_back(backbone ? at(pc.damping_ratio, k) : std::nullopt);
        row.push_back(backbone ? std::nullopt : at(pc.amplitude, k));
        const std::vector<std::string> label = {curve_word(curves[c].first)};
        csv.write_row(row, label);
      }
    }
  }
}

Json summary(const std::string& case_file, const study::StudySpec& spec, const study::StudyResult& r) {
  Json j;
  const Status st = r.status();
  j["status"] = std::string(to_string(st.termination));
  j["message"] = st.message;
  j["case"] = case_file;
  Json design;
  design["sampling"] = study::to_string(spec.sampling.kind);
  design["samples"] = r.samples.size();
  if (spec.sampling.kind == study::SamplingKind::latin_hypercube) design["seed"] = spec.sampling.seed;
  Json params = Json::array();
  for (const auto& p : spec.sampling.parameters) {
    Json q;
    q["name"] = p.name;
    if (!p.values.empty()) {
      q["values"] = p.values;
    } else {
      q["lower"] = p.lower;
      q["upper"] = p.upper;
      q["log_scale"] = p.log_scale;
    }
    params.push_back(q);
  }
  design["parameters"] = params;
  design["friction_in_dynamics_only"] = spec.friction_in_dynamics_only;
  j["design"] = design;
  j["outputs"] = {{"modes", spec.outputs.modes}, {"amplitudes", spec.outputs.amplitudes},
                  {"levels", spec.outputs.levels}, {"frequencies_hz", spec.outputs.frequencies_hz}};
  j["counts"] = {{"computed", r.computed}, {"reused", r.reused}, {"failed", r.failed}, {"not_run", r.not_run}};
  j["ranks"] = r.ranks;
  j["jobs"] = r.jobs;
  j["seconds"] = r.seconds;
  double sample_seconds = 0.0;
  for (const auto& s : r.samples) sample_seconds += s.reused ? 0.0 : s.seconds;
  j["sample_seconds"] = sample_seconds;
  Json failed = Json::array();
  for (std::size_t i = 0; i < r.samples.size(); ++i) {
    if (r.done[i] && !r.samples[i].status.ok()) failed.push_back({{"sample", i}, {"message", r.samples[i].status.message}});
  }
  j["failed_samples"] = failed;
  Json stats = Json::array();
  for (const auto& s : r.statistics) {
    Json q;
    q["output"] = study_column(s.key);
    q["count"] = s.count;
    if (s.count > 0) {
      q["mean"] = number_or_null(s.mean);
      q["std_dev"] = number_or_null(s.std_dev);
      q["min"] = number_or_null(s.min);
      q["max"] = number_or_null(s.max);
      Json qs = Json::object();
      for (std::size_t k = 0; k < spec.quantiles.size() && k < s.quantiles.size(); ++k)
        qs[fmt::format("{:g}", spec.quantiles[k])] = number_or_null(s.quantiles[k]);
      q["quantiles"] = qs;
    }
    stats.push_back(q);
  }
  j["statistics"] = stats;
  j["warnings"] = r.warnings;
  j["files"] = {"study.csv", "study_statistics.csv", "study_curves.csv", "samples/"};
  return j;
}

}  // namespace

std::string study_column(const study::OutputKey& key) {
  const std::string curve = fmt::format("{}{}", key.curve == fit::TargetKind::backbone ? "mode" : "level", key.index);
  if (key.quantity.rfind("peak_", 0) == 0) return curve + "_" + key.quantity;
  return fmt::format("{}_{}_{}{:g}", curve, key.quantity, key.curve == fit::TargetKind::backbone ? "q" : "f", key.abscissa);
}

void write_study_outputs(const std::filesystem::path& dir, const std::string& case_file, const study::StudySpec& spec,
                         const study::StudyResult& result) {
  write_table(dir, spec, result);
  write_statistics(dir, spec, result);
  write_curves(dir, result);
  const std::filesystem::path file = dir / "study.json";
  std::ofstream out(file, std::ios::trunc);
  out << summary(case_file, spec, result).dump(2) << '\n';
  if (!out.flush()) throw std::runtime_error("cannot write to '" + file.string() + "'");
}

}  // namespace jointhb::io
