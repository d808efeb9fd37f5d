// The history of queries as a CSV file in the output directory: a header naming
// each column (step, time, each query, each reported expression, each trigger's
// condition and whether it fired), then one row per evaluated step, flushed at
// once (a job killed later keeps its rows). Rank 0 writes it; a write that fails
// is reported once and the file given up, never failing a step.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace canopy
{

class QueryHistoryFile
{
public:
  /// Creates (truncates) `path` and writes the header; `columns` after step and time.
  QueryHistoryFile(const std::string& path, const std::vector<std::string>& columns);
  ~QueryHistoryFile();
  QueryHistoryFile(const QueryHistoryFile&) = delete;
  QueryHistoryFile& operator=(const QueryHistoryFile&) = delete;

  /// One row: values in the header's order. Returns the problem, once, if writing fails.
  std::string write(std::int64_t step, double time, const std::vector<double>& values);

private:
  std::string Path;
  std::FILE* File = nullptr;
  bool Failed = false;
  std::string Problem; ///< why the file could not be created
};

} // namespace canopy
