#include <canopy/io/HtgFileWriter.h>

#include "CellArraySelection.h"
#include <canopy/io/CellArrayBlocks.h>
#include <canopy/io/HyperTreeGridPiece.h>

#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <sstream>
#include <vector>

namespace canopy::io
{
namespace
{

/// VTK XML's name for a value type.
const char* xmlTypeName(int type)
{
  switch (type)
  {
  case VTK_FLOAT:
    return "Float32";
  case VTK_DOUBLE:
    return "Float64";
  case VTK_CHAR:
  case VTK_SIGNED_CHAR:
    return "Int8";
  case VTK_UNSIGNED_CHAR:
    return "UInt8";
  case VTK_SHORT:
    return "Int16";
  case VTK_UNSIGNED_SHORT:
    return "UInt16";
  case VTK_INT:
    return "Int32";
  case VTK_UNSIGNED_INT:
    return "UInt32";
  case VTK_LONG:
    return sizeof(long) == 8 ? "Int64" : "Int32";
  case VTK_UNSIGNED_LONG:
    return sizeof(long) == 8 ? "UInt64" : "UInt32";
  case VTK_LONG_LONG:
  case VTK_ID_TYPE:
    return "Int64";
  case VTK_UNSIGNED_LONG_LONG:
    return "UInt64";
  default:
    return nullptr;
  }
}

std::string escaped(const std::string& text)
{
  std::string out;
  for (char c : text)
  {
    switch (c)
    {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    default:
      out += c;
    }
  }
  return out;
}

/// One block of the appended section: its size in bytes and how to write it.
struct Block
{
  std::uint64_t bytes;
  std::function<bool(std::FILE*)> write;
};

/// The file being assembled: XML elements that refer to appended blocks by offset.
class AppendedFile
{
public:
  /// Adds a DataArray element whose values are a block; returns the element.
  std::string dataArray(const std::string& name, const char* type, std::int64_t tuples,
                        int components, std::uint64_t bytes, std::function<bool(std::FILE*)> write)
  {
    std::ostringstream element;
    element << "<DataArray type=\"" << type << "\" Name=\"" << escaped(name) << "\"";
    if (components > 1)
    {
      element << " NumberOfComponents=\"" << components << "\"";
    }
    element << " NumberOfTuples=\"" << tuples << "\" format=\"appended\" offset=\"" << this->Offset
            << "\"/>";
    // Each block is preceded by its size (header_type UInt64).
    this->Offset += sizeof(std::uint64_t) + bytes;
    this->Blocks.push_back({bytes, std::move(write)});
    return element.str();
  }

  std::string bytes(const std::string& name, const char* type, std::int64_t values,
                    std::vector<unsigned char> data)
  {
    const std::uint64_t size = data.size();
    return this->dataArray(name, type, values, 1, size,
                           [data = std::move(data)](std::FILE* file) {
                             return data.empty() ||
                                    std::fwrite(data.data(), data.size(), 1, file) == 1;
                           });
  }

  std::string bits(const std::string& name, const PackedBits& bits)
  {
    return this->bytes(name, "Bit", bits.size(), bits.bytes());
  }

  std::string int64s(const std::string& name, const std::vector<std::int64_t>& values)
  {
    std::vector<unsigned char> data(values.size() * sizeof(std::int64_t));
    if (!values.empty())
    {
      std::memcpy(data.data(), values.data(), data.size());
    }
    return this->bytes(name, "Int64", static_cast<std::int64_t>(values.size()), std::move(data));
  }

