#pragma once
// Errors in user input (case files, command-line options). The message is one line:
//   FILE:LINE:COLUMN: key 'KEY': CONSTRAINT
// so that an editor can jump to it. Thrown by the io layer, caught by the CLI (exit code 2).

#include <stdexcept>
#include <string>

namespace jointhb::io {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, int column, std::string key, std::string constraint);
  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] int line() const { return line_; }
  [[nodiscard]] const std::string& key() const { return key_; }
  [[nodiscard]] const std::string& constraint() const { return constraint_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
  std::string constraint_;
};

}  // namespace jointhb::io
