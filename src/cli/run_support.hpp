#pragma once
// What the analyses of `jointhb run` share: the output directory, summary.json, timing.

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>

namespace jointhb::cli {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Creates DIR (and parents); io::InputError naming -o when impossible.
void create_output_directory(const std::filesystem::path& dir);

/// Writes summary.json (2-space indent); std::runtime_error naming the path when it fails.
void write_summary(const std::filesystem::path& path, const nlohmann::ordered_json& summary);

}  // namespace jointhb::cli
