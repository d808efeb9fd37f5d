#include "RandomForest.h"

#include <random>

namespace canopy::testing
{

std::uint64_t checksum(const void* data, std::size_t bytes)
{
  std::uint64_t hash = 1469598103934665603ull;
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i)
  {
    hash = (hash ^ p[i]) * 1099511628211ull;
  }
  return hash;
}

RandomForest::RandomForest(const RandomForestOptions& o)
{
  std::mt19937_64 random(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);

  std::size_t trees = 1;
  for (int a = 0; a < 3; ++a)
  {
    const bool flat =
        (o.dimension == 2 && a == o.flatAxis) || (o.dimension == 1 && a != o.activeAxis);
    const std::size_t cells = flat ? 0 : o.rootCells[a];
    double x = o.origin[a];
    Coordinates[a].push_back(x);
    for (std::size_t i = 0; i < cells; ++i)
    {
      x += 0.5 + unit(random); // non-uniform spacing
      Coordinates[a].push_back(x);
    }
    trees *= flat ? 1 : cells;
  }
  Children = 1;
  for (int d = 0; d < o.dimension; ++d)
  {
    Children *= static_cast<std::size_t>(o.branchFactor);
  }

  Description.dimension = o.dimension;
  Description.branchFactor = o.branchFactor;
  Description.maxLevels = o.maxLevels;
  Description.rootGrid = {Coordinates[0].data(), Coordinates[1].data(), Coordinates[2].data(),
                          Coordinates[0].size(), Coordinates[1].size(), Coordinates[2].size()};

  for (std::size_t root = 0; root < trees; ++root)
  {
    if (o.skipEveryOtherRoot && root % 2 == 1)
    {
      continue;
    }
    std::vector<std::uint8_t> refinement;
    std::vector<Node> nodes;
    refinement.push_back(0);
    nodes.push_back({0, 0, -1, 0});
    for (std::size_t n = 0; n < refinement.size(); ++n)
    {
      const int level = nodes[n].level;
      const bool refine = level + 1 < o.maxLevels && unit(random) < o.refineProbability;
      if (!refine)
      {
        continue;
      }
      refinement[n] = 1;
      for (std::size_t c = 0; c < Children; ++c)
      {
        refinement.push_back(0);
        nodes.push_back({0, level + 1, static_cast<std::int64_t>(n), static_cast<int>(c)});
      }
    }
    std::vector<std::uint8_t> masked;
    if (o.maskProbability > 0)
    {
      for (std::size_t n = 0; n < refinement.size(); ++n)
      {
        masked.push_back(unit(random) < o.maskProbability ? 1 : 0);
      }
    }
    Refinement.push_back(std::move(refinement));
    Masked.push_back(std::move(masked));
    Nodes.push_back(std::move(nodes));
    TreeDescription tree;
    tree.rootIndex = static_cast<std::int64_t>(root);
    Description.trees.push_back(tree);
  }

  // Storage slots.
  std::size_t offset = 0;
  Slots.resize(Nodes.size());
  for (std::size_t t = 0; t < Nodes.size(); ++t)
  {
    auto& nodes = Nodes[t];
    const auto& refinement = Refinement[t];
    if (o.order == StorageOrder::BreadthFirst)
    {
      for (std::size_t n = 0; n < nodes.size(); ++n)
      {
        nodes[n].slot = static_cast<std::int64_t>(offset + n);
      }
    }
    else
    {
      // Pre-order: first child of breadth-first node n, then a stack walk.
      std::vector<std::size_t> firstChild(nodes.size(), 0);
      std::size_t next = 1;
      for (std::size_t n = 0; n < nodes.size(); ++n)
      {
        if (refinement[n])
        {
          firstChild[n] = next;
          next += Children;
        }
      }
      std::vector<std::size_t> stack{0};
      std::size_t order = offset;
      while (!stack.empty())
      {
        const std::size_t n = stack.back();
        stack.pop_back();
        nodes[n].slot = static_cast<std::int64_t>(order++);
        if (refinement[n])
        {
          for (std::size_t c = Children; c-- > 0;)
          {
            stack.push_back(firstChild[n] + c);
          }
        }
      }
      Slots[t].resize(nodes.size());
      for (std::size_t n = 0; n < nodes.size(); ++n)
      {
        Slots[t][n] = nodes[n].slot;
      }
    }
    FirstCell.push_back(static_cast<std::int64_t>(offset));
    offset += nodes.size();
    for (auto r : refinement)
    {
      TotalLeaves += r == 0;
    }
    TreeDescription& tree = Description.trees[t];
    tree.refinement = refinement.data();
    tree.numberOfNodes = refinement.size();
    tree.masked = Masked[t].empty() ? nullptr : Masked[t].data();
    tree.storageSlots = Slots[t].empty() ? nullptr : Slots[t].data();
  }
  TotalNodes = offset;
}

} // namespace canopy::testing
