#include "HyperTreeAccessCache.h"

#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkUnsignedCharArray.h>

namespace canopy
{

bool HyperTreeAccessCache::Key::operator==(const Key& o) const
{
  return grid == o.grid && gridTime == o.gridTime && mask == o.mask && maskTime == o.maskTime &&
         maskBits == o.maskBits && maskSize == o.maskSize && ghosts == o.ghosts &&
         ghostTime == o.ghostTime && ghostValues == o.ghostValues && cells == o.cells &&
         trees == o.trees;
}

HyperTreeAccessCache::Key HyperTreeAccessCache::keyOf(vtkHyperTreeGrid* grid)
{
  Key key;
  key.grid = grid;
  key.gridTime = grid->GetMTime();
  key.cells = grid->GetNumberOfCells();
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
    key.trees.push_back({index, tree, tree->GetNumberOfVertices(), elder});
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
