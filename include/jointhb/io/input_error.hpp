#pragma once
// Errors in user input (case files, command-line options). The message is one line:
//   FILE:LINE:COLUMN: key 'KEY': CONSTRAINT
// so that an editor can jump to it. Thrown by the io layer, caught by the CLI (exit code 2).
//
// Where a position does not exist the message leaves it out rather than inventing one:
//   line <= 0   ->  FILE: key 'KEY': CONSTRAINT      (command-line options, unreadable files)
//   empty key   ->  FILE:LINE:COLUMN: CONSTRAINT     (YAML syntax errors, which belong to no key)
// Line and column are 1-based (yaml-cpp marks are 0-based: add one before constructing).

#include <stdexcept>
#include <string>
#include <string_view>

namespace jointhb::io {

/// `text` made safe to print as one line of a terminal or log: line breaks and tabs become
/// blanks; other control bytes (C0, DEL, the C1 range, U+2028/U+2029) and bytes that are not
/// UTF-8 become \xNN escapes (text echoed from a binary file must neither break the line nor
/// drive the terminal). Valid UTF-8 (file names, the messages' own symbols) is kept.
std::string printable_one_line(std::string_view text);

/// The FILE part of errors about command-line options.
inline constexpr const char* command_line = "command line";

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, int column, std::string key, std::string constraint);
  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] int line() const { return line_; }
  [[nodiscard]] int column() const { return column_; }
  [[nodiscard]] const std::string& key() const { return key_; }
  [[nodiscard]] const std::string& constraint() const { return constraint_; }

 private:
  std::string file_;
  int line_;
  int column_;
  std::string key_;
  std::string constraint_;
};

}  // namespace jointhb::io
