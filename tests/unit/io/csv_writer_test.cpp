#include "jointhb/io/csv_writer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "temp_file.hpp"

namespace jointhb::io {
namespace {

using testing::TempFile;

std::vector<std::vector<std::string>> split_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

TEST(io_CsvWriter, RoundTripIsBitExact) {
  const TempFile file(".csv");
  const std::vector<std::vector<double>> rows = {
      {0.1, 1.0 / 3.0, -2.5e17},
      {1e-300, 4.9e-324, std::numeric_limits<double>::max()},
      {0.0, -0.0, 123456789.123456789},
  };
  {
    CsvWriter csv(file.path(), {"a_m", "b_N", "c_J"});
    for (const auto& row : rows) csv.write_row(row);
    EXPECT_EQ(csv.rows(), rows.size());
  }
  const auto cells = split_csv(file.contents());
  ASSERT_EQ(cells.size(), rows.size() + 1);
  EXPECT_EQ(cells[0], (std::vector<std::string>{"a_m", "b_N", "c_J"}));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(cells[i + 1].size(), 3u);
    for (std::size_t j = 0; j < 3; ++j) {
      const double read = std::strtod(cells[i + 1][j].c_str(), nullptr);
      EXPECT_EQ(read, rows[i][j]) << cells[i + 1][j];
      EXPECT_EQ(std::signbit(read), std::signbit(rows[i][j]));
    }
  }
}

TEST(io_CsvWriter, EveryRowIsOnDiskAsSoonAsItIsWritten) {
  const TempFile file(".csv");
  CsvWriter csv(file.path(), {"x"});
  EXPECT_EQ(file.contents(), "x\n");
  csv.write_row({1.5});
  EXPECT_EQ(file.contents(), "x\n1.5\n");  // read while the writer is still open
}

TEST(io_CsvWriter, RefusesNonFiniteValuesAndWrongWidths) {
  const TempFile file(".csv");
  CsvWriter csv(file.path(), {"x", "y"});
  EXPECT_THROW(csv.write_row({1.0, std::nan("")}), std::invalid_argument);
  EXPECT_THROW(csv.write_row({std::numeric_limits<double>::infinity(), 1.0}),
               std::invalid_argument);
  EXPECT_THROW(csv.write_row({1.0}), std::invalid_argument);
  EXPECT_EQ(file.contents(), "x,y\n");  // nothing half-written
  EXPECT_EQ(csv.rows(), 0u);
}

TEST(io_CsvWriter, RefusesColumnNamesThatBreakTheFormat) {
  const TempFile file(".csv");
  EXPECT_THROW(CsvWriter(file.path(), {}), std::invalid_argument);
  EXPECT_THROW(CsvWriter(file.path(), {"a,b"}), std::invalid_argument);
  EXPECT_THROW(CsvWriter(file.path(), {""}), std::invalid_argument);
}

TEST(io_CsvWriter, UnopenablePathIsNamedInTheError) {
  const std::string path = "/nonexistent-jointhb-dir/out.csv";
  try {
    CsvWriter csv(path, {"x"});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace jointhb::io
