#pragma once
// The files of a parameter study (docs/studies.md §4), written by `jointhb study` and by the Python
// `jointhb.run_study` alike:
//   study.csv             one row per sample: its parameter values, every output (empty where the
//                         sample did not reach it) and its termination — the result table, the
//                         same bit for bit for any thread or rank count (no timings in it)
//   study_statistics.csv  per output: count, mean, standard deviation, min, max, the quantiles
//   study_curves.csv      every sample's whole curves (damping curves: q, f, ζ; FRFs: f, |x̂₁|)
//   study.json            the design, counts, status, failed samples with their reasons,
//                         statistics, timings, warnings

#include <filesystem>
#include <string>
#include <vector>

#include "jointhb/study/study.hpp"

namespace jointhb::io {

/// The column name of an output in study.csv: "mode1_frequency_hz_q1e-06",
/// "level0_amplitude_f12.5", "level0_peak_amplitude".
[[nodiscard]] std::string study_column(const study::OutputKey& key);

/// Writes the four files into `dir` (which exists). `case_file` names the case in study.json.
/// Throws std::runtime_error naming a file that cannot be written.
void write_study_outputs(const std::filesystem::path& dir, const std::string& case_file, const study::StudySpec& spec,
                         const study::StudyResult& result);

}  // namespace jointhb::io
