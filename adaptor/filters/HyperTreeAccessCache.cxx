#include "HyperTreeAccessCache.h"

#include <vtkHyperTreeGrid.h>

namespace canopy
{

std::shared_ptr<const HyperTreeAccess>
HyperTreeAccessCache::get(vtkHyperTreeGrid* grid, bool indexTables, bool maskedDescendants)
{
  Key key;
  key.grid = gridTopologyKey(grid, key.trees);
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