  bool writeBlocks(std::FILE* file) const
  {
    for (const Block& block : this->Blocks)
    {
      if (std::fwrite(&block.bytes, sizeof(block.bytes), 1, file) != 1 || !block.write(file))
      {
        return false;
      }
    }
    return true;
  }

private:
  std::uint64_t Offset = 0;
  std::vector<Block> Blocks;
};

std::vector<unsigned char> coordinates(vtkDataArray* array)
{
  std::vector<double> values(array ? static_cast<std::size_t>(array->GetNumberOfTuples()) : 0);
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    values[i] = array->GetComponent(static_cast<vtkIdType>(i), 0);
  }
  std::vector<unsigned char> data(values.size() * sizeof(double));
  if (!values.empty())
  {
    std::memcpy(data.data(), values.data(), data.size());
  }
  return data;
}

/// The .htg of `htg`: its XML `header` (up to the appended data's start) and
/// the appended `file` blocks. Empty on success, otherwise what is wrong.
std::string assemble(vtkHyperTreeGrid* htg, const std::vector<std::string>& arrays,
                     AppendedFile& file, std::string& header)
{
  if (htg == nullptr)
  {
    return "no grid to write";
  }
  std::vector<std::string> problems;
  const std::vector<vtkDataArray*> cellArrays = selectCellArrays(htg, arrays, problems);
  for (vtkDataArray* array : cellArrays)
  {
    if (xmlTypeName(array->GetDataType()) == nullptr)
    {
      problems.push_back(std::string("cell array '") + array->GetName() + "' has a value type " +
                         "the .htg format cannot store");
    }
  }
  if (!problems.empty())
  {
    std::string text = problems.front();
    for (std::size_t i = 1; i < problems.size(); ++i)
    {
      text += "; " + problems[i];
    }
    return text;
  }
  const HyperTreeGridPiece piece = HyperTreeGridPiece::describe(htg);

  std::ostringstream xml;
  const unsigned int* dimensions = htg->GetDimensions();
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"HyperTreeGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n"
      << "  <HyperTreeGrid BranchFactor=\"" << htg->GetBranchFactor()
      << "\" TransposedRootIndexing=\"" << (htg->GetTransposedRootIndexing() ? 1 : 0)
      << "\" Dimensions=\"" << dimensions[0] << " " << dimensions[1] << " " << dimensions[2]
      << "\">\n    <Grid>\n"
      << "      "
      << file.bytes("XCoordinates", "Float64", dimensions[0], coordinates(htg->GetXCoordinates()))
      << "\n      "
      << file.bytes("YCoordinates", "Float64", dimensions[1], coordinates(htg->GetYCoordinates()))
      << "\n      "
      << file.bytes("ZCoordinates", "Float64", dimensions[2], coordinates(htg->GetZCoordinates()))
      << "\n    </Grid>\n    <Trees>\n";
  std::size_t depthCursor = 0;
  for (std::size_t t = 0; t < piece.treeIds.size(); ++t)
  {
    const std::int64_t levels = piece.depthPerTree[t];
    const std::vector<std::int64_t> perLevel(
        piece.cellsPerTreeDepth.begin() + static_cast<std::ptrdiff_t>(depthCursor),
        piece.cellsPerTreeDepth.begin() + static_cast<std::ptrdiff_t>(depthCursor + levels));
    depthCursor += static_cast<std::size_t>(levels);
    const std::int64_t firstCell = piece.treeCellStart[t];
    const std::int64_t cells =
        (t + 1 < piece.treeIds.size() ? piece.treeCellStart[t + 1] : piece.numberOfCells) -
        firstCell;
    const std::int64_t firstBit = piece.treeDescriptorStart[t];
    const std::int64_t bits = cells - perLevel.back();
    xml << "      <Tree Index=\"" << piece.treeIds[t] << "\" NumberOfLevels=\"" << levels
        << "\" NumberOfVertices=\"" << cells << "\">\n"
        << "        " << file.bits("Descriptor", piece.descriptors.slice(firstBit, bits)) << "\n"
        << "        " << file.int64s("NbVerticesByLevel", perLevel) << "\n";
    if (piece.mask.size() > 0)
    {
      xml << "        " << file.bits("Mask", piece.mask.slice(firstCell, cells)) << "\n";
    }
    xml << "        <CellData>\n";
    auto runs = std::make_shared<std::vector<CellRun>>(piece.runsAt(firstCell, cells));
    for (vtkDataArray* array : cellArrays)
    {
      const int components = array->GetNumberOfComponents();
      const auto bytes = static_cast<std::uint64_t>(cells) *
                         static_cast<std::uint64_t>(components) *
                         static_cast<std::uint64_t>(array->GetDataTypeSize());
      xml << "          "
          << file.dataArray(
                 array->GetName(), xmlTypeName(array->GetDataType()), cells, components, bytes,
                 [array, runs](std::FILE* out)
                 {
                   bool ok = true;
                   CellArrayBlocks(array, *runs)
                       .forEach(
                           [&](const void* values, vtkIdType tuples)
                           {
                             const std::size_t size =
                                 static_cast<std::size_t>(tuples) *
                                 static_cast<std::size_t>(array->GetNumberOfComponents()) *
                                 static_cast<std::size_t>(array->GetDataTypeSize());
                             ok = ok && std::fwrite(values, size, 1, out) == 1;
                           });
                   return ok;
                 })
          << "\n";
    }
    xml << "        </CellData>\n      </Tree>\n";
  }
  xml << "    </Trees>\n  </HyperTreeGrid>\n  <AppendedData encoding=\"raw\">\n   _";

  header = xml.str();
  return {};
}

/// Writes an assembled .htg to `out`; false if a write failed (errno says why).
bool writeAssembled(const std::string& header, const AppendedFile& file, std::FILE* out)
{
  const std::string trailer = "\n  </AppendedData>\n</VTKFile>\n";
  return std::fwrite(header.data(), header.size(), 1, out) == 1 && file.writeBlocks(out) &&
         std::fwrite(trailer.data(), trailer.size(), 1, out) == 1;
}

} // namespace

