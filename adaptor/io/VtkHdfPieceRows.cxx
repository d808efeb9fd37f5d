// This rank's rows of a VTKHDF step (see VtkHdfPieceRows.h).
#include "VtkHdfPieceRows.h"

#include "CellArrayBlocks.h"
#include "HyperTreeGridPiece.h"
#include "VtkHdfLayout.h"

#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>

namespace canopy::io
{
namespace
{

/// Where the values of a grid dataset are, for those the piece holds as stored.
struct PieceValues
{
  hid_t memoryType;
  const void* values;
};

/// The values of `which` (not a coordinate axis) in `piece`, whose counts are
/// `counts` (both borrowed: the result points into them).
PieceValues valuesOf(GridDataset which, const HyperTreeGridPiece& piece, const PieceCounts& counts)
{
  switch (which)
  {
  case GridDataset::TreeIds:
    return {H5T_NATIVE_INT64, piece.treeIds.data()};
  case GridDataset::DepthPerTree:
    return {H5T_NATIVE_INT64, piece.depthPerTree.data()};
  case GridDataset::NumberOfCellsPerTreeDepth:
    return {H5T_NATIVE_INT64, piece.cellsPerTreeDepth.data()};
  case GridDataset::Descriptors:
    return {H5T_NATIVE_UCHAR, piece.descriptors.bytes().data()};
  case GridDataset::Mask:
    return {H5T_NATIVE_UCHAR, piece.leafMask.bytes().data()};
  default:
    break;
  }
  for (const PerPieceField& field : PerPieceFields)
  {
    if (field.dataset == which)
    {
      return {H5T_NATIVE_INT64, &(counts.*field.count)};
    }
  }
  return {H5I_INVALID_HID, nullptr};
}

std::string writeCoordinates(const Series& series, std::int64_t first, std::int64_t length,
                             vtkHyperTreeGrid* htg)
{
  vtkDataArray* axis = series.axis == 0   ? htg->GetXCoordinates()
                       : series.axis == 1 ? htg->GetYCoordinates()
                                          : htg->GetZCoordinates();
  std::vector<double> values(static_cast<std::size_t>(length), 0.0);
  for (std::int64_t i = 0; axis != nullptr && i < length && i < axis->GetNumberOfTuples(); ++i)
  {
    values[static_cast<std::size_t>(i)] = axis->GetComponent(i, 0);
  }
  return writeDatasetRows(series.data, first, length, H5T_NATIVE_DOUBLE, values.data());
}

/// `array` (null: only the ghost array may be missing, on a rank without other
/// ranks' parts; written as zeros) in the piece's file order.
std::string writeCellArray(const Series& series, std::int64_t first,
                           const HyperTreeGridPiece& piece, vtkDataArray* array)
{
  if (array == nullptr)
  {
    std::vector<unsigned char> zeros(
        static_cast<std::size_t>(piece.numberOfCells * series.data.columns), 0);
    return writeDatasetRows(series.data, first, piece.numberOfCells, H5T_NATIVE_UCHAR,
                            zeros.data());
  }
  const hid_t memoryType = memoryTypeOf(array->GetDataType());
  std::string problem;
  std::int64_t row = first;
  CellArrayBlocks(array, piece.runs)
      .forEach(
          [&](const void* values, vtkIdType tuples)
          {
            if (problem.empty())
            {
              problem = writeDatasetRows(series.data, row, tuples, memoryType, values);
            }
            row += tuples;
          });
  return problem;
}

} // namespace

std::string writePieceRows(VtkHdfLayout& layout, const StepShape& shape,
                           const HyperTreeGridPiece& piece, vtkHyperTreeGrid* htg,
                           const std::vector<vtkDataArray*>& arrays)
{
  const int rank = shape.rank;
  auto firstRow = [&](const Series& series)
  { return series.data.committed + shape.prefix(series.kind, rank, series.axis); };
  std::string problem;
  for (std::size_t d = 0; d < NumberOfGridDatasets && problem.empty(); ++d)
  {
    const auto which = static_cast<GridDataset>(d);
    const Series& series = layout.grid(which);
    const std::int64_t rows = shape.rows(series.kind, rank, series.axis);
    if (series.kind == Kind::Coordinate)
    {
      problem = writeCoordinates(series, firstRow(series), rows, htg);
    }
    else
    {
      const PieceValues values = valuesOf(which, piece, shape.mine());
      problem =
          writeDatasetRows(series.data, firstRow(series), rows, values.memoryType, values.values);
    }
  }
  for (std::size_t a = 0; a < layout.arrays().size() && problem.empty(); ++a)
  {
    const Series& series = layout.cellData(a);
    problem =
        writeCellArray(series, firstRow(series), piece, findArray(arrays, layout.arrays()[a].name));
  }
  return problem;
}

} // namespace canopy::io
