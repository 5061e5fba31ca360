#include "jointhb/io/csv_writer.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>
#include <vector>

namespace jointhb::io {

CsvWriter::CsvWriter(std::filesystem::path path, std::vector<std::string> columns)
    : path_(std::move(path)), columns_(std::move(columns)) {
  if (columns_.empty()) throw std::invalid_argument("CsvWriter: the header has no columns");
  for (const auto& column : columns_) {
    if (column.empty() || column.find_first_of(",\"\r\n") != std::string::npos) {
      throw std::invalid_argument("CsvWriter: column name '" + column +
                                  "' is empty or contains a comma, quote or line break");
    }
  }
  out_.open(path_, std::ios::out | std::ios::trunc);
  if (!out_) {
    throw std::runtime_error("cannot open '" + path_.string() +
                             "' for writing: " + std::strerror(errno));
  }
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    out_ << (i ? "," : "") << columns_[i];
  }
  out_ << '\n';
  flush_or_throw();
}

void CsvWriter::write_row(std::span<const double> values) { write_row(values, {}); }

void CsvWriter::write_row(std::span<const double> values, std::span<const std::string> labels) {
  const std::vector<std::optional<double>> known(values.begin(), values.end());
  write_row(std::span<const std::optional<double>>(known), labels);
}

void CsvWriter::write_row(std::span<const std::optional<double>> values, std::span<const std::string> labels) {
  if (values.size() + labels.size() != columns_.size()) {
    throw std::invalid_argument("CsvWriter: row of " + std::to_string(values.size() + labels.size()) +
                                " values for " + std::to_string(columns_.size()) + " columns in '" +
                                path_.string() + "'");
  }
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (labels[i].empty() || labels[i].find_first_of(",\"\r\n ") != std::string::npos) {
      throw std::invalid_argument("CsvWriter: column '" + columns_[values.size() + i] + "' of '" +
                                  path_.string() + "' is empty or not one word");
    }
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i] && !std::isfinite(*values[i])) {
      throw std::invalid_argument("CsvWriter: column '" + columns_[i] + "' of '" + path_.string() +
                                  "' is not finite");
    }
  }
  // The whole row is formatted before anything is written, so a failed row leaves no half line.
  std::string line;
  char buffer[32];
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) line += ',';
    if (!values[i]) continue;  // empty field: not known
    std::snprintf(buffer, sizeof buffer, "%.17g", *values[i]);
    line += buffer;
  }
  for (std::size_t j = 0; j < labels.size(); ++j) line += (values.empty() && j == 0 ? "" : ",") + labels[j];
  line += '\n';
  out_ << line;
  flush_or_throw();
  ++rows_;
}

void CsvWriter::flush_or_throw() {
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write to '" + path_.string() + "'");
}

}  // namespace jointhb::io
