#include "run_support.hpp"

#include <fmt/format.h>

#include <fstream>
#include <stdexcept>
#include <system_error>

#include "cli_support.hpp"

namespace jointhb::cli {

namespace fs = std::filesystem;

void write_summary(const fs::path& path, const nlohmann::ordered_json& summary) {
  std::ofstream out(path, std::ios::out | std::ios::trunc);
  out << summary.dump(2) << '\n';
  out.flush();
  if (!out) throw std::runtime_error(fmt::format("cannot write '{}'", path.string()));
}

void create_output_directory(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    require_option("-o",
                   fmt::format("cannot create directory '{}': {}", dir.string(), ec.message()));
  }
  if (!fs::is_directory(dir, ec)) {
    require_option("-o", fmt::format("'{}' exists and is not a directory", dir.string()));
  }
}

}  // namespace jointhb::cli
