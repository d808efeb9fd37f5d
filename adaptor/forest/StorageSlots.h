// Where a node's values live: its storage slot, which is also its global cell
// index in the vtkHyperTreeGrid.
#pragma once

#include "ForestLayout.h"
#include <canopy/ForestDescription.h>

#include <cstddef>

namespace canopy
{

inline std::size_t storageSlot(const TreeDescription& tree, const TreeLayout& shape,
                               std::size_t node)
{
  return tree.storageSlots ? static_cast<std::size_t>(tree.storageSlots[node])
                           : shape.firstSlot + node;
}

/// Number of children of a refined node.
inline std::size_t childrenPerNode(const ForestDescription& forest)
{
  std::size_t children = 1;
  for (int d = 0; d < forest.dimension; ++d)
  {
    children *= static_cast<std::size_t>(forest.branchFactor);
  }
  return children;
}

} // namespace canopy
