#include <canopy/io/HtgSeriesWriter.h>

#include "WriterAgreement.h"
#include <canopy/io/HtgFileWriter.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>

namespace canopy::io
{
namespace
{

std::string stepLabel(std::int64_t step)
{
  std::ostringstream label;
  label << std::setw(6) << std::setfill('0') << step;
  return label.str();
}

/// Writes `text` to `path` through a temporary file: readers never see a half file.
std::string replaceFile(const std::filesystem::path& path, const std::string& text)
{
  const std::filesystem::path temporary = path.string() + ".part";
  std::FILE* out = std::fopen(temporary.c_str(), "wb");
  if (out == nullptr)
  {
    return "cannot open " + temporary.string() + ": " + std::strerror(errno);
  }
  errno = 0;
  bool ok = std::fwrite(text.data(), text.size(), 1, out) == 1;
  int error = errno;
  if (std::fclose(out) != 0 && ok)
  {
    ok = false;
    error = errno;
  }
  std::error_code status;
  if (ok)
  {
    std::filesystem::rename(temporary, path, status);
    if (!status)
    {
      return {};
    }
  }
  std::error_code ignored;
  std::filesystem::remove(temporary, ignored);
  return "cannot write " + path.string() + ": " +
         (status ? status.message() : std::string(std::strerror(error ? error : EIO)));
}

/// The shortest text that reads back as `value` (0.1, not 0.10000000000000001).
std::string shortest(double value)
{
  char text[32];
  const auto result = std::to_chars(text, text + sizeof(text), value);
  return std::string(text, result.ptr);
}

std::string escapedAttribute(const std::string& text)
{
  std::string out;
  for (char c : text)
  {
    out += c == '"' ? std::string("&quot;") : c == '&' ? std::string("&amp;") : std::string(1, c);
  }
  return out;
}

} // namespace

HtgSeriesWriter::HtgSeriesWriter(MPI_Comm communicator, std::string seriesFile,
                                 std::vector<std::string> arrays)
    : Communicator(communicator), Arrays(std::move(arrays))
{
  const std::filesystem::path path(seriesFile);
  this->Folder = path.parent_path().string();
  this->Name = path.stem().string();
}

std::string HtgSeriesWriter::stepFileName(std::int64_t step) const
{
  return this->Name + "_" + stepLabel(step) + ".vtm";
}

std::string HtgSeriesWriter::pieceFileName(std::int64_t step, int rank) const
{
  const std::string stem = this->Name + "_" + stepLabel(step);
  return stem + "/" + stem + "_" + std::to_string(rank) + ".htg";
}

void HtgSeriesWriter::writeStep(vtkHyperTreeGrid* htg, std::int64_t step, double time)
{
  const int rank = rankOf(this->Communicator);
  const int size = sizeOf(this->Communicator);
  const std::filesystem::path folder(this->Folder.empty() ? "." : this->Folder);
  const std::filesystem::path piece = folder / this->pieceFileName(step, rank);
  std::string problem;
  std::error_code status;
  std::filesystem::create_directories(piece.parent_path(), status);
  if (status)
  {
    problem = "cannot create " + piece.parent_path().string() + ": " + status.message();
  }
  else
  {
    problem = writeHtgFile(htg, piece.string(), this->Arrays);
  }
  const std::string pieces = gatherProblems(this->Communicator, problem);

  std::string index;
  if (pieces.empty() && rank == 0)
  {
    std::ostringstream vtm;
    vtm << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n  <vtkMultiBlockDataSet>\n";
    for (int r = 0; r < size; ++r)
    {
      vtm << "    <DataSet index=\"" << r << "\" name=\"rank " << r << "\" file=\""
          << escapedAttribute(this->pieceFileName(step, r)) << "\"/>\n";
    }
    vtm << "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
    index = replaceFile(folder / this->stepFileName(step), vtm.str());
    if (index.empty())
    {
      std::vector<Entry> steps = this->Steps;
      steps.erase(std::remove_if(steps.begin(), steps.end(),
                                 [step](const Entry& e) { return e.step == step; }),
                  steps.end());
      steps.push_back({step, time});
      std::ostringstream pvd;
      pvd << "<?xml version=\"1.0\"?>\n"
          << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          << "  <Collection>\n";
      for (const Entry& entry : steps)
      {
        pvd << "    <DataSet timestep=\"" << shortest(entry.time)
            << "\" group=\"\" part=\"0\" file=\""
            << escapedAttribute(this->stepFileName(entry.step)) << "\"/>\n";
      }
      pvd << "  </Collection>\n</VTKFile>\n";
      index = replaceFile(folder / (this->Name + ".pvd"), pvd.str());
    }
  }
  const std::string indexProblem = gatherProblems(this->Communicator, index);
  if (!pieces.empty() || !indexProblem.empty())
  {
    // The step is not in the series: leave none of its files behind.
    std::error_code ignored;
    std::filesystem::remove(piece, ignored);
    // Once every rank removed its piece, the step's folder too (only if empty:
    // remove() leaves a folder that holds anything else).
    gatherProblems(this->Communicator, std::string());
    if (rank == 0)
    {
      std::filesystem::remove(folder / this->stepFileName(step), ignored);
      std::filesystem::remove(piece.parent_path(), ignored);
    }
    throw WriteError("hypertree-grid extract " + (folder / (this->Name + ".pvd")).string() +
                     ": step " + std::to_string(step) +
                     " not written: " + (pieces.empty() ? indexProblem : pieces));
  }
  this->Steps.erase(std::remove_if(this->Steps.begin(), this->Steps.end(),
                                   [step](const Entry& e) { return e.step == step; }),
                    this->Steps.end());
  this->Steps.push_back({step, time});
}

} // namespace canopy::io
