#include "RankPart.h"

namespace canopy::testing
{

RankPart::RankPart(const ForestDescription& whole, int rank, int ranks, bool depthFirstSlots)
    : trees(partitionForRank(whole, rank, ranks))
{
  description.dimension = whole.dimension;
  description.branchFactor = whole.branchFactor;
  description.maxLevels = whole.maxLevels;
  description.rootGrid = whole.rootGrid;
  std::size_t children = 1;
  for (int d = 0; d < whole.dimension; ++d)
  {
    children *= static_cast<std::size_t>(whole.branchFactor);
  }
  // Present nodes get slots breadth-first (default) or depth-first (slot maps).
  std::vector<std::pair<std::size_t, std::size_t>> nodeAtSlot; // (tree, node)
  for (std::size_t t = 0; t < trees.size(); ++t)
  {
    const auto& tree = trees[t];
    std::vector<std::int64_t> slot(tree.refinement.size(), -7); // absent: ignored
    if (depthFirstSlots)
    {
      std::vector<std::size_t> first(tree.refinement.size(), 0);
      for (std::size_t n = 0, next = 1; n < tree.refinement.size(); ++n)
      {
        if (tree.refinement[n])
        {
          first[n] = next;
          next += children;
        }
      }
      auto walk = [&](auto& self, std::size_t n) -> void
      {
        if (tree.absent[n])
        {
          return;
        }
        slot[n] = static_cast<std::int64_t>(nodeAtSlot.size());
        nodeAtSlot.emplace_back(t, n);
        for (std::size_t c = 0; tree.refinement[n] && c < children; ++c)
        {
          self(self, first[n] + c);
        }
      };
      walk(walk, 0);
    }
    else
    {
      for (std::size_t n = 0; n < tree.refinement.size(); ++n)
      {
        if (!tree.absent[n])
        {
          slot[n] = static_cast<std::int64_t>(nodeAtSlot.size());
          nodeAtSlot.emplace_back(t, n);
        }
      }
    }
    slots.push_back(std::move(slot));
  }
  for (const auto& [t, n] : nodeAtSlot)
  {
    const double value = wholeValue(trees[t].wholeTree, trees[t].wholeNode[n]);
    nodeValues.push_back(value);
    hashValues.push_back(wholeHash(trees[t].wholeTree, trees[t].wholeNode[n]));
    if (!trees[t].refinement[n])
    {
      leafValues.push_back(value);
    }
  }
  for (std::size_t t = 0; t < trees.size(); ++t)
  {
    const auto& tree = trees[t];
    description.trees.push_back({tree.rootIndex, tree.refinement.data(), tree.refinement.size(),
                                 nullptr, depthFirstSlots ? slots[t].data() : nullptr,
                                 tree.absent.data()});
  }
  // Every root cell of the whole forest has its tree on some rank.
  description.missingTreesAreElsewhere = true;
  description.fields.push_back(FieldDescription::aos("node", nodeValues.data(), nodeValues.size()));
  description.fields.push_back(FieldDescription::aos("leaf", leafValues.data(), leafValues.size(),
                                                     1, Centering::LeavesOnly));
  description.fields.push_back(FieldDescription::aos("hash", hashValues.data(), hashValues.size()));
}

} // namespace canopy::testing
