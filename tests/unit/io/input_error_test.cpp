#include "jointhb/io/input_error.hpp"

#include <gtest/gtest.h>

namespace jointhb::io {
namespace {

TEST(io_InputError, MessageIsFileLineColumnKeyConstraint) {
  const InputError e("case.yaml", 4, 5, "analysis.loop_sweep.mu", "must be > 0, got -1");
  EXPECT_STREQ(e.what(), "case.yaml:4:5: key 'analysis.loop_sweep.mu': must be > 0, got -1");
  EXPECT_EQ(e.file(), "case.yaml");
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.column(), 5);
  EXPECT_EQ(e.key(), "analysis.loop_sweep.mu");
  EXPECT_EQ(e.constraint(), "must be > 0, got -1");
}

TEST(io_InputError, CommandLineOptionsHaveNoPosition) {
  const InputError e(command_line, 0, 0, "--mu", "must be > 0, got -1");
  EXPECT_STREQ(e.what(), "command line: key '--mu': must be > 0, got -1");
  EXPECT_EQ(e.column(), 0);
}

TEST(io_InputError, SyntaxErrorsHaveNoKey) {
  const InputError e("case.yaml", 2, 1, "", "invalid YAML: end of map not found");
  EXPECT_STREQ(e.what(), "case.yaml:2:1: invalid YAML: end of map not found");
}

TEST(io_InputError, MessageStaysOnOneLine) {
  const InputError e("a\nb.yaml", 1, 1, "k", "first\nsecond");
  EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
}

}  // namespace
}  // namespace jointhb::io
