// The filters' one rule for what changed (see TopologyKeys.h).
#include "TopologyKeys.h"

#include "ByteHash.h"
#include "TopologyStamp.h"

#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkFieldData.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <optional>

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

/// A stamped marks revision never equals a fingerprint: fingerprints have the
/// top bit set, revisions (build counts) never do.
constexpr std::uint64_t FingerprintBit = 1ull << 63;

} // namespace

bool GridTopologyKey::operator==(const GridTopologyKey& o) const
{
  return grid == o.grid && gridTime == o.gridTime && shape == o.shape && mask == o.mask &&
         maskTime == o.maskTime && maskBits == o.maskBits && maskSize == o.maskSize &&
         ghosts == o.ghosts && ghostTime == o.ghostTime && ghostValues == o.ghostValues &&
         cells == o.cells;
}

GridTopologyKey gridTopologyKey(vtkHyperTreeGrid* grid, std::vector<TreeTopologyKey>& trees)
{
  GridTopologyKey key;
  key.grid = grid;
  key.cells = grid->GetNumberOfCells();
  // The grid's shape, by value: a simulation's builder may hand the same
  // coordinates in new array objects at every step.
  const unsigned int* dims = grid->GetDimensions();
  std::uint64_t shape = hashCombine(0x7A11ull, grid->GetDimension());
  shape = hashCombine(shape, grid->GetBranchFactor());
  shape = hashCombine(shape, grid->GetTransposedRootIndexing() ? 1 : 0);
  shape = hashBytes(dims, 3 * sizeof(unsigned int), shape);
  for (vtkDataArray* axis :
       {grid->GetXCoordinates(), grid->GetYCoordinates(), grid->GetZCoordinates()})
  {
    for (vtkIdType i = 0; axis && i < axis->GetNumberOfTuples(); ++i)
    {
      const double value = axis->GetComponent(i, 0);
      shape = hashBytes(&value, sizeof value, shape);
    }
    shape = hashCombine(shape, axis ? static_cast<std::uint64_t>(axis->GetNumberOfTuples()) : 0);
  }
  if (vtkDataArray* flag = grid->GetFieldData()->GetArray(missingTreesElsewhereName()))
  {
    shape =
        hashCombine(shape, flag->GetNumberOfTuples() > 0 && flag->GetComponent(0, 0) != 0 ? 2 : 1);
  }
  key.shape = shape;
  if (vtkBitArray* mask = grid->HasMask() ? grid->GetMask() : nullptr)
  {
    key.mask = mask;
    key.maskTime = mask->GetMTime();
    key.maskSize = mask->GetNumberOfValues();
    key.maskBits = key.maskSize > 0 ? mask->GetPointer(0) : nullptr;
  }
  if (auto* ghosts = vtkUnsignedCharArray::SafeDownCast(
          grid->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName())))
  {
    key.ghosts = ghosts;
    key.ghostTime = ghosts->GetMTime();
    key.ghostValues = ghosts->GetNumberOfValues() > 0 ? ghosts->GetPointer(0) : nullptr;
  }
  const std::optional<TopologyStamp> stamp = readTopologyStamp(grid);
  trees.clear();
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  grid->InitializeTreeIterator(it);
  vtkIdType index = 0;
  while (vtkHyperTree* tree = it.GetNextTree(index))
  {
    TreeTopologyKey t;
    t.index = index;
    t.tree = tree;
    t.treeTime = tree->GetMTime();
    t.vertices = tree->GetNumberOfVertices();
    t.elderChild = tree->GetElderChildIndexArray(t.elderChildSize);
    t.firstCell = tree->GetGlobalIndexStart();
    if (const TreeStamp* vouched = stamp ? stamp->vouchedTree(index, tree) : nullptr)
    {
      t.builder = stamp->builder;
      t.topology = vouched->topology;
    }
    if (t.firstCell < 0)
    {
      // Explicit global indices: their tables are not compared, the grid's time is.
      key.gridTime = grid->GetMTime();
    }
    trees.push_back(t);
  }
  return key;
}

TreeTopologyKey treeTopologyKey(const HyperTreeAccess& grid, const TreeAccess& tree)
{
  TreeTopologyKey key;
  key.index = tree.treeIndex;
  key.tree = tree.tree;
  key.treeTime = tree.tree ? tree.tree->GetMTime() : 0;
  key.vertices = tree.numberOfVertices;
  key.elderChild = tree.elderChild;
  key.elderChildSize = tree.elderChildSize;
  key.firstCell = tree.implicitGlobalIndex ? tree.globalIndexStart : -1;
  key.builder = tree.stampBuilder;
  key.topology = tree.stampTopology;
  if (tree.stampMarks != 0)
  {
    key.marks = tree.stampMarks;
    return key;
  }
  if (key.firstCell < 0)
  {
    key.marks = FingerprintBit; // explicit indices: never kept (see SelectionMaskMemo.h)
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
  key.marks = marks | FingerprintBit;
  return key;
}

} // namespace canopy
