// A cell array's values in file order, handed to a writer block by block with
// as little copying as the array's memory allows:
//  - an array of structures (VTK's default arrays, and Canopy's fields wrapped
//    in place) over one run of cells is handed over from its own memory: zero copy;
//  - anything else (Canopy's arrays that read the simulation's memory through a
//    cell -> slot table, strided or structure-of-arrays fields, cells out of
//    order) goes through one staging buffer of bounded size (1 MiB by default),
//    filled by typed reads, never a copy of the whole array.
#pragma once

#include "CanopyIOModule.h"
#include <canopy/io/HyperTreeGridPiece.h>

#include <cstddef>
#include <functional>
#include <vector>

class vtkDataArray;

namespace canopy::io
{

class CANOPYIO_EXPORT CellArrayBlocks
{
public:
  /// A writer of consecutive tuples, in file order.
  using Sink = std::function<void(const void* values, vtkIdType tuples)>;

  CellArrayBlocks(vtkDataArray* array, const std::vector<CellRun>& runs,
                  std::size_t stagingBytes = std::size_t(1) << 20);

  /// Calls `sink` for consecutive blocks until every run was handed over.
  void forEach(const Sink& sink) const;

private:
  vtkDataArray* Array;
  const std::vector<CellRun>& Runs;
  std::size_t StagingBytes;
};

} // namespace canopy::io
