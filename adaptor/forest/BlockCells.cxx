#include "BlockCells.h"

#include "StorageSlots.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace canopy
{
namespace
{

/// A run found by the walk, positioned within its level.
struct LevelRun
{
  std::uint64_t position; ///< first cell of the run among the level's cells
  std::int64_t first;     ///< described node, or block
  std::int32_t subLevel;  ///< 0: described nodes
  std::uint64_t count;
};

/// Sets `count` bits from bit `from` on (MSB first, as vtkBitArray).
void setOnes(unsigned char* bits, std::size_t from, std::size_t count)
{
  while (count > 0 && (from & 7) != 0)
  {
    bits[from >> 3] |= static_cast<unsigned char>(0x80u >> (from & 7));
    ++from;
    --count;
  }
  std::memset(bits + (from >> 3), 0xFF, count >> 3);
  from += count & ~static_cast<std::size_t>(7);
  for (count &= 7; count > 0; --count, ++from)
  {
    bits[from >> 3] |= static_cast<unsigned char>(0x80u >> (from & 7));
  }
}

} // namespace

BlockCells BlockCells::build(const ForestDescription& forest, const ForestLayout& layout)
{
  BlockCells index;
  index.Dimension = forest.dimension;
  index.BranchFactor = forest.branchFactor;
  index.BlockLevels = layout.blockLevels;
  index.CellsPerSide = static_cast<std::size_t>(forest.blockCellsPerSide);
  index.Children = canopy::childrenPerNode(forest);
  index.TotalCells = layout.totalCells;
  const std::size_t children = index.Children;
  const int m = index.BlockLevels;

  index.NodeCell.assign(layout.totalNodes, 0);
  index.NodeBlock.assign(layout.totalNodes, -1);
  index.NodeFirstChild.assign(layout.totalNodes, -1);
  index.NodeFlags.assign(layout.totalNodes, 0);
  index.BlockNode.assign(layout.totalBlocks, 0);
  index.FirstNode.reserve(forest.trees.size());

  // Breadth-first: children, flags, and blocks (the present leaves, in blockIndex's
  // order or breadth-first tree by tree).
  std::size_t base = 0;
  std::int64_t nextBlock = 0;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    index.FirstNode.push_back(base);
    std::size_t nextChild = 1;
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
    {
      const bool absent = tree.absent && tree.absent[n];
      index.NodeFlags[base + n] = static_cast<std::uint8_t>(
          (absent ? AbsentFlag : 0) | (tree.masked && tree.masked[n] ? MaskedFlag : 0));
      if (absent)
      {
        continue;
      }
      if (tree.refinement[n])
      {
        index.NodeFirstChild[base + n] = static_cast<std::int64_t>(base + nextChild);
        nextChild += children;
        continue;
      }
      const std::int64_t block = tree.blockIndex ? tree.blockIndex[n] : nextBlock++;
      index.NodeBlock[base + n] = block;
      index.BlockNode[static_cast<std::size_t>(block)] = base + n;
    }
    base += tree.numberOfNodes;
  }

  // Depth-first, children in order: each level's cells come in path order, so a
  // run's position in its level is the count of that level's cells seen before it.
  std::vector<std::uint64_t> cellsPerSubLevel(static_cast<std::size_t>(m) + 1, 1);
  for (int s = 1; s <= m; ++s)
  {
    cellsPerSubLevel[static_cast<std::size_t>(s)] =
        cellsPerSubLevel[static_cast<std::size_t>(s) - 1] * children;
  }
  std::vector<std::vector<LevelRun>> runs;
  std::vector<std::uint64_t> seen;
  std::vector<std::pair<std::size_t, std::size_t>> stack; // (forest node, level)
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeLayout& shape = layout.trees[t];
    const auto levels = static_cast<std::size_t>(shape.levels);
    runs.assign(levels, {});
    seen.assign(levels, 0);
    stack.assign(1, {index.FirstNode[t], 0});
    while (!stack.empty())
    {
      const auto [node, level] = stack.back();
      stack.pop_back();
      std::vector<LevelRun>& here = runs[level];
      if (!here.empty() && here.back().subLevel == 0 &&
          here.back().position + here.back().count == seen[level] &&
          here.back().first + static_cast<std::int64_t>(here.back().count) ==
              static_cast<std::int64_t>(node))
      {
        ++here.back().count;
      }
      else
      {
        here.push_back({seen[level], static_cast<std::int64_t>(node), 0, 1});
      }
      ++seen[level];
      if (const std::int64_t block = index.NodeBlock[node]; block >= 0)
      {
        for (int s = 1; s <= m; ++s)
        {
          const std::size_t at = level + static_cast<std::size_t>(s);
          const std::uint64_t count = cellsPerSubLevel[static_cast<std::size_t>(s)];
          runs[at].push_back({seen[at], block, s, count});
          seen[at] += count;
        }
      }
      else if (const std::int64_t first = index.NodeFirstChild[node]; first >= 0)
      {
        for (std::size_t c = children; c-- > 0;)
        {
          stack.emplace_back(static_cast<std::size_t>(first) + c, level + 1);
        }
      }
    }
    std::uint64_t levelStart = shape.firstCell;
    for (std::size_t level = 0; level < levels; ++level)
    {
      for (const LevelRun& run : runs[level])
      {
        const std::uint64_t cell = levelStart + run.position;
        index.RunCell.push_back(cell);
        index.RunFirst.push_back(run.first);
        index.RunLevel.push_back(run.subLevel);
        for (std::uint64_t i = 0; run.subLevel == 0 && i < run.count; ++i)
        {
          index.NodeCell[static_cast<std::size_t>(run.first) + i] = cell + i;
        }
      }
      levelStart += seen[level];
    }
    if (levelStart != shape.firstCell + shape.cells)
    {
      throw std::logic_error("BlockCells: the walk found another number of cells than the layout");
    }
  }
  return index;
}

