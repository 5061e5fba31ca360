#pragma once
// A file in the system temp directory, unique to this process and test, removed afterwards.

#include <gtest/gtest.h>

#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/input_error.hpp"

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace jointhb::io::testing {

class TempFile {
 public:
  explicit TempFile(const std::string& suffix) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("jointhb-" + std::to_string(::getpid()) + "-" + info->test_suite_name() + "-" +
             info->name() + suffix);
  }
  TempFile(const std::string& suffix, const std::string& contents) : TempFile(suffix) {
    std::ofstream(path_) << contents;
  }
  ~TempFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] std::string contents() const {
    std::ifstream in(path_);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

 private:
  std::filesystem::path path_;
};

// A directory in the system temp directory, unique to this process and test, removed afterwards,
// in which a case file (and the files it names) is written and read.
class CaseDir {
 public:
  CaseDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = std::filesystem::temp_directory_path() /
          ("jointhb-" + std::to_string(::getpid()) + "-" + info->test_suite_name() + "-" + info->name());
    std::filesystem::create_directories(dir);
  }
  ~CaseDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
  CaseDir(const CaseDir&) = delete;
  CaseDir& operator=(const CaseDir&) = delete;

  void write(const std::string& name, const std::string& text) const { std::ofstream(dir / name) << text; }
  [[nodiscard]] FeCase read(const std::string& yaml) const {
    write("case.yaml", yaml);
    return read_fe_case(dir / "case.yaml");
  }
  // The one-line message of the InputError that reading `yaml` throws ("no error" if none).
  [[nodiscard]] std::string error(const std::string& yaml) const {
    try {
      (void)read(yaml);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }

  std::filesystem::path dir;
};

}  // namespace jointhb::io::testing
