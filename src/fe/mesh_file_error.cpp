#include "jointhb/fe/mesh_file_error.hpp"

#include <algorithm>
#include <utility>

namespace jointhb::fe {
namespace {

std::string format_message(const std::string& file, int line, const std::string& problem) {
  std::string message = file;
  if (line > 0) message += ':' + std::to_string(line);
  message += ": " + problem;
  // One line whatever the file name or the offending text contains (editors and the CLI rely on
  // it).
  std::replace_if(
      message.begin(), message.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return message;
}

}  // namespace

MeshFileError::MeshFileError(std::string file, int line, std::string problem)
    : std::runtime_error(format_message(file, line, problem)),
      file_(std::move(file)),
      line_(line > 0 ? line : 0),
      problem_(std::move(problem)) {}

}  // namespace jointhb::fe
