#include "HyperTreeAccessCache.h"

#include "ByteHash.h"

#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkFieldData.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkUnsignedCharArray.h>

namespace canopy
{

bool HyperTreeAccessCache::Key::operator==(const Key& o) const
{
  return grid == o.grid && gridTime == o.gridTime && shape == o.shape && mask == o.mask &&
         maskTime == o.maskTime && maskBits == o.maskBits && maskSize == o.maskSize &&
         ghosts == o.ghosts && ghostTime == o.ghostTime && ghostValues == o.ghostValues &&
         cells == o.cells && trees == o.trees;
}

HyperTreeAccessCache::Key HyperTreeAccessCache::keyOf(vtkHyperTreeGrid* grid)
{
  Key key;
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
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  grid->InitializeTreeIterator(it);
  vtkIdType index = 0;
  while (vtkHyperTree* tree = it.GetNextTree(index))
  {
    std::size_t size = 0;
    const unsigned int* elder = tree->GetElderChildIndexArray(size);
    const vtkIdType start = tree->GetGlobalIndexStart();
    key.trees.push_back(
        {index, tree, tree->GetMTime(), tree->GetNumberOfVertices(), elder, size, start});
    if (start < 0)
    {
      // Explicit global indices: their tables are not compared, the grid's time is.
      key.gridTime = grid->GetMTime();
    }
  }
  return key;
}

std::shared_ptr<const HyperTreeAccess>
HyperTreeAccessCache::get(vtkHyperTreeGrid* grid, bool indexTables, bool maskedDescendants)
{
  Key key = keyOf(grid);
  if (Access && key == Kept && (Access->hasIndexTables() || !indexTables) &&
      (Access->hasMaskedDescendantFlags() || !maskedDescendants))
  {
    LastWasKept = true;
    return Access;
  }
  LastWasKept = false;
  clear();
  Access = std::make_shared<const HyperTreeAccess>(grid, indexTables, maskedDescendants);
  Kept = std::move(key);
  return Access;
}

void HyperTreeAccessCache::clear()
{
  Access.reset();
  Kept = Key();
}

} // namespace canopy
