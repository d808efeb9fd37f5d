// Writes a run's hypertree grids into one VTKHDF file, every step after the
// other, as VTK's file-format documentation gives the HyperTreeGrid layout
// (VTKHDF 2.4, with the temporal "Steps" group); VTK 9.5+ and ParaView 6 read
// it with vtkHDFReader. Every rank's piece is one part of the step; rank 0
// writes the file, the other ranks send it their rows. A step that fails on
// any rank, at any write, is undone byte for byte: the file is left as it was
// before the step, and no rank waits on another (docs/insitu.md, "Grid extracts").
//
// Usable without Catalyst:
//
//   canopy::io::VtkHdfWriter writer(MPI_COMM_WORLD, "run/grid.vtkhdf");
//   for (...) { auto htg = canopy::buildHyperTreeGrid(forest); writer.writeStep(htg, step, time); }
//
// Fields are written from the grid's arrays: Canopy's zero-copy arrays over
// the simulation's memory go to HDF5 straight from there; arrays that read
// through a cell -> slot table go through a bounded staging buffer (see
// CellArrayBlocks.h). Masks follow the specification: refined cells are never
// masked, masked subtrees are masked at their leaves (HyperTreeGridPiece.h).
#pragma once

#include "CanopyIOModule.h"
#include <canopy/io/WriteError.h>

#include <mpi.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

class vtkHyperTreeGrid;

namespace canopy::io
{

struct VtkHdfWriterOptions
{
  /// Cell arrays to write; empty: every numeric cell array the first step has on
  /// any rank. vtkGhostType (Canopy's mark of other ranks' parts of split trees)
  /// is written whenever the first step has it.
  std::vector<std::string> arrays;
  /// Continue the file of an earlier run. Off: the first step replaces the file.
  bool append = false;
  /// Refuse a step that will not fit in the free space left, before touching the
  /// file. Off: the write is attempted and, if it fails, the step is undone.
  bool checkFreeSpace = true;
};

class CANOPYIO_EXPORT VtkHdfWriter
{
public:
  /// `communicator`: the ranks writing pieces (MPI_COMM_NULL: one process
  /// without MPI); it must stay valid while the writer lives (the first step
  /// duplicates it for the rows sent to rank 0). `fileName`: the .vtkhdf file
  /// (its folder must exist). Nothing is opened before the first step; the
  /// file is closed after each.
  VtkHdfWriter(MPI_Comm communicator, std::string fileName, VtkHdfWriterOptions options = {});
  ~VtkHdfWriter();
  VtkHdfWriter(const VtkHdfWriter&) = delete;
  VtkHdfWriter& operator=(const VtkHdfWriter&) = delete;

  /// Appends this rank's piece of `htg` (borrowed for the call only; null is an
  /// error reported like any other) as the file's next step, at `time`.
  /// Collective. `step` (the simulation's; -1: none) only labels messages (the
  /// argument order is HtgSeriesWriter::writeStep's). Throws WriteError on every
  /// rank if any rank failed (disk full or failing, unwritable folder, HDF5
  /// error, grids that do not match the file): the step is then not in the
  /// file, and the file is byte for byte what it was before the step (if the
  /// disk refuses even that, the next step tries again before writing).
  void writeStep(vtkHyperTreeGrid* htg, std::int64_t step, double time);

  /// Steps in the file after the last successful write.
  std::int64_t numberOfSteps() const;
  const std::string& fileName() const;

private:
  struct Implementation;
  std::unique_ptr<Implementation> Impl;
};

} // namespace canopy::io