BlockCells::Location BlockCells::locate(std::uint64_t cell) const
{
  const auto it = std::upper_bound(this->RunCell.begin(), this->RunCell.end(), cell);
  const auto r = static_cast<std::size_t>(it - this->RunCell.begin()) - 1;
  std::uint64_t offset = cell - this->RunCell[r];
  Location where;
  where.subLevel = this->RunLevel[r];
  if (where.subLevel == 0)
  {
    where.node = this->RunFirst[r] + static_cast<std::int64_t>(offset);
    return where;
  }
  where.block = this->RunFirst[r];
  // The offset's base-children digits, finest last: each the child index, x fastest.
  const auto bf = static_cast<std::uint32_t>(this->BranchFactor);
  std::array<std::uint32_t, 3> position{{0, 0, 0}};
  std::uint32_t scale = 1;
  for (int s = 0; s < where.subLevel; ++s)
  {
    auto digit = static_cast<std::uint32_t>(offset % this->Children);
    offset /= this->Children;
    for (int a = 0; a < this->Dimension; ++a)
    {
      position[static_cast<std::size_t>(a)] += (digit % bf) * scale;
      digit /= bf;
    }
    scale *= bf;
  }
  where.position = position;
  return where;
}

void BlockCells::writeDescriptor(std::uint64_t firstCell, std::size_t count, unsigned char* bits,
                                 std::size_t bitOffset) const
{
  if (count == 0)
  {
    return;
  }
  const std::uint64_t end = firstCell + count;
  auto r = static_cast<std::size_t>(
      std::upper_bound(this->RunCell.begin(), this->RunCell.end(), firstCell) -
      this->RunCell.begin() - 1);
  for (; r < this->RunCell.size() && this->RunCell[r] < end; ++r)
  {
    const std::uint64_t runEnd =
        r + 1 < this->RunCell.size() ? std::min(this->RunCell[r + 1], end) : end;
    const std::uint64_t from = std::max(this->RunCell[r], firstCell);
    const std::size_t at = bitOffset + static_cast<std::size_t>(from - firstCell);
    const std::int32_t subLevel = this->RunLevel[r];
    if (subLevel == 0)
    {
      // Every present described node is refined in the grid: block roots have
      // their cells below them.
      const auto first = static_cast<std::size_t>(this->RunFirst[r]) +
                         static_cast<std::size_t>(from - this->RunCell[r]);
      for (std::uint64_t i = 0; i < runEnd - from; ++i)
      {
        if (!(this->NodeFlags[first + i] & AbsentFlag))
        {
          setOnes(bits, at + static_cast<std::size_t>(i), 1);
        }
      }
    }
    else if (subLevel < this->BlockLevels)
    {
      setOnes(bits, at, static_cast<std::size_t>(runEnd - from));
    }
  }
}

} // namespace canopy
