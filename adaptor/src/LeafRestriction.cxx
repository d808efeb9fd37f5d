#include "LeafRestriction.h"

#include "FieldView.h"
#include "StorageSlots.h"

namespace canopy
{

LeafTupleMap LeafTupleMap::build(const ForestDescription& forest, const ForestLayout& layout)
{
  auto slotToTuple = std::make_shared<std::vector<std::int64_t>>(layout.totalNodes);
  auto& table = *slotToTuple;
  // First mark which slots hold coarse nodes, then number leaves and coarse
  // nodes separately in slot order.
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    const TreeLayout& shape = layout.trees[t];
    for (std::size_t n = 0; n < shape.numberOfNodes; ++n)
    {
      table[storageSlot(tree, shape, n)] = tree.refinement[n] != 0;
    }
  }
  std::int64_t leaves = 0;
  std::int64_t coarse = 0;
  for (auto& entry : table)
  {
    entry = entry ? -(++coarse) : leaves++;
  }
  LeafTupleMap map;
  map.slotToTuple = std::move(slotToTuple);
  map.numberOfCoarse = static_cast<std::size_t>(coarse);
  return map;
}

template <typename T>
std::vector<T> restrictToCoarse(const ForestDescription& forest, const ForestLayout& layout,
                                const FieldDescription& field, const LeafTupleMap& map)
{
  const auto nc = static_cast<std::size_t>(field.components);
  const FieldView<T> leaves = FieldView<T>::of(field);
  const auto& table = *map.slotToTuple;
  std::vector<T> coarse(map.numberOfCoarse * nc);
  const std::size_t children = childrenPerNode(forest);
  std::vector<std::size_t> elderChild;
  std::vector<double> sum(nc);

  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    const TreeLayout& shape = layout.trees[t];
    // Breadth-first numbering: the k-th refined node's children start at 1 + k * children.
    elderChild.assign(shape.descriptorBits, 0);
    std::size_t refinedSoFar = 0;
    for (std::size_t n = 0; n < shape.descriptorBits; ++n)
    {
      if (tree.refinement[n])
      {
        elderChild[n] = 1 + refinedSoFar++ * children;
      }
    }
    // Children come after their parent, so a reverse sweep sees them first.
    for (std::size_t n = shape.descriptorBits; n-- > 0;)
    {
      if (!tree.refinement[n])
      {
        continue;
      }
      std::fill(sum.begin(), sum.end(), 0.0);
      std::size_t used = 0;
      for (int pass = 0; pass < 2 && used == 0; ++pass)
      {
        // Pass 0: unmasked children only; pass 1 (all children masked): every child.
        for (std::size_t k = 0; k < children; ++k)
        {
          const std::size_t child = elderChild[n] + k;
          if (pass == 0 && tree.masked && tree.masked[child])
          {
            continue;
          }
          const std::int64_t tuple = table[storageSlot(tree, shape, child)];
          for (std::size_t c = 0; c < nc; ++c)
          {
            sum[c] +=
                tuple >= 0
                    ? static_cast<double>(leaves.at(static_cast<std::size_t>(tuple), c))
                    : static_cast<double>(coarse[static_cast<std::size_t>(-tuple - 1) * nc + c]);
          }
          ++used;
        }
      }
      const auto target = static_cast<std::size_t>(-table[storageSlot(tree, shape, n)] - 1);
      for (std::size_t c = 0; c < nc; ++c)
      {
        coarse[target * nc + c] = static_cast<T>(sum[c] / static_cast<double>(used));
      }
    }
  }
  return coarse;
}

template std::vector<float> restrictToCoarse<float>(const ForestDescription&, const ForestLayout&,
                                                    const FieldDescription&, const LeafTupleMap&);
template std::vector<double> restrictToCoarse<double>(const ForestDescription&, const ForestLayout&,
                                                      const FieldDescription&, const LeafTupleMap&);

} // namespace canopy
