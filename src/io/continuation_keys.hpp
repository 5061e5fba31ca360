#pragma once
// The `continuation:` mapping of an analysis (docs/case-files.md, "analysis.frf.continuation"),
// shared by the discrete-model and finite-element readers (private to the io layer).

#include <string>

#include "jointhb/continuation/accuracy.hpp"
#include "jointhb/continuation/frf.hpp"
#include "jointhb/continuation/pseudo_arclength.hpp"
#include "yaml_support.hpp"

namespace jointhb::io {

/// Reads initial_step, min_step, max_step, max_points, residual_tolerance into `o` (keys not given
/// keep o's values) and checks min_step ≤ initial_step ≤ max_step, blaming a value the file gives.
void read_continuation_keys(const yaml::Reader& reader, const YAML::Node& node,
                            const std::string& path, continuation::Options& o);

/// Reads the `accuracy:` mapping of a damping curve or, with `frf`, of an FRF (docs/case-files.md;
/// continuation/accuracy.hpp): frequency and damping (damping curves) or amplitude (FRFs), relative
/// in [0, 1), at least one > 0; min_harmonics, max_harmonics, max_time_samples; then checks that the
/// starting level (harmonics, time_samples) lies in the range, blaming the accuracy key.
void read_accuracy_keys(const yaml::Reader& reader, const YAML::Node& node, const std::string& path,
                        int harmonics, int time_samples, bool frf, continuation::Accuracy& a);

/// The value of a `stability:` key (`auto`, `true` or `false`; the key's path in messages).
continuation::Stability read_stability_key(const yaml::Reader& reader, const YAML::Node& value,
                                           const std::string& key);

/// The value of a `stability_method:` key (`monodromy` or `hill`; the key's path in messages).
continuation::StabilityMethod read_stability_method_key(const yaml::Reader& reader,
                                                        const YAML::Node& value, const std::string& key);

}  // namespace jointhb::io
