#pragma once
// Text helpers shared by the mesh-file readers (private to the fe layer).

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace jointhb::fe::detail {

/// `text` without leading and trailing blanks (spaces, tabs, CR).
[[nodiscard]] std::string_view trim(std::string_view text);
/// ASCII upper case.
[[nodiscard]] std::string upper(std::string_view text);
/// The whole of `text` (trimmed, optional leading '+') as an integer, or nothing.
[[nodiscard]] std::optional<long> to_integer(std::string_view text);
/// The whole of `text` as a finite number; Fortran exponents (1.5D3) are accepted.
[[nodiscard]] std::optional<double> to_number(std::string_view text);
/// The lines of `text`, without their line breaks ("\n" or "\r\n").
[[nodiscard]] std::vector<std::string_view> split_lines(std::string_view text);
/// `text` split at `separator`, each piece trimmed.
[[nodiscard]] std::vector<std::string_view> split(std::string_view text, char separator);
/// `text` split at blanks, empty pieces dropped.
[[nodiscard]] std::vector<std::string_view> split_blanks(std::string_view text);
/// The contents of `file`; throws MeshFileError (no line) when it cannot be read.
[[nodiscard]] std::string read_file(const std::filesystem::path& file);

}  // namespace jointhb::fe::detail