std::string writeHtgFile(vtkHyperTreeGrid* htg, const std::string& fileName,
                         const std::vector<std::string>& arrays)
{
  AppendedFile file;
  std::string header;
  const std::string problem = assemble(htg, arrays, file, header);
  if (!problem.empty())
  {
    return problem;
  }
  const std::string temporary = fileName + ".part";
  std::FILE* out = std::fopen(temporary.c_str(), "wb");
  if (out == nullptr)
  {
    return "cannot open " + temporary + " for writing: " + std::strerror(errno);
  }
  errno = 0;
  bool ok = writeAssembled(header, file, out);
  int error = errno;
  if (std::fclose(out) != 0 && ok)
  {
    ok = false;
    error = errno;
  }
  std::error_code ignored;
  if (!ok)
  {
    std::filesystem::remove(temporary, ignored);
    return "cannot write " + fileName + ": " + std::strerror(error ? error : EIO);
  }
  std::error_code renamed;
  std::filesystem::rename(temporary, fileName, renamed);
  if (renamed)
  {
    std::filesystem::remove(temporary, ignored);
    return "cannot rename " + temporary + " to " + fileName + ": " + renamed.message();
  }
  return {};
}

std::string writeHtgText(vtkHyperTreeGrid* htg, std::string& text,
                         const std::vector<std::string>& arrays)
{
  text.clear();
  AppendedFile file;
  std::string header;
  const std::string problem = assemble(htg, arrays, file, header);
  if (!problem.empty())
  {
    return problem;
  }
  // A stream into memory, so that the file's own writing code writes it.
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  if (out == nullptr)
  {
    return std::string("cannot open a memory stream: ") + std::strerror(errno);
  }
  errno = 0;
  const bool written = writeAssembled(header, file, out);
  int error = errno;
  const bool closed = std::fclose(out) == 0;
  if (!closed && written)
  {
    error = errno;
  }
  if (written && closed)
  {
    text.assign(buffer, size);
  }
  std::free(buffer);
  return written && closed ? std::string()
                           : std::string("cannot write the .htg text in memory: ") +
                                 std::strerror(error ? error : ENOMEM);
}

} // namespace canopy::io
