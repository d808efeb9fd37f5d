// What the ranks of a VTKHDF writer gather about a step before touching the
// file: each rank's piece counts, hence how many rows every dataset grows by,
// where each rank writes within them, and whether the step fits on the disk.
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

class vtkDataArray;
class vtkHyperTreeGrid;

namespace canopy::io
{

struct HyperTreeGridPiece;

/// What a dataset of the series grows by each step, per piece.
enum class Kind
{
  PerPiece,        // NumberOfTrees, NumberOfCells, NumberOfDepths, DescriptorsSize
  PerTree,         // TreeIds, DepthPerTree
  PerDepth,        // NumberOfCellsPerTreeDepth
  DescriptorBytes, // Descriptors: each piece from a new byte
  MaskBytes,       // Mask: likewise
  Coordinate,      // X/Y/ZCoordinates: one copy of the axis per piece
  PerCell          // CellData/<name>
};

/// What one rank tells every other about its piece of a step. Plain data: the
/// ranks gather it as it is.
struct PieceCounts
{
  std::int64_t trees = 0;
  std::int64_t cells = 0;
  std::int64_t depths = 0;
  std::int64_t descriptorBits = 0;
  std::int64_t branchFactor = 2;
  std::array<std::int64_t, 3> dimensions = {1, 1, 1};
  std::int64_t dataBytes = 0; // what the piece adds to the file
};
static_assert(std::is_trivially_copyable_v<PieceCounts>, "gathered as its bytes");

/// Sizes of everything a step adds, over all ranks, and this rank's offsets within it.
struct StepShape
{
  int rank = 0;
  std::vector<PieceCounts> pieces; // one per rank, in rank order
  std::array<std::int64_t, 3> dimensions = {1, 1, 1};
  std::int64_t dataBytes = 0; // the step's data, all ranks

  static std::int64_t bytes(std::int64_t bits) { return (bits + 7) / 8; }
  int numberOfPieces() const { return static_cast<int>(this->pieces.size()); }
  const PieceCounts& mine() const { return this->pieces[static_cast<std::size_t>(this->rank)]; }
  /// Rows a dataset of `kind` grows by (axis: the coordinate axis).
  std::int64_t total(Kind kind, int axis = 0) const
  {
    return this->prefix(kind, this->numberOfPieces(), axis);
  }
  /// Rows of the ranks before `rank`: where that rank writes within the step.
  std::int64_t prefix(Kind kind, int rank, int axis = 0) const;
  /// Rows of rank `r`'s piece in a dataset of `kind`.
  std::int64_t rows(Kind kind, int r, int axis = 0) const;
  /// True when every rank's grid has this rank's branch factor and dimensions.
  bool gridsMatch() const;
};

/// This rank's counts: `piece` of `htg` (borrowed, not null), writing `arrays`.
PieceCounts countPiece(const HyperTreeGridPiece& piece, vtkHyperTreeGrid* htg,
                       const std::vector<vtkDataArray*>& arrays);

/// Every rank's counts. Collective over `communicator` (MPI_COMM_NULL: one process).
StepShape gatherStepShape(MPI_Comm communicator, const PieceCounts& mine);

/// Why a step of `bytes` bytes will not fit where `file` goes ("" if it will):
/// the data, 5 % for chunks a step leaves partly filled, 2 MiB for metadata.
std::string freeSpaceProblem(const std::string& file, std::int64_t bytes);

} // namespace canopy::io
