// The per-tree layout a validation establishes (internal to Canopy::forest):
// everything a build needs to know about the shape of the forest, computed once
// so the builder never re-walks the refinement bytes to find sizes. The public
// face of the same pass is canopy/ForestValidation.h (validateForest, counts only).
#pragma once

#include <canopy/ForestValidation.h>

#include <array>
#include <cstddef>
#include <vector>

namespace canopy
{

struct ValidatedTrees;

/// Shape of one validated tree.
struct TreeLayout
{
  std::size_t numberOfNodes = 0;  ///< every described node, absent ones included
  std::size_t numberOfLeaves = 0; ///< every described leaf, absent ones included
  /// Nodes and leaves that are not absent: what the simulation's arrays hold.
  std::size_t numberOfPresentNodes = 0;
  std::size_t numberOfPresentLeaves = 0;
  /// Nodes above the deepest level: the bits VTK's breadth-first descriptor needs.
  /// Like `levels` and `cells`, of the grid's tree: in a block forest, with the
  /// cells of its blocks (BlockValidation.h).
  std::size_t descriptorBits = 0;
  int levels = 0;
  /// Cells of the grid's tree: numberOfNodes, or in a block forest its described
  /// nodes plus the cells below its blocks' roots.
  std::size_t cells = 0;
  /// Block forests: present leaves, each a block.
  std::size_t blocks = 0;
  /// First storage slot when slots are implicit (present nodes breadth-first, trees
  /// back to back).
  std::size_t firstSlot = 0;
  /// First cell (VTK global index) of the tree when cells are numbered breadth-first
  /// over every described node (forests with absent nodes).
  std::size_t firstCell = 0;
};

/// Shape of a validated forest.
struct ForestLayout
{
  std::vector<TreeLayout> trees; ///< same order as ForestDescription::trees
  std::size_t totalNodes = 0;    ///< every described node
  std::size_t totalCells = 0;    ///< cells of the grid: totalNodes, or with blocks' cells
  std::size_t totalBlocks = 0;   ///< block forests: present leaves, each a block
  int blockLevels = 0;           ///< block forests: levels of cells below a block's root
  std::size_t totalLeaves = 0;
  std::size_t totalPresentNodes = 0;  ///< tuples an every-node field holds
  std::size_t totalPresentLeaves = 0; ///< tuples a leaves-only field holds
  std::size_t totalDescriptorBits = 0;
  bool explicitSlots = false;
  bool anyMask = false;
  bool anyAbsent = false;
  std::array<std::size_t, 3> rootCells{{0, 0, 0}}; ///< root cells per axis (1 on a flat axis)
  std::size_t numberOfRootCells = 0;
};

/// Validates `forest` as validateForest does (throws InvalidForest) and returns its
/// layout. With `known` (GridBuilder: trees unchanged since an earlier build),
/// the trees it marks unchanged are taken as valid with their earlier shape
/// (ValidatedTrees.h). `known` is only read during the call.
ForestLayout layoutForest(const ForestDescription& forest, const ValidatedTrees* known = nullptr);

} // namespace canopy
