// The VTKHDF HyperTreeGrid layout (VTKHDF 2.4, with the temporal Steps group):
// the datasets under /VTKHDF that every step grows, the datasets under
// /VTKHDF/Steps that say where each step's rows start, and how a file gets them
// (created, or reopened with the rows its steps hold), grows by a step and
// shrinks back to its steps. Datasets are named (GridDataset, StepDataset);
// their order is the order the file is made in.
#pragma once

#include "HdfHandle.h"
#include "VtkHdfArrays.h"
#include "VtkHdfStepShape.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace canopy::io
{

/// The grid's datasets under /VTKHDF (its cell arrays come after them).
enum class GridDataset
{
  NumberOfTrees,
  NumberOfCells,
  NumberOfDepths,
  DescriptorsSize,
  TreeIds,
  DepthPerTree,
  NumberOfCellsPerTreeDepth,
  Descriptors,
  Mask,
  XCoordinates,
  YCoordinates,
  ZCoordinates
};
constexpr std::size_t NumberOfGridDatasets = 12;

/// The datasets under /VTKHDF/Steps that are not another dataset's offsets.
enum class StepDataset
{
  Values,
  PartOffsets,
  NumberOfParts
};
constexpr std::size_t NumberOfStepDatasets = 3;

/// The per-piece datasets and the count of PieceCounts each holds, in file order.
struct PerPieceField
{
  GridDataset dataset;
  std::int64_t PieceCounts::*count;
};
inline constexpr PerPieceField PerPieceFields[] = {
    {GridDataset::NumberOfTrees, &PieceCounts::trees},
    {GridDataset::NumberOfCells, &PieceCounts::cells},
    {GridDataset::NumberOfDepths, &PieceCounts::depths},
    {GridDataset::DescriptorsSize, &PieceCounts::descriptorBits}};

/// A dataset the steps grow by rows.
struct GrowingDataset
{
  const char* group = "VTKHDF/"; // where it is, from the file's root
  std::string path;              // within `group`, as messages name it
  hid_t fileType = H5I_INVALID_HID;
  int columns = 1;
  HdfDataset handle;          // open while a step is written
  std::int64_t committed = 0; // rows holding the file's steps
};

/// A dataset of /VTKHDF, how it grows, and (except for the per-piece counts)
/// its offsets under /VTKHDF/Steps: where each step's rows start.
struct Series
{
  GrowingDataset data;
  Kind kind = Kind::PerPiece;
  int axis = 0; // Coordinate: 0, 1, 2 for X, Y, Z
  std::optional<GrowingDataset> offsets;
};

/// The datasets of one file. Its functions that return a string return what
/// went wrong on this rank ("" if nothing did), for the writer's agreement.
class VtkHdfLayout
{
public:
  /// The datasets of a file with the cell arrays `arrays`, none of them open.
  explicit VtkHdfLayout(std::vector<ArraySpec> arrays = {});

  const std::vector<ArraySpec>& arrays() const { return this->Arrays; }
  /// Every dataset of /VTKHDF: the grid's in GridDataset order, then one per arrays() entry.
  std::size_t numberOfSeries() const { return this->AllSeries.size(); }
  Series& series(std::size_t index) { return this->AllSeries[index]; }
  const Series& series(std::size_t index) const { return this->AllSeries[index]; }
  Series& grid(GridDataset which) { return this->series(static_cast<std::size_t>(which)); }
  GrowingDataset& step(StepDataset which)
  {
    return this->StepDatasets[static_cast<std::size_t>(which)];
  }

  /// Creates /VTKHDF in `file` (borrowed): attributes, groups, empty datasets,
  /// chunked for steps like `shape`.
  std::string create(hid_t file, const StepShape& shape, bool transposedRootIndexing);
  /// Becomes the layout of `file` (borrowed), written before: checks it holds
  /// a grid like `shape`'s, takes its cell arrays, opens its datasets, reads its
  /// number of steps into `steps` and the rows they hold.
  std::string open(hid_t file, const StepShape& shape, std::int64_t& steps);

  /// Drops rows beyond the file's steps (a step a killed run left behind).
  std::string trim();
  /// Grows /VTKHDF's datasets by the step's rows.
  std::string extendData(const StepShape& shape);
  /// Grows /VTKHDF/Steps' datasets by a row.
  std::string extendSteps();
  /// The step's row of every /VTKHDF/Steps dataset.
  std::string writeStepRow(const StepShape& shape, double time);
  /// Closes every dataset.
  void close();

private:
  /// Every dataset in the order the file is made in: /VTKHDF's, then /VTKHDF/Steps'.
  template <typename Visit>
  void forEachDataset(Visit visit);
  /// /VTKHDF/Steps' datasets alone, in the same order.
  template <typename Visit>
  void forEachStepsDataset(Visit visit);
  std::string openDatasets(hid_t file);
  std::string readCommittedRows(std::int64_t steps, const StepShape& shape);

  std::vector<ArraySpec> Arrays;
  std::vector<Series> AllSeries; // the grid's datasets, then one per cell array
  std::array<GrowingDataset, NumberOfStepDatasets> StepDatasets;
};

/// Writes `rows` rows of `memoryType` from `values` (borrowed) at row `first` of
/// `dataset` (open). "" or what went wrong.
std::string writeDatasetRows(const GrowingDataset& dataset, std::int64_t first, std::int64_t rows,
                             hid_t memoryType, const void* values);

/// Sets /VTKHDF/Steps' NSteps of `file` (borrowed) to `steps`: readers see the
/// step from then on.
std::string writeNumberOfSteps(hid_t file, std::int64_t steps);

} // namespace canopy::io
