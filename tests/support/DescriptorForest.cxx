#include "DescriptorForest.h"

#include <stdexcept>

namespace canopy::testing
{

std::vector<std::string> descriptorLevels(const std::string& descriptor)
{
  std::vector<std::string> levels(1);
  for (char c : descriptor)
  {
    if (c == '|')
    {
      levels.emplace_back();
    }
    else if (c != ' ')
    {
      levels.back().push_back(c);
    }
  }
  return levels;
}

namespace
{

/// Distributes one symbol stream per level over the trees: level l lists the
/// children of level l-1's refined nodes, tree by tree, each tree breadth-first.
std::vector<std::vector<char>> perTreeSymbols(const std::vector<std::string>& levels,
                                              const std::vector<std::string>& refinementLevels,
                                              std::size_t trees, std::size_t children)
{
  std::vector<std::vector<char>> symbols(trees);
  // refinedInLevel[t]: refined nodes of tree t in the previous level.
  std::vector<std::size_t> refinedInLevel(trees, 0);
  if (levels[0].size() != trees)
  {
    throw std::invalid_argument("descriptor level 0 must have one symbol per root cell");
  }
  for (std::size_t t = 0; t < trees; ++t)
  {
    symbols[t].push_back(levels[0][t]);
    refinedInLevel[t] = refinementLevels[0][t] == 'R' ? 1 : 0;
  }
  for (std::size_t l = 1; l < levels.size(); ++l)
  {
    std::size_t position = 0;
    for (std::size_t t = 0; t < trees; ++t)
    {
      const std::size_t count = refinedInLevel[t] * children;
      std::size_t refined = 0;
      for (std::size_t i = 0; i < count; ++i)
      {
        if (position + i >= levels[l].size())
        {
          throw std::invalid_argument("descriptor level " + std::to_string(l) + " is too short");
        }
        symbols[t].push_back(levels[l][position + i]);
        refined += refinementLevels[l][position + i] == 'R' ? 1 : 0;
      }
      position += count;
      refinedInLevel[t] = refined;
    }
    if (position != levels[l].size())
    {
      throw std::invalid_argument("descriptor level " + std::to_string(l) + " is too long");
    }
  }
  return symbols;
}

} // namespace

DescriptorForest::DescriptorForest(const SourceParameters& p)
{
  const int dimension = (p.dimensions[0] > 1) + (p.dimensions[1] > 1) + (p.dimensions[2] > 1);
  std::size_t trees = 1;
  for (int a = 0; a < 3; ++a)
  {
    const unsigned int points = p.dimensions[a];
    for (unsigned int i = 0; i < points; ++i)
    {
      Coordinates[a].push_back(i * p.gridScale[a]);
    }
    trees *= points > 1 ? points - 1 : 1;
  }
  std::size_t children = 1;
  for (int d = 0; d < dimension; ++d)
  {
    children *= static_cast<std::size_t>(p.branchFactor);
  }

  const std::vector<std::string> levels = descriptorLevels(p.descriptor);
  const auto treeSymbols = perTreeSymbols(levels, levels, trees, children);
  std::vector<std::vector<char>> maskSymbols;
  if (!p.mask.empty())
  {
    const std::vector<std::string> maskLevels = descriptorLevels(p.mask);
    if (maskLevels.size() != levels.size())
    {
      throw std::invalid_argument("mask and descriptor have different numbers of levels");
    }
    maskSymbols = perTreeSymbols(maskLevels, levels, trees, children);
  }

  Refinement.resize(trees);
  Masked.resize(trees);
  Description.dimension = dimension;
  Description.branchFactor = p.branchFactor;
  Description.maxLevels = p.maxDepth;
  Description.rootGrid = {Coordinates[0].data(), Coordinates[1].data(), Coordinates[2].data(),
                          Coordinates[0].size(), Coordinates[1].size(), Coordinates[2].size()};
  for (std::size_t t = 0; t < trees; ++t)
  {
    const auto& symbols = treeSymbols[t];
    for (char c : symbols)
    {
      Refinement[t].push_back(c == 'R' ? 1 : 0);
    }
    // Levels of a breadth-first tree: walk level by level counting refined nodes.
    std::size_t begin = 0;
    std::size_t end = 1;
    double level = 0;
    while (begin < symbols.size())
    {
      std::size_t refined = 0;
      for (std::size_t n = begin; n < end; ++n)
      {
        Depth.push_back(level);
        refined += Refinement[t][n];
      }
      begin = end;
      end += refined * children;
      level += 1;
    }
    if (!maskSymbols.empty())
    {
      for (char c : maskSymbols[t])
      {
        Masked[t].push_back(c == '0' ? 1 : 0);
      }
    }
    TreeDescription tree;
    tree.rootIndex = static_cast<std::int64_t>(t);
    tree.refinement = Refinement[t].data();
    tree.numberOfNodes = Refinement[t].size();
    tree.masked = Masked[t].empty() ? nullptr : Masked[t].data();
    Description.trees.push_back(tree);
  }
  Description.fields.push_back(FieldDescription::aos("Depth", Depth.data(), Depth.size()));
}

std::size_t DescriptorForest::numberOfLeaves() const
{
  std::size_t leaves = 0;
  for (const auto& tree : Refinement)
  {
    for (auto r : tree)
    {
      leaves += r == 0;
    }
  }
  return leaves;
}

std::size_t DescriptorForest::numberOfUnmaskedLeaves() const
{
  // A leaf is visible when neither it nor an ancestor is masked.
  std::size_t visible = 0;
  std::size_t children = 1;
  for (int d = 0; d < Description.dimension; ++d)
  {
    children *= static_cast<std::size_t>(Description.branchFactor);
  }
  for (std::size_t t = 0; t < Refinement.size(); ++t)
  {
    const auto& refinement = Refinement[t];
    std::vector<std::uint8_t> hidden(refinement.size(), 0);
    std::size_t next = 1;
    for (std::size_t n = 0; n < refinement.size(); ++n)
    {
      hidden[n] = hidden[n] || (!Masked[t].empty() && Masked[t][n]);
      if (refinement[n])
      {
        for (std::size_t c = 0; c < children; ++c)
        {
          hidden[next + c] = hidden[n];
        }
        next += children;
      }
      else if (!hidden[n])
      {
        ++visible;
      }
    }
  }
  return visible;
}

} // namespace canopy::testing
