// This rank's rows of a VTKHDF step (see VtkHdfPieceRows.h).
#include "VtkHdfPieceRows.h"

#include "VtkHdfLayout.h"
#include "VtkHdfRowTransfer.h"
#include <canopy/io/CellArrayBlocks.h>
#include <canopy/io/HyperTreeGridPiece.h>

#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>

namespace canopy::io
{
namespace
{

/// Where the values of a grid dataset are, for those the piece holds as stored.
struct PieceValues
{
  int vtkType;
  const void* values;
};

/// The values of `which` (not a coordinate axis) in `piece`, whose counts are
/// `counts` (both borrowed: the result points into them).
PieceValues valuesOf(GridDataset which, const HyperTreeGridPiece& piece, const PieceCounts& counts)
{
  switch (which)
  {
  case GridDataset::TreeIds:
    return {VTK_LONG_LONG, piece.treeIds.data()};
  case GridDataset::DepthPerTree:
    return {VTK_LONG_LONG, piece.depthPerTree.data()};
  case GridDataset::NumberOfCellsPerTreeDepth:
    return {VTK_LONG_LONG, piece.cellsPerTreeDepth.data()};
  case GridDataset::Descriptors:
    return {VTK_UNSIGNED_CHAR, piece.descriptors.bytes().data()};
  case GridDataset::Mask:
    return {VTK_UNSIGNED_CHAR, piece.leafMask.bytes().data()};
  default:
    break;
  }
  for (const PerPieceField& field : PerPieceFields)
  {
    if (field.dataset == which)
    {
      return {VTK_LONG_LONG, &(counts.*field.count)};
    }
  }
  return {VTK_VOID, nullptr};
}

std::string putCoordinates(RowSink& sink, std::size_t index, const Series& series,
                           std::int64_t length, vtkHyperTreeGrid* htg)
{
  vtkDataArray* axis = series.axis == 0   ? htg->GetXCoordinates()
                       : series.axis == 1 ? htg->GetYCoordinates()
                                          : htg->GetZCoordinates();
  std::vector<double> values(static_cast<std::size_t>(length), 0.0);
  for (std::int64_t i = 0; axis != nullptr && i < length && i < axis->GetNumberOfTuples(); ++i)
  {
    values[static_cast<std::size_t>(i)] = axis->GetComponent(i, 0);
  }
  return sink.put(index, 0, length, VTK_DOUBLE, 1, values.data());
}

/// `array` (null: only the ghost array may be missing, on a rank without other
/// ranks' parts; given as zeros) in the piece's file order.
std::string putCellArray(RowSink& sink, std::size_t index, const Series& series,
                         const HyperTreeGridPiece& piece, vtkDataArray* array)
{
  const int columns = series.data.columns;
  if (array == nullptr)
  {
    std::vector<unsigned char> zeros(static_cast<std::size_t>(piece.numberOfCells * columns), 0);
    return sink.put(index, 0, piece.numberOfCells, VTK_UNSIGNED_CHAR, columns, zeros.data());
  }
  std::string problem;
  std::int64_t row = 0;
  CellArrayBlocks(array, piece.runs)
      .forEach(
          [&](const void* values, vtkIdType tuples)
          {
            if (problem.empty())
            {
              problem = sink.put(index, row, tuples, array->GetDataType(), columns, values);
            }
            row += tuples;
          });
  return problem;
}

} // namespace

std::string putPieceRows(RowSink& sink, const VtkHdfLayout& layout, const StepShape& shape,
                         const HyperTreeGridPiece& piece, vtkHyperTreeGrid* htg,
                         const std::vector<vtkDataArray*>& arrays)
{
  std::string problem;
  for (std::size_t d = 0; d < NumberOfGridDatasets && problem.empty(); ++d)
  {
    const auto which = static_cast<GridDataset>(d);
    const Series& series = layout.series(d);
    const std::int64_t rows = shape.rows(series.kind, shape.rank, series.axis);
    if (series.kind == Kind::Coordinate)
    {
      problem = putCoordinates(sink, d, series, rows, htg);
    }
    else
    {
      const PieceValues values = valuesOf(which, piece, shape.mine());
      problem = sink.put(d, 0, rows, values.vtkType, 1, values.values);
    }
  }
  for (std::size_t a = 0; a < layout.arrays().size() && problem.empty(); ++a)
  {
    const std::size_t index = NumberOfGridDatasets + a;
    problem = putCellArray(sink, index, layout.series(index), piece,
                           findArray(arrays, layout.arrays()[a].name));
  }
  return problem;
}

} // namespace canopy::io
