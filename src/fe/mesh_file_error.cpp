#include "jointhb/fe/mesh_file_error.hpp"

#include <algorithm>
#include <cctype>
#include <string>
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

// A quoted token of the file that reads as NaN ('nan', '.nan', '-NaN', ...) is named in words: no
// jointhb message contains "nan" (issue 20, item 4).
std::string spell_out_nan(std::string problem) {
  std::size_t open = 0;
  while ((open = problem.find('\'', open)) != std::string::npos) {
    const std::size_t close = problem.find('\'', open + 1);
    if (close == std::string::npos) break;
    std::string token = problem.substr(open + 1, close - open - 1);
    token.erase(0, token.find_first_not_of(".+-"));
    std::transform(token.begin(), token.end(), token.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (token == "nan") {
      problem.replace(open, close - open + 1, "not-a-number");
      open += 12;
    } else {
      open = close + 1;
    }
  }
  return problem;
}

}  // namespace

MeshFileError::MeshFileError(std::string file, int line, std::string problem)
    : std::runtime_error(format_message(file, line, spell_out_nan(problem))),
      file_(std::move(file)),
      line_(line > 0 ? line : 0),
      problem_(spell_out_nan(std::move(problem))) {}

}  // namespace jointhb::fe
