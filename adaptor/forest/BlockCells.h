// Where each cell of a block forest's grid is, without a table per cell.
//
// VTK numbers the cells of a tree built from a breadth-first descriptor level by
// level, and within a level in the lexicographic order of the paths from the
// root (a parent's children are consecutive, parents in order). A block's cells
// at one of its levels share the path of the block's root, so they are one
// consecutive run of bf^(d s) cells (s levels below the root), ordered by their
// path inside the block: base-bf^d digits, coarsest first, each digit the child
// index (x fastest). Every cell of the grid therefore lies in a run that is either
// consecutive described nodes (refined nodes, block roots, absent leaves: their
// breadth-first indices are consecutive too) or one block's cells at one level.
// The runs, found by one depth-first walk of the description (which visits each
// level in path order), are what this index keeps: O(blocks x block levels)
// entries, searched by cell. Checked cell by cell against the block arrays by
// tests/unit/BlockForestTest.cxx (and BlockForestFiltersTest.cxx).
#pragma once

#include "ForestLayout.h"
#include <canopy/ForestDescription.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace canopy
{

class BlockCells
{
public:
  /// Index of a validated block forest (layoutForest's layout of the same description).
  static BlockCells build(const ForestDescription& forest, const ForestLayout& layout);

  /// What a cell is: a described node (subLevel 0; block roots are described
  /// leaves), or the cell at `position` (per axis, 0 .. bf^subLevel - 1) of a
  /// block's level subLevel >= 1 (blockLevels() is its interior cells).
  struct Location
  {
    std::int64_t node = -1;  ///< described node (forest numbering), subLevel 0
    std::int64_t block = -1; ///< block (in the fields' block tables), subLevel >= 1
    int subLevel = 0;
    std::array<std::uint32_t, 3> position{{0, 0, 0}};
  };
  Location locate(std::uint64_t cell) const;

  /// Writes the grid's breadth-first descriptor bits (1 = refined) of cells
  /// [firstCell, firstCell + count) into `bits` from bit `bitOffset` on, MSB first
  /// as vtkBitArray stores them; the bits must start zeroed.
  void writeDescriptor(std::uint64_t firstCell, std::size_t count, unsigned char* bits,
                       std::size_t bitOffset) const;

  /// Described nodes are numbered tree by tree, breadth-first: firstNode(t) + n.
  std::size_t firstNode(std::size_t tree) const { return FirstNode[tree]; }
  std::size_t numberOfNodes() const { return NodeCell.size(); }
  std::uint64_t cellOfNode(std::size_t node) const { return NodeCell[node]; }
  /// The block a present described leaf is, or -1 (refined or absent nodes).
  std::int64_t blockOfNode(std::size_t node) const { return NodeBlock[node]; }
  /// First child of a refined described node (forest numbering), or -1.
  std::int64_t firstChildOfNode(std::size_t node) const { return NodeFirstChild[node]; }
  bool isAbsent(std::size_t node) const { return NodeFlags[node] & AbsentFlag; }
  bool isMasked(std::size_t node) const { return NodeFlags[node] & MaskedFlag; }

  std::size_t numberOfBlocks() const { return BlockNode.size(); }
  std::size_t nodeOfBlock(std::size_t block) const { return BlockNode[block]; }
  std::size_t numberOfCells() const { return TotalCells; }

  int dimension() const { return Dimension; }
  int branchFactor() const { return BranchFactor; }
  int blockLevels() const { return BlockLevels; }
  std::size_t cellsPerSide() const { return CellsPerSide; }
  std::size_t childrenPerNode() const { return Children; }

private:
  static constexpr std::uint8_t AbsentFlag = 1;
  static constexpr std::uint8_t MaskedFlag = 2;

  /// Runs, sorted by first cell (separate arrays: the search reads only the first).
  std::vector<std::uint64_t> RunCell;
  std::vector<std::int64_t> RunFirst; ///< first described node, or the block
  std::vector<std::int32_t> RunLevel; ///< 0: described nodes; s >= 1: block cells

  std::vector<std::size_t> FirstNode;
  std::vector<std::uint64_t> NodeCell;
  std::vector<std::int64_t> NodeBlock;
  std::vector<std::int64_t> NodeFirstChild;
  std::vector<std::uint8_t> NodeFlags;
  std::vector<std::size_t> BlockNode;

  int Dimension = 0;
  int BranchFactor = 0;
  int BlockLevels = 0;
  std::size_t CellsPerSide = 0;
  std::size_t Children = 0;
  std::size_t TotalCells = 0;
};

} // namespace canopy
