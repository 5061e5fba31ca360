#pragma once
// A CSV file of numbers written row by row: a header row, then rows of doubles at full precision
// (%.17g, so every value reads back bit for bit). Each row is flushed as soon as it is written, so
// a run that is interrupted keeps every row computed so far (docs/cli.md, "FRF outputs").

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace jointhb::io {

class CsvWriter {
 public:
  /// Creates (truncates) the file and writes the header. Throws std::runtime_error naming the path
  /// when it cannot be opened, std::invalid_argument for an empty header or a column name that
  /// would break the format (comma, quote, line break).
  CsvWriter(std::filesystem::path path, std::vector<std::string> columns);

  /// Appends one row and flushes it. Throws std::invalid_argument when the number of values differs
  /// from the header or a value is not finite (no NaN ever reaches an output file), and
  /// std::runtime_error naming the path when the write fails (disk full).
  void write_row(std::span<const double> values);
  void write_row(std::initializer_list<double> values) {
    write_row(std::span<const double>(values.begin(), values.size()));
  }

  /// Appends one row whose last labels.size() columns hold words (e.g. "fold", "none") and the
  /// others numbers. Throws std::invalid_argument as write_row does, and for a label that is empty
  /// or holds a comma, quote, line break or space.
  void write_row(std::span<const double> values, std::span<const std::string> labels);

  /// As above, with an empty field for a value that is not known (std::nullopt), e.g. an output
  /// that one kind of run does not compute: still never a NaN.
  void write_row(std::span<const std::optional<double>> values, std::span<const std::string> labels = {});

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] const std::vector<std::string>& columns() const { return columns_; }
  [[nodiscard]] std::size_t rows() const { return rows_; }

 private:
  void flush_or_throw();

  std::filesystem::path path_;
  std::vector<std::string> columns_;
  std::ofstream out_;
  std::size_t rows_ = 0;
};

}  // namespace jointhb::io
