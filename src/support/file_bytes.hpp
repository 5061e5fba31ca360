#pragma once
// A whole file as bytes (the stage keys hash imported files; the stage cache reads its files).

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

namespace jointhb::support {

/// The whole file; nullopt when it cannot be opened or read.
inline std::optional<std::string> file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) return std::nullopt;
  const std::streamoff size = in.tellg();
  if (size < 0) return std::nullopt;
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), size)) return std::nullopt;
  return bytes;
}

}  // namespace jointhb::support
