// A filter's HyperTreeAccess kept across executions while the grid's topology
// is unchanged, so what costs a pass over every node (explicit global-index
// tables, masked- and absent-descendant flags) is paid once per topology, not
// once per camera move.
//
// The key is what VTK's pipeline says changed: the grid object and its
// modified time, the mask's and the ghost array's objects, times and storage,
// plus each tree's object, vertex count and child table (a tree refined in
// place without Modified() is noticed too). Checking it costs one step per
// tree, not per node.
#pragma once

#include "HyperTreeAccess.h"

#include <vtkType.h>

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
  struct TreeKey
  {
    vtkIdType index;
    const void* tree;
    vtkIdType vertices;
    const void* elderChild;
    bool operator==(const TreeKey& o) const
    {
      return index == o.index && tree == o.tree && vertices == o.vertices &&
             elderChild == o.elderChild;
    }
  };
  struct Key
  {
    const void* grid = nullptr;
    vtkMTimeType gridTime = 0;
    const void* mask = nullptr;
    vtkMTimeType maskTime = 0;
    const void* maskBits = nullptr;
    vtkIdType maskSize = 0;
    const void* ghosts = nullptr;
    vtkMTimeType ghostTime = 0;
    const void* ghostValues = nullptr;
    vtkIdType cells = 0;
    std::vector<TreeKey> trees;
    bool operator==(const Key& o) const;
  };
  static Key keyOf(vtkHyperTreeGrid* grid);

  Key Kept;
  std::shared_ptr<const HyperTreeAccess> Access;
  bool LastWasKept = false;
};

} // namespace canopy
