// A rank's hypertree grid as both file formats store it: its trees one after
// another (ordered by the global index of their root, so a grid whose cells
// are numbered breadth-first tree by tree, as Canopy builds them, is read in
// its own memory order), each tree breadth-first.
//
// Every writer starts from this description: refinement descriptors, cells per
// depth, masks and, for the fields, which cell (VTK global index) comes at each
// position in the file, as runs of consecutive global indices.
#pragma once

#include "CanopyIOModule.h"

#include <vtkType.h>

#include <cstdint>
#include <vector>

class vtkHyperTreeGrid;

namespace canopy::io
{

/// Cells first .. first + count - 1 (VTK global indices), consecutive in the file.
struct CellRun
{
  vtkIdType first = 0;
  vtkIdType count = 0;
};

/// Bits packed as VTK's vtkBitArray and the VTKHDF format pack them: the first
/// value in the most significant bit of the first byte.
class CANOPYIO_EXPORT PackedBits
{
public:
  void push(bool value)
  {
    if ((this->Size & 7) == 0)
    {
      this->Bytes.push_back(0);
    }
    if (value)
    {
      this->Bytes.back() |= static_cast<unsigned char>(0x80u >> (this->Size & 7));
    }
    ++this->Size;
  }
  bool get(std::int64_t index) const
  {
    return (this->Bytes[static_cast<std::size_t>(index >> 3)] & (0x80u >> (index & 7))) != 0;
  }
  /// Drops values from `size` on (the bytes keep the remaining bits, the rest zero).
  void truncate(std::int64_t size);
  /// Bits first .. first + count - 1 repacked from bit 0.
  PackedBits slice(std::int64_t first, std::int64_t count) const;
  std::int64_t size() const { return this->Size; }
  const std::vector<unsigned char>& bytes() const { return this->Bytes; }

private:
  std::vector<unsigned char> Bytes;
  std::int64_t Size = 0;
};

struct CANOPYIO_EXPORT HyperTreeGridPiece
{
  /// Root index of each tree, in file order.
  std::vector<std::int64_t> treeIds;
  /// Levels of each tree (a leaf root has one).
  std::vector<std::int64_t> depthPerTree;
  /// For each tree in turn, its number of cells at each level.
  std::vector<std::int64_t> cellsPerTreeDepth;
  /// Refinement, one bit per cell, trees back to back, each without its deepest
  /// level (all leaves): what VTKHDF's Descriptors holds for a piece.
  PackedBits descriptors;
  /// Where each tree's descriptor bits start in `descriptors`, and its cells in file order.
  std::vector<std::int64_t> treeDescriptorStart;
  std::vector<std::int64_t> treeCellStart;
  /// The grid's mask in file order (empty when the grid has none).
  PackedBits mask;
  /// The same mask with masked refined cells pushed down to their leaves, as the
  /// VTKHDF specification requires ("a refined cell cannot be masked"): a leaf is
  /// masked when it or any ancestor is, a refined cell never. Shows the same cells.
  PackedBits leafMask;
  /// The cells in file order.
  std::vector<CellRun> runs;
  std::int64_t numberOfCells = 0;
  std::int64_t numberOfLeaves = 0;

  /// Walks every tree of `htg` once. A null grid is an empty piece.
  static HyperTreeGridPiece describe(vtkHyperTreeGrid* htg);

  std::int64_t numberOfTrees() const { return static_cast<std::int64_t>(this->treeIds.size()); }
  std::int64_t numberOfDepths() const
  {
    return static_cast<std::int64_t>(this->cellsPerTreeDepth.size());
  }
  /// The cells at file positions first .. first + count - 1, as runs.
  std::vector<CellRun> runsAt(std::int64_t first, std::int64_t count) const;
  /// True when the file order is the grid's own order from its first cell on:
  /// arrays are then written straight from their memory.
  bool contiguous() const { return this->runs.size() <= 1; }
};

} // namespace canopy::io
