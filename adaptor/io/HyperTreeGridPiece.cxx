#include <canopy/io/HyperTreeGridPiece.h>

#include <vtkBitArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>

#include <algorithm>
#include <limits>
#include <utility>

namespace canopy::io
{

void PackedBits::truncate(std::int64_t size)
{
  if (size >= this->Size)
  {
    return;
  }
  this->Size = size;
  this->Bytes.resize(static_cast<std::size_t>((size + 7) / 8));
  if ((size & 7) != 0)
  {
    // Trailing bits of the last byte must read as zeros.
    this->Bytes.back() &= static_cast<unsigned char>(0xFFu << (8 - (size & 7)));
  }
}

PackedBits PackedBits::slice(std::int64_t first, std::int64_t count) const
{
  PackedBits part;
  part.Bytes.reserve(static_cast<std::size_t>((count + 7) / 8));
  for (std::int64_t i = 0; i < count; ++i)
  {
    part.push(this->get(first + i));
  }
  return part;
}

namespace
{

struct TreeEntry
{
  vtkIdType index;
  vtkHyperTree* tree;
  vtkIdType firstCell;
};

/// Appends a cell to the runs, extending the last run when it follows it.
void appendCell(std::vector<CellRun>& runs, vtkIdType cell)
{
  if (!runs.empty() && runs.back().first + runs.back().count == cell)
  {
    ++runs.back().count;
    return;
  }
  runs.push_back({cell, 1});
}

} // namespace

HyperTreeGridPiece HyperTreeGridPiece::describe(vtkHyperTreeGrid* htg)
{
  HyperTreeGridPiece piece;
  if (htg == nullptr)
  {
    return piece;
  }
  std::vector<TreeEntry> trees;
  vtkHyperTreeGrid::vtkHyperTreeGridIterator iterator;
  htg->InitializeTreeIterator(iterator);
  vtkIdType index = 0;
  while (vtkHyperTree* tree = iterator.GetNextTree(index))
  {
    trees.push_back({index, tree, tree->GetGlobalIndexFromLocal(0)});
  }
  // Memory order: Canopy numbers cells tree by tree, so this is its trees' order.
  std::sort(trees.begin(), trees.end(),
            [](const TreeEntry& a, const TreeEntry& b) { return a.firstCell < b.firstCell; });

  vtkBitArray* mask = htg->HasMask() ? htg->GetMask() : nullptr;
  const unsigned int children = htg->GetNumberOfChildren();
  constexpr unsigned int noChild = std::numeric_limits<unsigned int>::max();
  std::vector<vtkIdType> order;     // local index of each breadth-first position
  std::vector<char> maskedAncestor; // per breadth-first position
  for (const TreeEntry& entry : trees)
  {
    vtkHyperTree* tree = entry.tree;
    const vtkIdType vertices = tree->GetNumberOfVertices();
    std::size_t elderCount = 0;
    const unsigned int* elder = tree->GetElderChildIndexArray(elderCount);
    // VTK 9.2's IsGlobalIndexImplicit() answers the opposite of its name; the
    // start is reliable: -1 means a per-node table.
    const vtkIdType start = tree->GetGlobalIndexStart();
    const bool implicit = start >= 0;

    piece.treeIds.push_back(entry.index);
    piece.treeDescriptorStart.push_back(piece.descriptors.size());
    piece.treeCellStart.push_back(piece.numberOfCells);
    order.assign(1, 0);
    order.reserve(static_cast<std::size_t>(vertices));
    maskedAncestor.assign(1, 0);
    std::size_t levelEnd = 1;
    std::int64_t levelCells = 0;
    std::int64_t depth = 0;
    std::int64_t lastLevelCells = 0;
    for (std::size_t position = 0; position < order.size(); ++position)
    {
      const vtkIdType local = order[position];
      const vtkIdType cell = implicit ? start + local : tree->GetGlobalIndexFromLocal(local);
      const auto slot = static_cast<std::size_t>(local);
      // As VTK's compact tree decides, guarded: a single-vertex tree is a leaf
      // whatever its table says (a fresh tree keeps a 0 there), and an entry
      // pointing past the tree's vertices is never followed.
      const bool refined = vertices > 1 && slot < elderCount && elder[slot] != noChild &&
                           elder[slot] != 0 &&
                           static_cast<vtkIdType>(elder[slot]) + children <= vertices;
      const bool masked = mask != nullptr && mask->GetValue(cell) != 0;
      const bool hidden = masked || maskedAncestor[position] != 0;
      piece.descriptors.push(refined);
      if (mask != nullptr)
      {
        piece.mask.push(masked);
      }
      piece.leafMask.push(hidden && !refined);
      appendCell(piece.runs, cell);
      if (refined)
      {
        for (unsigned int c = 0; c < children; ++c)
        {
          order.push_back(static_cast<vtkIdType>(elder[slot]) + c);
          maskedAncestor.push_back(hidden ? 1 : 0);
        }
      }
      else
      {
        ++piece.numberOfLeaves;
      }
      ++levelCells;
      if (position + 1 == levelEnd)
      {
        piece.cellsPerTreeDepth.push_back(levelCells);
        lastLevelCells = levelCells;
        ++depth;
        levelCells = 0;
        levelEnd = order.size();
      }
    }
    // The deepest level is all leaves: VTK's descriptors leave it out.
    piece.descriptors.truncate(piece.descriptors.size() - lastLevelCells);
    piece.depthPerTree.push_back(depth);
    piece.numberOfCells += static_cast<std::int64_t>(order.size());
  }
  return piece;
}

std::vector<CellRun> HyperTreeGridPiece::runsAt(std::int64_t first, std::int64_t count) const
{
  std::vector<CellRun> part;
  std::int64_t position = 0; // file position of the current run's first cell
  for (const CellRun& run : this->runs)
  {
    const std::int64_t begin = std::max<std::int64_t>(first, position);
    const std::int64_t end = std::min<std::int64_t>(first + count, position + run.count);
    if (begin < end)
    {
      part.push_back({run.first + (begin - position), end - begin});
    }
    position += run.count;
    if (position >= first + count)
    {
      break;
    }
  }
  return part;
}

} // namespace canopy::io
