// The hypertree-grid extract ParaView 5.11 opens, written by every rank of a
// run: for each step, one .htg piece per rank (HtgFileWriter), a multiblock
// file listing the pieces as one dataset, and a .pvd time series of every step
// written so far.
//
//   <name>.pvd                               the series (open this for all steps)
//   <name>_<step>.vtm                        one step, every rank's piece
//   <name>_<step>/<name>_<step>_<rank>.htg   the pieces
//
// Why this form: ParaView 5.11's .phtg reader (VTK 9.2) crashes, its .htg
// writer loses vectors; its multiblock (.vtm) and .pvd readers take .htg
// blocks, so pieces from any number of ranks open as one dataset or one
// time series (docs/insitu.md).
#pragma once

#include "CanopyIOModule.h"
#include <canopy/io/WriteError.h>

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

class vtkHyperTreeGrid;

namespace canopy::io
{

class CANOPYIO_EXPORT HtgSeriesWriter
{
public:
  /// `seriesFile` is the .pvd path; the other files go next to it. `arrays`:
  /// the cell arrays to write (empty: all). `communicator` MPI_COMM_NULL: one
  /// process without MPI.
  HtgSeriesWriter(MPI_Comm communicator, std::string seriesFile,
                  std::vector<std::string> arrays = {});

  /// Writes this rank's piece of step `step` at `time`, then (rank 0) the step's
  /// .vtm and the .pvd. Collective. Throws WriteError on every rank when any rank
  /// failed; the step is then not in the series and its pieces are removed.
  void writeStep(vtkHyperTreeGrid* htg, std::int64_t step, double time);

  /// Steps in the series so far (this writer's).
  std::size_t numberOfSteps() const { return this->Steps.size(); }

  /// The file names of a step, relative to the series' folder.
  std::string stepFileName(std::int64_t step) const;
  std::string pieceFileName(std::int64_t step, int rank) const;

private:
  struct Entry
  {
    std::int64_t step;
    double time;
  };

  MPI_Comm Communicator;
  std::string Folder;
  std::string Name;
  std::vector<std::string> Arrays;
  std::vector<Entry> Steps;
};

} // namespace canopy::io
