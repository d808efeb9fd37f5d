#include "SelectionMaskMemo.h"

#include "ByteHash.h"

#include <vtkBitArray.h>
#include <vtkHyperTree.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <cstring>

namespace canopy
{

namespace
{

/// Hash of the bits [from, to) of a vtkBitArray's packed bits (most significant
/// first), realigned so that bit `from` leads: the same bits hash the same
/// wherever they start.
std::uint64_t hashBits(const unsigned char* bits, vtkIdType from, vtkIdType to, std::uint64_t seed)
{
  if (to <= from)
  {
    return hashBytes(nullptr, 0, seed);
  }
  const vtkIdType count = to - from;
  std::vector<unsigned char> aligned(static_cast<std::size_t>((count + 7) / 8));
  const unsigned char* p = bits + from / 8;
  const int shift = static_cast<int>(from % 8);
  const vtkIdType lastByte = (to - 1) / 8 - from / 8; // of the source, relative to p
  for (std::size_t i = 0; i < aligned.size(); ++i)
  {
    const auto k = static_cast<vtkIdType>(i);
    const unsigned int high = p[k];
    const unsigned int low = k + 1 <= lastByte ? p[k + 1] : 0;
    aligned[i] = static_cast<unsigned char>(((high << 8 | low) >> (8 - shift)) & 0xFF);
  }
  // Bits past `to` in the last byte are another tree's: cleared.
  const int used = static_cast<int>(count % 8);
  if (used != 0)
  {
    aligned.back() = static_cast<unsigned char>(aligned.back() & (0xFF00u >> used));
  }
  return hashBytes(aligned.data(), aligned.size(), seed);
}

} // namespace

bool SelectionMaskMemo::TreeKey::sameFlags(const TreeKey& o, bool numbering) const
{
  return index == o.index && tree == o.tree && treeTime == o.treeTime && vertices == o.vertices &&
         (!numbering || firstCell == o.firstCell) && elderChild == o.elderChild &&
         elderChildSize == o.elderChildSize && box == o.box && marks == o.marks;
}

SelectionMaskMemo::TreeKey SelectionMaskMemo::keyOf(const HyperTreeAccess& grid,
                                                    const TreeAccess& tree)
{
  TreeKey key;
  key.index = tree.treeIndex;
  key.tree = tree.tree;
  key.treeTime = tree.tree ? tree.tree->GetMTime() : 0;
  key.vertices = tree.numberOfVertices;
  key.firstCell = tree.implicitGlobalIndex ? tree.globalIndexStart : -1;
  // The child table by where it lives and the vertex count, as
  // HyperTreeAccessCache keys it: VTK 9.2 only refines a tree in place
  // (SubdivideLeaf adds vertices), never coarsens one.
  key.elderChild = tree.elderChild;
  key.elderChildSize = tree.elderChildSize;
  key.box = hashBytes(tree.size.data(), sizeof(tree.size),
                      hashBytes(tree.origin.data(), sizeof(tree.origin), 0x5E1EC7ull));
  if (key.firstCell < 0)
  {
    return key;
  }
  // The cells' marks, wherever the tree's cells are numbered: its own mask bits
  // (realigned to start on a byte) and its ghost marks.
  const vtkIdType first = key.firstCell;
  const vtkIdType end = first + tree.numberOfVertices;
  std::uint64_t marks = 0x3A5Cull;
  if (const unsigned char* bits = grid.maskBits())
  {
    marks = hashBits(bits, std::min(first, grid.maskSize()), std::min(end, grid.maskSize()), marks);
  }
  if (const unsigned char* ghosts = grid.ghostMarks())
  {
    const vtkIdType from = std::min(first, grid.ghostMarkCount());
    const vtkIdType to = std::min(end, grid.ghostMarkCount());
    marks = hashBytes(ghosts + from, static_cast<std::size_t>(to - from), marks);
  }
  key.marks = marks;
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
    while (l < last.size() && last[l].key.index < entry.key.index)
    {
      ++l;
    }
    const bool found = l < last.size() && last[l].key.index == entry.key.index;
    if (sameSelection && found && entry.key.firstCell >= 0 &&
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
