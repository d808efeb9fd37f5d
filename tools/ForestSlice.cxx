#include "ForestSlice.h"

#include <stdexcept>

namespace canopy::tools
{
namespace
{

std::size_t leavesOf(const TreeDescription& tree)
{
  std::size_t leaves = 0;
  for (std::size_t n = 0; n < tree.numberOfNodes; ++n)
    leaves += tree.refinement[n] == 0;
  return leaves;
}

/// Moves a field's start `first` tuples on and keeps `count` tuples.
FieldDescription narrowed(FieldDescription field, std::size_t first, std::size_t count)
{
  const std::size_t value = sizeOf(field.type);
  switch (field.layout)
  {
  case Layout::AoS:
    field.data = static_cast<const char*>(field.data) + first * value * field.components;
    break;
  case Layout::Strided:
    field.data = static_cast<const char*>(field.data) + first * field.tupleStrideBytes;
    break;
  case Layout::SoA:
    for (auto& component : field.componentData)
      component = static_cast<const char*>(component) + first * value;
    break;
  case Layout::Indirect:
    field.tupleAddresses += first;
    break;
  case Layout::Blocks:
    throw std::invalid_argument("field '" + field.name +
                                "': a block field is per block, not per tuple");
  }
  field.numberOfTuples = count;
  return field;
}

} // namespace

std::size_t countLeaves(const ForestDescription& forest)
{
  std::size_t leaves = 0;
  for (const auto& tree : forest.trees)
    leaves += leavesOf(tree);
  return leaves;
}

std::size_t countNodes(const ForestDescription& forest)
{
  std::size_t nodes = 0;
  for (const auto& tree : forest.trees)
    nodes += tree.numberOfNodes;
  return nodes;
}

ForestDescription rankSlice(const ForestDescription& forest, int rank, int ranks)
{
  ForestDescription slice = forest;
  slice.trees.clear();
  slice.fields.clear();
  std::size_t firstNode = 0, firstLeaf = 0, nodes = 0, leaves = 0;
  bool started = false;
  const std::size_t trees = forest.trees.size();
  for (std::size_t t = 0; t < trees; ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    if (tree.storageSlots || tree.absent)
      throw std::invalid_argument("rankSlice: slot maps and absent nodes are not supported");
    const bool mine = static_cast<int>(t * static_cast<std::size_t>(ranks) / trees) == rank;
    const std::size_t treeLeaves = leavesOf(tree);
    if (mine)
    {
      started = true;
      slice.trees.push_back(tree);
      nodes += tree.numberOfNodes;
      leaves += treeLeaves;
    }
    else if (!started)
    {
      firstNode += tree.numberOfNodes;
      firstLeaf += treeLeaves;
    }
  }
  for (const auto& field : forest.fields)
  {
    const bool everyNode = field.centering == Centering::EveryNode;
    slice.fields.push_back(
        narrowed(field, everyNode ? firstNode : firstLeaf, everyNode ? nodes : leaves));
  }
  slice.missingTreesAreElsewhere = forest.missingTreesAreElsewhere || ranks > 1;
  return slice;
}

} // namespace canopy::tools
