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

TEST(io_InputError, ControlBytesAreEscapedAndUtf8IsKept) {
  // Issue 20, item 6: a binary target CSV echoed its control bytes (vertical tab, form feed,
  // escape sequences, NEL, U+2028) and so broke the message over lines and drove the terminal.
  const std::string binary = std::string("a\x0b" "b\x0c" "c\x1b[31m\x7f") + "\xc2\x85" + "\xe2\x80\xa8" +
                             std::string(1, '\0') + "\xff\xc3";
  const InputError e("t.csv", 1, 1, "fit.targets[0].file", "got '" + binary + "'");
  EXPECT_STREQ(e.what(),
               "t.csv:1:1: key 'fit.targets[0].file': got "
               "'a\\x0Bb\\x0Cc\\x1B[31m\\x7F\\xC2\\x85\\xE2\\x80\\xA8\\x00\\xFF\\xC3'");
  // Tabs and line breaks become blanks; valid UTF-8 (symbols of the messages, file names) stays.
  EXPECT_EQ(printable_one_line("σ = 1\tμm → «ok»\r\n"), "σ = 1 μm → «ok»  ");
}

}  // namespace
}  // namespace jointhb::io
