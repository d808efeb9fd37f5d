// Where a rank's rows of a VTKHDF step go (see VtkHdfRowTransfer.h).
#include "VtkHdfRowTransfer.h"

#include "VtkHdfArrays.h"
#include "VtkHdfLayout.h"

#include <vtkDataArray.h>

#include <algorithm>
#include <array>

namespace canopy::io
{
namespace
{

constexpr int RowsTag = 1;
/// A message's values at most: large pieces go in several (MPI counts are ints).
constexpr std::int64_t MaximumMessageBytes = std::int64_t(1) << 26;

/// series, first, rows, vtkType, columns, bytes; series < 0: the sender is done.
using Header = std::array<std::int64_t, 6>;

} // namespace

WrittenRows::WrittenRows(VtkHdfLayout& layout, const StepShape& shape, int from)
    : Layout(layout), Shape(shape), From(from)
{
}

std::string WrittenRows::put(std::size_t series, std::int64_t first, std::int64_t rows, int vtkType,
                             int columns, const void* values)
{
  const std::string sender = "rank " + std::to_string(this->From) + " sent rows ";
  if (series >= this->Layout.numberOfSeries())
  {
    return sender + "for a dataset the file does not have";
  }
  const Series& target = this->Layout.series(series);
  const std::int64_t pieceRows = this->Shape.rows(target.kind, this->From, target.axis);
  if (first < 0 || rows < 0 || first + rows > pieceRows || columns != target.data.columns)
  {
    return sender + "outside its piece of " + target.data.path;
  }
  const hid_t memoryType = memoryTypeOf(vtkType);
  if (memoryType == H5I_INVALID_HID)
  {
    return sender + "of a value type VTKHDF cannot store to " + target.data.path;
  }
  return writeDatasetRows(target.data,
                          target.data.committed +
                              this->Shape.prefix(target.kind, this->From, target.axis) + first,
                          rows, memoryType, values);
}

std::string SentRows::put(std::size_t series, std::int64_t first, std::int64_t rows, int vtkType,
                          int columns, const void* values)
{
  const std::int64_t rowBytes =
      std::int64_t(vtkDataArray::GetDataTypeSize(vtkType)) * std::max(columns, 1);
  if (rowBytes <= 0)
  {
    return "rows of an unknown value type";
  }
  const std::int64_t perMessage = std::max<std::int64_t>(1, MaximumMessageBytes / rowBytes);
  const auto* bytes = static_cast<const unsigned char*>(values);
  for (std::int64_t done = 0; done < rows; done += perMessage)
  {
    const std::int64_t count = std::min(perMessage, rows - done);
    const Header header{
        static_cast<std::int64_t>(series), first + done, count, vtkType, columns, count * rowBytes};
    MPI_Send(header.data(), static_cast<int>(header.size()), MPI_INT64_T, 0, RowsTag,
             this->Communicator);
    MPI_Send(bytes + done * rowBytes, static_cast<int>(header[5]), MPI_BYTE, 0, RowsTag,
             this->Communicator);
  }
  return {};
}

void SentRows::finish()
{
  const Header done{-1, 0, 0, 0, 0, 0};
  MPI_Send(done.data(), static_cast<int>(done.size()), MPI_INT64_T, 0, RowsTag, this->Communicator);
}

std::string receiveRows(MPI_Comm communicator, int from, RowSink& sink)
{
  std::string problem;
  std::vector<unsigned char> buffer;
  while (true)
  {
    Header header{};
    MPI_Recv(header.data(), static_cast<int>(header.size()), MPI_INT64_T, from, RowsTag,
             communicator, MPI_STATUS_IGNORE);
    if (header[0] < 0)
    {
      return problem;
    }
    buffer.resize(static_cast<std::size_t>(header[5]));
    MPI_Recv(buffer.data(), static_cast<int>(header[5]), MPI_BYTE, from, RowsTag, communicator,
             MPI_STATUS_IGNORE);
    if (problem.empty())
    {
      problem = sink.put(static_cast<std::size_t>(header[0]), header[1], header[2],
                         static_cast<int>(header[3]), static_cast<int>(header[4]), buffer.data());
    }
  }
}

} // namespace canopy::io
