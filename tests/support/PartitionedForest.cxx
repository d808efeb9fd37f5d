#include "PartitionedForest.h"

#include <algorithm>
#include <deque>

namespace canopy::testing
{
namespace
{

std::size_t childrenOf(const ForestDescription& forest)
{
  std::size_t children = 1;
  for (int d = 0; d < forest.dimension; ++d)
  {
    children *= static_cast<std::size_t>(forest.branchFactor);
  }
  return children;
}

std::vector<std::size_t> firstChildren(const TreeDescription& tree, std::size_t children)
{
  std::vector<std::size_t> first(tree.numberOfNodes, 0);
  std::size_t next = 1;
  for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
  {
    if (tree.refinement[n])
    {
      first[n] = next;
      next += children;
    }
  }
  return first;
}

/// Per node of every tree: the lowest and highest rank owning a leaf below it.
struct Owners
{
  std::vector<std::vector<int>> lowest;
  std::vector<std::vector<int>> highest;
};

Owners computeOwners(const ForestDescription& whole, int ranks)
{
  const std::size_t children = childrenOf(whole);
  std::size_t totalLeaves = 0;
  for (const auto& tree : whole.trees)
  {
    for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
    {
      totalLeaves += tree.refinement[n] == 0;
    }
  }
  const auto ownerOf = [&](std::size_t leaf)
  {
    // The rank r with N r / k <= leaf < N (r + 1) / k.
    int r = static_cast<int>(leaf * static_cast<std::size_t>(ranks) /
                             std::max<std::size_t>(1, totalLeaves));
    while (r + 1 < ranks &&
           totalLeaves * static_cast<std::size_t>(r + 1) / static_cast<std::size_t>(ranks) <= leaf)
    {
      ++r;
    }
    while (r > 0 &&
           totalLeaves * static_cast<std::size_t>(r) / static_cast<std::size_t>(ranks) > leaf)
    {
      --r;
    }
    return r;
  };
  Owners owners;
  std::size_t leafSequence = 0;
  for (const auto& tree : whole.trees)
  {
    const auto first = firstChildren(tree, children);
    std::vector<int> lowest(tree.numberOfNodes, ranks);
    std::vector<int> highest(tree.numberOfNodes, -1);
    // Pre-order (Morton) walk numbering the leaves, then owners propagate up.
    auto walk = [&](auto& self, std::size_t node) -> void
    {
      if (!tree.refinement[node])
      {
        lowest[node] = highest[node] = ownerOf(leafSequence++);
        return;
      }
      for (std::size_t c = 0; c < children; ++c)
      {
        const std::size_t child = first[node] + c;
        self(self, child);
        lowest[node] = std::min(lowest[node], lowest[child]);
        highest[node] = std::max(highest[node], highest[child]);
      }
    };
    walk(walk, 0);
    owners.lowest.push_back(std::move(lowest));
    owners.highest.push_back(std::move(highest));
  }
  return owners;
}

} // namespace

std::vector<PartitionedTree> partitionForRank(const ForestDescription& whole, int rank, int ranks)
{
  const std::size_t children = childrenOf(whole);
  const Owners owners = computeOwners(whole, ranks);
  std::vector<PartitionedTree> part;
  for (std::size_t t = 0; t < whole.trees.size(); ++t)
  {
    const TreeDescription& tree = whole.trees[t];
    const auto& lowest = owners.lowest[t];
    const auto& highest = owners.highest[t];
    // Leaves below a node are contiguous in Morton order, so the ranks owning
    // them are exactly lowest .. highest (a rank with no leaves owns no range).
    const auto has = [&](std::size_t node)
    { return lowest[node] <= rank && rank <= highest[node]; };
    if (!has(0))
    {
      continue;
    }
    const auto first = firstChildren(tree, children);
    PartitionedTree local;
    local.rootIndex = tree.rootIndex;
    local.wholeTree = t;
    std::deque<std::size_t> queue{0};
    while (!queue.empty())
    {
      const std::size_t node = queue.front();
      queue.pop_front();
      const bool present = has(node);
      const bool refined = present && tree.refinement[node] != 0;
      local.refinement.push_back(refined ? 1 : 0);
      local.absent.push_back(present ? 0 : 1);
      local.wholeNode.push_back(node);
      for (std::size_t c = 0; refined && c < children; ++c)
      {
        queue.push_back(first[node] + c);
      }
    }
    part.push_back(std::move(local));
  }
  return part;
}

std::vector<std::size_t> leavesPerRank(const ForestDescription& whole, int ranks)
{
  std::vector<std::size_t> counts(static_cast<std::size_t>(ranks), 0);
  for (int r = 0; r < ranks; ++r)
  {
    for (const auto& tree : partitionForRank(whole, r, ranks))
    {
      for (std::size_t n = 0; n < tree.refinement.size(); ++n)
      {
        counts[static_cast<std::size_t>(r)] += !tree.refinement[n] && !tree.absent[n];
      }
    }
  }
  return counts;
}

} // namespace canopy::testing
