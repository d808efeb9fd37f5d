// A filter's HyperTreeAccess kept across executions while the grid's topology
// is unchanged, so what costs a pass over every node (explicit global-index
// tables, masked- and absent-descendant flags) is paid once per topology, not
// once per camera move.
//
// The key is what the access reads (TopologyKeys.h, the filters' one rule for
// what changed): the grid's shape (dimension, branch factor, root dimensions,
// the coordinates' values, the trees-elsewhere flag), the mask's and the ghost
// array's objects, times and storage, and each tree's object and modified time,
// vertex count, child table and first global index (a tree refined in place
// without Modified() is noticed too), and what Canopy's builder says of it in
// the grid's topology stamp. Not the grid's own modified time, which changes at
// every step of a simulation even when only its field values did: a
// simulation's masked grid (split trees, a masked block forest) keeps its
// access, masked-descendant flags and surface memos from step to step while its
// topology holds. Grids with explicit global indices key on the grid's modified
// time as well (their index tables are not compared). Checking it costs one step
// per tree and root coordinate, not per node.
#pragma once

#include "HyperTreeAccess.h"
#include "TopologyKeys.h"

#include <vtkType.h>

#include <cstdint>
#include <memory>
#include <vector>

class vtkHyperTreeGrid;

namespace canopy
{

class HyperTreeAccessCache
{
public:
  /// The access for this grid: the kept one if its topology is unchanged (and
  /// it has index tables and masked-descendant flags when asked for), else a new
  /// one, which is kept. Throws as HyperTreeAccess does.
  std::shared_ptr<const HyperTreeAccess> get(vtkHyperTreeGrid* grid, bool indexTables,
                                             bool maskedDescendants = true);
  /// Forget the kept access (and the grid's trees it points into).
  void clear();
  /// Whether the last get() returned the access kept from before.
  bool lastWasKept() const { return LastWasKept; }

private:
  struct Key
  {
    GridTopologyKey grid;
    std::vector<TreeTopologyKey> trees;
    bool operator==(const Key& o) const { return grid == o.grid && trees == o.trees; }
  };

  Key Kept;
  std::shared_ptr<const HyperTreeAccess> Access;
  bool LastWasKept = false;
};

} // namespace canopy
