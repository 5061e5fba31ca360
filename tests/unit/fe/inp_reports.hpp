#pragma once
// Shared by the .inp reader tests: reading `text` as an .inp file fails with a MeshFileError whose
// message starts with "<file>:<line>: " and contains `part`.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <string>

#include "jointhb/fe/inp_reader.hpp"
#include "jointhb/fe/mesh_file_error.hpp"
#include "unit/io/temp_file.hpp"

namespace jointhb::fe::testing {

inline ::testing::AssertionResult inp_reports(const std::string& text, int line, const std::string& part,
                                              const InpOptions& options = {}) {
  const io::testing::TempFile file(".inp", text);
  std::string message;
  try {
    (void)read_inp(file.path(), options);
    return ::testing::AssertionFailure() << "no exception";
  } catch (const MeshFileError& e) {
    message = e.what();
  }
  const std::string position = fmt::format("{}:{}: ", file.path().string(), line);
  if (message.rfind(position, 0) != 0 || message.find(part) == std::string::npos)
    return ::testing::AssertionFailure() << "got: " << message;
  return ::testing::AssertionSuccess();
}

}  // namespace jointhb::fe::testing
