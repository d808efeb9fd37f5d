#include "QueryHistoryFile.h"

#include <cerrno>
#include <cstring>

namespace canopy
{
namespace
{

/// A CSV field: quoted (query texts hold commas), quotes doubled.
std::string quoted(const std::string& text)
{
  std::string out = "\"";
  for (char c : text)
  {
    out += c == '"' ? "\"\"" : std::string(1, c);
  }
  return out + "\"";
}

} // namespace

QueryHistoryFile::QueryHistoryFile(const std::string& path, const std::vector<std::string>& columns)
    : Path(path), File(std::fopen(path.c_str(), "w"))
{
  if (File == nullptr)
  {
    Problem = std::strerror(errno);
    return;
  }
  std::string header = "step,time";
  for (const auto& column : columns)
  {
    header += "," + quoted(column);
  }
  header += "\n";
  std::fputs(header.c_str(), File);
  std::fflush(File);
}

QueryHistoryFile::~QueryHistoryFile()
{
  if (File != nullptr)
  {
    std::fclose(File);
  }
}

std::string QueryHistoryFile::write(std::int64_t step, double time,
                                    const std::vector<double>& values)
{
  if (Failed)
  {
    return {};
  }
  if (File == nullptr)
  {
    Failed = true;
    return "the query history '" + Path + "' could not be created (" + Problem +
           "); no rows are written";
  }
  std::string row = std::to_string(step);
  char number[40];
  std::snprintf(number, sizeof number, ",%.17g", time);
  row += number;
  for (double value : values)
  {
    std::snprintf(number, sizeof number, ",%.17g", value);
    row += number;
  }
  row += "\n";
  errno = 0;
  if (std::fputs(row.c_str(), File) < 0 || std::fflush(File) != 0)
  {
    Failed = true;
    return "the query history '" + Path + "' could not be written (" + std::strerror(errno) +
           "); no more rows are written";
  }
  return {};
}

} // namespace canopy
