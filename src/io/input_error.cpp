#include "jointhb/io/input_error.hpp"

#include <algorithm>
#include <utility>

namespace jointhb::io {
namespace {

// The message must stay on one line (editors and the CLI tests rely on it), whatever the
// file name or a third-party error text contains.
std::string one_line(std::string text) {
  std::replace_if(
      text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return text;
}

std::string format_message(const std::string& file, int line, int column, const std::string& key,
                           const std::string& constraint) {
  std::string message = file;
  if (line > 0) {
    message += ':' + std::to_string(line) + ':' + std::to_string(std::max(column, 1));
  }
  message += ": ";
  if (!key.empty()) message += "key '" + key + "': ";
  message += constraint;
  return one_line(std::move(message));
}

}  // namespace

InputError::InputError(std::string file, int line, int column, std::string key,
                       std::string constraint)
    : std::runtime_error(format_message(file, line, column, key, constraint)),
      file_(std::move(file)),
      line_(line),
      column_(line > 0 ? std::max(column, 1) : 0),
      key_(std::move(key)),
      constraint_(std::move(constraint)) {}

}  // namespace jointhb::io
