#pragma once
// The study of a case file (docs/studies.md): what `jointhb study` and the Python
// `jointhb.run_study` share — the case read and its study section, the models of its samples,
// the run, and the files written.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "jointhb/study/study.hpp"

namespace jointhb::io {

struct StudyCase {
  std::filesystem::path file;
  study::StudySpec spec;
  /// What a restart's sample records must match: a hash of the case file's bytes.
  std::string identity;
  /// The sample models; a finite-element case keeps its stages in `cache_dir` (shared by the
  /// workers), none when it is empty.
  std::function<study::SampleModelFactory(const std::filesystem::path& cache_dir)> models;
};

/// Reads `file`. Throws io::InputError for a bad case file, std::invalid_argument naming the file
/// when it is neither a discrete nor a finite-element case or has no study section.
[[nodiscard]] StudyCase read_study_case(const std::filesystem::path& file);

/// Runs the study with `options` (its sample_directory and identity are set here: DIR/samples and
/// the case's identity) and, on rank 0, writes the files into `dir` (io/study_outputs.hpp).
/// `cache_dir` empty: DIR/.cache.
study::StudyResult run_study_case(const StudyCase& c, const std::filesystem::path& dir, study::RunOptions options,
                                  const std::filesystem::path& cache_dir = {});

}  // namespace jointhb::io
