#pragma once
// The objective history of a fit as CSV, one row per evaluation, flushed as it is written so that
// an interrupted run keeps it, and read back to resume (fit/fitter.hpp):
//   eval,start,objective,failed,<parameter names...>,r0,r1,...
// start is -1 for the Jacobian's evaluations; the residual columns are empty for a failed one.
// Numbers are written with 17 significant digits, so they read back to the same doubles (the
// replay matches parameter vectors exactly).

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "jointhb/fit/fitter.hpp"

namespace jointhb::fit {

class HistoryWriter {
 public:
  /// Creates (or, with `append`, extends) the file; the header is written when it is new.
  /// Throws std::runtime_error naming the file when it cannot be opened.
  HistoryWriter(const std::filesystem::path& file, const std::vector<std::string>& names,
                std::size_t residuals, bool append);
  ~HistoryWriter();
  HistoryWriter(const HistoryWriter&) = delete;
  HistoryWriter& operator=(const HistoryWriter&) = delete;
  void write(const HistoryRow& row);

 private:
  std::FILE* file_ = nullptr;
  std::size_t residuals_ = 0;
};

/// The rows of a history file written for these parameter names. A last line cut short by an
/// interruption is ignored. Throws std::runtime_error ("FILE:LINE: ...") for a file that cannot
/// be read, a header with other parameters, or a malformed row.
std::vector<HistoryRow> read_history(const std::filesystem::path& file,
                                     const std::vector<std::string>& names);

}  // namespace jointhb::fit
