#include "jointhb/fit/history.hpp"

#include <fmt/format.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "jointhb/io/value_checks.hpp"

namespace jointhb::fit {

HistoryWriter::HistoryWriter(const std::filesystem::path& file,
                             const std::vector<std::string>& names, std::size_t residuals,
                             bool append)
    : residuals_(residuals) {
  std::error_code ec;
  const bool exists =
      append && std::filesystem::exists(file, ec) && std::filesystem::file_size(file, ec) > 0;
  file_ = std::fopen(file.string().c_str(), append ? "a" : "w");
  if (!file_) throw std::runtime_error("cannot write " + file.string());
  if (!exists) {
    std::string header = "eval,start,objective,failed";
    for (const auto& n : names) header += "," + n;
    for (std::size_t i = 0; i < residuals; ++i) header += fmt::format(",r{}", i);
    std::fprintf(file_, "%s\n", header.c_str());
    std::fflush(file_);
  }
}

HistoryWriter::~HistoryWriter() {
  if (file_) std::fclose(file_);
}

void HistoryWriter::write(const HistoryRow& row) {
  std::string line =
      fmt::format("{},{},{:.17g},{}", row.eval, row.start, row.objective, row.failed ? 1 : 0);
  for (double v : row.values) line += fmt::format(",{:.17g}", v);
  for (std::size_t i = 0; i < residuals_; ++i) {
    line += i < row.residuals.size() ? fmt::format(",{:.17g}", row.residuals[i]) : ",";
  }
  std::fprintf(file_, "%s\n", line.c_str());
  std::fflush(file_);
}

namespace {
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream s(line);
  while (std::getline(s, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}
}  // namespace

std::vector<HistoryRow> read_history(const std::filesystem::path& file,
                                     const std::vector<std::string>& names) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot read the history to resume from");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
  }
  const bool complete_last = [&] {  // an interrupted write leaves a line without its newline
    std::ifstream raw(file, std::ios::binary | std::ios::ate);
    if (!raw || raw.tellg() <= 0) return true;
    raw.seekg(-1, std::ios::end);
    char c = 0;
    raw.get(c);
    return c == '\n';
  }();
  if (lines.empty()) throw std::runtime_error(file.string() + ":1: empty history file");
  const auto header = split(lines[0]);
  if (header.size() < 4 + names.size() || header[0] != "eval") {
    throw std::runtime_error(file.string() + ":1: not a fit history header");
  }
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (header[4 + i] != names[i]) {
      throw std::runtime_error(
          fmt::format("{}:1: column {} is '{}', the case fits '{}' (a history of another fit)",
                      file.string(), 5 + i, header[4 + i], names[i]));
    }
  }
  const std::size_t residuals = header.size() - 4 - names.size();
  std::vector<HistoryRow> rows;
  for (std::size_t l = 1; l < lines.size(); ++l) {
    if (lines[l].empty()) continue;
    const auto cells = split(lines[l]);
    const bool last = l + 1 == lines.size();
    if (cells.size() != header.size()) {
      if (last && !complete_last) break;
      throw std::runtime_error(fmt::format("{}:{}: {} columns, the header has {}", file.string(),
                                           l + 1, cells.size(), header.size()));
    }
    const auto number = [&](std::size_t c) {
      const auto v = io::parse_number(cells[c]);
      if (!v) {
        throw std::runtime_error(fmt::format("{}:{}: column {}: not a number: '{}'", file.string(),
                                             l + 1, c + 1, cells[c]));
      }
      return *v;
    };
    if (last && !complete_last) break;
    HistoryRow row;
    row.eval = static_cast<int>(number(0));
    row.start = static_cast<int>(number(1));
    row.objective = number(2);
    row.failed = number(3) != 0.0;
    for (std::size_t i = 0; i < names.size(); ++i) row.values.push_back(number(4 + i));
    if (!row.failed) {
      for (std::size_t i = 0; i < residuals; ++i)
        row.residuals.push_back(number(4 + names.size() + i));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace jointhb::fit
