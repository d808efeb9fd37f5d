#include <canopy/HtgBuilder.h>

#include "GridAssembly.h"
#include "TopologyStamp.h"

#include <vtkHyperTreeGrid.h>

namespace canopy
{

vtkSmartPointer<vtkHyperTreeGrid> buildHyperTreeGrid(const ForestDescription& forest,
                                                     const FieldRequest& request)
{
  // Always from the layout of the description as it is now: a stored layout that
  // no longer matches the trees would be read out of bounds.
  const ForestLayout layout = layoutForest(forest);
  const auto fields = assembly::selectFields(forest, request);
  vtkSmartPointer<vtkHyperTreeGrid> htg = assembly::newGrid(forest);
  assembly::FieldTables tables;
  tables.blocks = assembly::indexBlocks(forest, layout);
  assembly::buildTrees(htg, forest, layout, std::vector<bool>(forest.trees.size(), true),
                       tables.blocks.get());
  assembly::setTopologyArrays(htg, forest, layout, tables.blocks.get());
  assembly::setFields(htg, forest, layout, fields, tables);
  // Built once: every tree and array at its first revision, for the filters' memos.
  StampRevisions stamp;
  stamp.builder = newStampBuilder();
  stamp.arrays = 1;
  for (const TreeDescription& tree : forest.trees)
  {
    stamp.trees[tree.rootIndex] = {1, 1};
  }
  writeTopologyStamp(htg, stamp);
  return htg;
}

} // namespace canopy
