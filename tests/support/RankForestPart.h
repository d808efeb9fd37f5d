// A rank's part of a whole forest, as the MPI tests and benchmarks split it: trees cut
// between ranks (p4est's partition: RankPart), or whole trees dealt out in turn (the
// others' trees elsewhere).
#pragma once

#include "RankPart.h"

#include <canopy/HtgBuilder.h>

#include <vtkHyperTreeGrid.h>
#include <vtkSmartPointer.h>

#include <memory>

namespace canopy::testing
{

/// Rank `rank` of `ranks`'s part of `whole`; `keep` holds what the grid borrows
/// (the grid reads it until it is rebuilt). Cut trees are stored depth-first on
/// odd ranks when `depthFirstOnOddRanks` (a slot map), else breadth-first.
inline vtkSmartPointer<vtkHyperTreeGrid> rankForestPart(const ForestDescription& whole,
                                                        bool splitTrees, int rank, int ranks,
                                                        std::shared_ptr<void>& keep,
                                                        bool depthFirstOnOddRanks = true)
{
  if (splitTrees)
  {
    auto part =
        std::make_shared<RankPart>(whole, rank, ranks, depthFirstOnOddRanks && rank % 2 == 1);
    keep = part;
    return buildHyperTreeGrid(part->description);
  }
  auto mine = std::make_shared<ForestDescription>(whole);
  mine->trees.clear();
  mine->missingTreesAreElsewhere = true;
  for (std::size_t t = 0; t < whole.trees.size(); ++t)
  {
    if (static_cast<int>(t % static_cast<std::size_t>(ranks)) == rank)
    {
      mine->trees.push_back(whole.trees[t]);
    }
  }
  keep = mine;
  return buildHyperTreeGrid(*mine);
}

} // namespace canopy::testing
