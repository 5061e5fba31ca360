#pragma once
// Errors in a mesh file (Abaqus/CalculiX .inp, Gmsh .msh). The message is one line,
//   FILE:LINE: PROBLEM
// (or FILE: PROBLEM when no line applies, e.g. an unreadable file), so that an editor can jump to
// it. The fe layer sits below io and cannot use io::InputError; the CLI reports both alike.

#include <stdexcept>
#include <string>

namespace jointhb::fe {

class MeshFileError : public std::runtime_error {
 public:
  /// `line` is 1-based; line <= 0 leaves the position out.
  MeshFileError(std::string file, int line, std::string problem);
  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] int line() const { return line_; }
  [[nodiscard]] const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  int line_;
  std::string problem_;
};

}  // namespace jointhb::fe
