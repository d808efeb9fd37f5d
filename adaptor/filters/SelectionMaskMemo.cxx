#include "SelectionMaskMemo.h"

#include "ByteHash.h"

#include <vtkBitArray.h>
#include <vtkHyperTree.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <cstring>

namespace canopy
{

SelectionMaskMemo::TreeKey SelectionMaskMemo::keyOf(const HyperTreeAccess& grid,
                                                    const TreeAccess& tree)
{
  TreeKey key;
  key.topology = treeTopologyKey(grid, tree);
  key.box = hashBytes(tree.size.data(), sizeof(tree.size),
                      hashBytes(tree.origin.data(), sizeof(tree.origin), 0x5E1EC7ull));
  return key;
}

void SelectionMaskMemo::begin(const HyperTreeAccess& grid, std::uint64_t selection,
                              bool readsByCellNumber)
{
  const auto& trees = grid.trees();
  const bool sameSelection = selection == Selection;
  // Last execution's entries by tree index (the grid's trees come in index order).
  std::vector<TreeEntry> last = std::move(Current);
  Current.assign(trees.size(), TreeEntry());
  Kept.assign(trees.size(), 0);
  KeptTrees = 0;
  RecomputedNodes = 0;
  std::size_t l = 0;
  for (std::size_t t = 0; t < trees.size(); ++t)
  {
    TreeEntry& entry = Current[t];
    entry.key = keyOf(grid, trees[t]);
    while (l < last.size() && last[l].key.topology.index < entry.key.topology.index)
    {
      ++l;
    }
    const bool found = l < last.size() && last[l].key.topology.index == entry.key.topology.index;
    if (sameSelection && found && entry.key.topology.firstCell >= 0 &&
        entry.key.sameFlags(last[l].key, readsByCellNumber))
    {
      entry.flags = std::move(last[l].flags);
      Kept[t] = 1;
      ++KeptTrees;
    }
    else
    {
      RecomputedNodes += static_cast<std::size_t>(trees[t].numberOfVertices);
    }
  }
  Selection = selection;
}

namespace
{

/// Per cell: bit 0 visible, bit 1 pure; packed eight cells a byte, most
/// significant bit first (vtkBitArray's order). `flagsOf(cell)`.
template <typename FlagsOf>
void packBytes(vtkIdType cells, unsigned char* maskBits, unsigned char* pureBits,
               const FlagsOf& flagsOf)
{
  vtkSMPTools::For(0, (cells + 7) / 8,
                   [&](vtkIdType begin, vtkIdType end)
                   {
                     for (vtkIdType byte = begin; byte < end; ++byte)
                     {
                       unsigned char masked = 0;
                       unsigned char pure = 0;
                       for (vtkIdType bit = 0; bit < 8; ++bit)
                       {
                         const vtkIdType cell = 8 * byte + bit;
                         const unsigned char flags = cell < cells ? flagsOf(cell) : 2;
                         masked = static_cast<unsigned char>(masked | (!(flags & 1) << (7 - bit)));
                         pure =
                             static_cast<unsigned char>(pure | (((flags >> 1) & 1) << (7 - bit)));
                       }
                       maskBits[byte] = masked;
                       pureBits[byte] = pure;
                     }
                   });
}

void setBit(unsigned char* bits, vtkIdType cell, bool on)
{
  const auto bit = static_cast<unsigned char>(1u << (7 - (cell & 7)));
  bits[cell >> 3] = static_cast<unsigned char>(on ? bits[cell >> 3] | bit : bits[cell >> 3] & ~bit);
}

} // namespace

void SelectionMaskMemo::pack(const HyperTreeAccess& grid, vtkSmartPointer<vtkBitArray>& mask,
                             vtkSmartPointer<vtkBitArray>& pure)
{
  const auto& trees = grid.trees();
  const vtkIdType cells = grid.numberOfCells();
  std::vector<std::array<vtkIdType, 3>> ranges(trees.size());
  bool patch = LastCells == cells && cells >= 0 && LastRanges.size() == trees.size();
  for (std::size_t t = 0; t < trees.size(); ++t)
  {
    const TreeAccess& tree = trees[t];
    ranges[t] = {{tree.treeIndex, tree.implicitGlobalIndex ? tree.globalIndexStart : -1,
                  tree.numberOfVertices}};
    // Every tree's cells where they were: the redone trees' bits are then all
    // that differs (cells of no tree keep theirs).
    patch = patch && ranges[t][1] >= 0 && ranges[t] == LastRanges[t];
  }
  // The packed bits are kept in the memo's own buffers (a consumer could write
  // the output's arrays), patched or packed there, then copied out.
  const auto bytes = static_cast<std::size_t>((cells + 7) / 8);
  if (patch)
  {
    for (std::size_t t = 0; t < trees.size(); ++t)
    {
      if (Kept[t])
      {
        continue;
      }
      const std::vector<unsigned char>& flags = Current[t].flags.flags;
      const vtkIdType first = trees[t].globalIndexStart;
      for (vtkIdType n = 0; n < trees[t].numberOfVertices; ++n)
      {
        const unsigned char f = flags[static_cast<std::size_t>(n)];
        setBit(LastMask.data(), first + n, !(f & 1));
        setBit(LastPure.data(), first + n, (f & 2) != 0);
      }
    }
  }
  else
  {
    // Cells of no tree stay masked.
    std::vector<unsigned char> byCell(static_cast<std::size_t>(cells), 0);
    for (std::size_t t = 0; t < trees.size(); ++t)
    {
      const TreeAccess& tree = trees[t];
      const std::vector<unsigned char>& flags = Current[t].flags.flags;
      if (tree.implicitGlobalIndex)
      {
        std::copy(flags.begin(), flags.end(),
                  byCell.begin() + static_cast<std::ptrdiff_t>(tree.globalIndexStart));
        continue;
      }
      for (vtkIdType n = 0; n < tree.numberOfVertices; ++n)
      {
        byCell[static_cast<std::size_t>(tree.globalIndex(n))] = flags[static_cast<std::size_t>(n)];
      }
    }
    LastMask.assign(bytes, 0);
    LastPure.assign(bytes, 0);
    packBytes(cells, LastMask.data(), LastPure.data(),
              [&](vtkIdType cell) { return byCell[static_cast<std::size_t>(cell)]; });
  }
  LastCells = cells;
  LastRanges = std::move(ranges);
  mask = vtkSmartPointer<vtkBitArray>::New();
  mask->SetName("vtkHyperTreeGridMask");
  pure = vtkSmartPointer<vtkBitArray>::New();
  mask->SetNumberOfValues(cells);
  pure->SetNumberOfValues(cells);
  if (bytes > 0)
  {
    std::memcpy(mask->GetPointer(0), LastMask.data(), bytes);
    std::memcpy(pure->GetPointer(0), LastPure.data(), bytes);
  }
  mask->Modified();
  pure->Modified();
}

void SelectionMaskMemo::clear()
{
  *this = SelectionMaskMemo();
}

} // namespace canopy
