// Where a rank's rows of a VTKHDF step go. One process writes the file (rank 0
// of the writer's communicator; StepRollback.h says why): it writes its own
// piece's rows and then every other rank's, in rank order, as they arrive;
// the other ranks send theirs. Rows are addressed by the layout's series (its
// datasets under /VTKHDF in order) and the row within the sending rank's piece;
// rank 0 places them at the rank's offset within the step (StepShape).
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace canopy::io
{

class VtkHdfLayout;
struct StepShape;

/// Takes rows of one rank's piece. put() returns "" or what went wrong.
class RowSink
{
public:
  virtual ~RowSink() = default;
  /// `rows` rows of `columns` values of VTK type `vtkType` from `values`
  /// (borrowed for the call), at row `first` of the piece's rows in the layout's
  /// series `series`.
  virtual std::string put(std::size_t series, std::int64_t first, std::int64_t rows, int vtkType,
                          int columns, const void* values) = 0;
};

/// Rank 0: writes rank `from`'s rows into `layout`'s open datasets.
class WrittenRows : public RowSink
{
public:
  /// `layout` and `shape` are borrowed for the sink's life.
  WrittenRows(VtkHdfLayout& layout, const StepShape& shape, int from);
  std::string put(std::size_t series, std::int64_t first, std::int64_t rows, int vtkType,
                  int columns, const void* values) override;

private:
  VtkHdfLayout& Layout;
  const StepShape& Shape;
  int From;
};

/// The other ranks: sends the rows to rank 0 of `communicator` (which must be
/// one only the writer uses: its messages carry no step number).
class SentRows : public RowSink
{
public:
  explicit SentRows(MPI_Comm communicator) : Communicator(communicator) {}
  std::string put(std::size_t series, std::int64_t first, std::int64_t rows, int vtkType,
                  int columns, const void* values) override;
  /// Tells rank 0 this rank has sent all its rows. Always called once, last.
  void finish();

private:
  MPI_Comm Communicator;
};

/// Rank 0: takes rank `from`'s messages until it has finished, putting them
/// into `sink` while nothing has gone wrong (after a problem, the rest are
/// received and dropped, so the sender never waits forever). "" or the first problem.
std::string receiveRows(MPI_Comm communicator, int from, RowSink& sink);

} // namespace canopy::io
