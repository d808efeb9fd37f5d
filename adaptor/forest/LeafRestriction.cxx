#include "LeafRestriction.h"

#include "FieldView.h"
#include "SimulationFieldArray.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace canopy
{

LeafTupleMap LeafTupleMap::build(const ForestDescription& forest, const ForestLayout& layout,
                                 const CellSlots& slots)
{
  // Mark which slots hold coarse nodes, then number leaves and coarse nodes
  // separately in slot order.
  IndexTable bySlot(layout.totalPresentNodes);
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    const TreeLayout& shape = layout.trees[t];
    for (std::size_t n = 0; n < shape.numberOfNodes; ++n)
    {
      if (slots.identity())
      {
        bySlot[storageSlot(tree, shape, n)] = tree.refinement[n] != 0;
      }
      else if (!isAbsent(tree, n))
      {
        const auto slot = (*slots.slotOfCell)[shape.firstCell + n];
        bySlot[static_cast<std::size_t>(slot)] = tree.refinement[n] != 0;
      }
    }
  }
  std::int64_t leaves = 0;
  std::size_t coarse = 0;
  for (auto& entry : bySlot)
  {
    entry = entry ? computedEntry(1 + coarse++) : leaves++;
  }
  LeafTupleMap map;
  map.numberOfCoarse = coarse;
  if (slots.identity())
  {
    map.cellToTuple = std::make_shared<IndexTable>(std::move(bySlot));
    return map;
  }
  const auto& slotOfCell = *slots.slotOfCell;
  auto byCell = std::make_shared<IndexTable>(layout.totalNodes);
  for (std::size_t cell = 0; cell < layout.totalNodes; ++cell)
  {
    const std::int64_t slot = slotOfCell[cell];
    (*byCell)[cell] =
        slot == CellSlots::NoSlot ? computedEntry(0) : bySlot[static_cast<std::size_t>(slot)];
  }
  map.cellToTuple = std::move(byCell);
  return map;
}

template <typename T>
std::vector<T> restrictToCoarse(const ForestDescription& forest, const ForestLayout& layout,
                                const FieldDescription& field, const LeafTupleMap& map)
{
  const auto nc = static_cast<std::size_t>(field.components);
  const FieldView leaves = FieldView::of(field);
  const auto& table = *map.cellToTuple;
  // Computed tuple 0 is what absent cells read.
  std::vector<T> computed((1 + map.numberOfCoarse) * nc);
  std::fill(computed.begin(), computed.begin() + static_cast<std::ptrdiff_t>(nc), absentValue<T>());
  const std::size_t children = childrenPerNode(forest);
  std::vector<double> sum(nc);
  // The value of a child, leaf (borrowed) or coarse (computed before it: see below).
  const auto value = [&](std::int64_t tuple, std::size_t c)
  {
    return tuple >= 0 ? static_cast<double>(leaves.at<T>(static_cast<std::size_t>(tuple), c))
                      : static_cast<double>(computed[computedIndexOf(tuple) * nc + c]);
  };

  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    const TreeLayout& shape = layout.trees[t];
    // Breadth-first numbering: the k-th refined node's children start at
    // 1 + k * children. Children come after their parent, so a sweep from the
    // last refined node back sees them first.
    std::size_t refined = 0;
    for (std::size_t n = 0; n < shape.descriptorBits; ++n)
    {
      refined += tree.refinement[n] != 0;
    }
    // Without masked or absent children every child counts: the loop the
    // unchanged steps of a leaves-only field pay for (docs/benchmarks.md).
    const bool everyChild = !tree.masked && !tree.absent;
    for (std::size_t n = shape.descriptorBits; n-- > 0;)
    {
      if (!tree.refinement[n])
      {
        continue;
      }
      const std::size_t first = 1 + --refined * children;
      const std::int64_t* entry = &table[cellIndex(shape, first)];
      const std::size_t target = computedIndexOf(table[cellIndex(shape, n)]);
      if (everyChild && !leaves.tupleAddress)
      {
        // Strided leaves (AoS, SoA, records): the address arithmetic in locals,
        // which the compiler cannot hoist past the writes into `computed`.
        for (std::size_t c = 0; c < nc; ++c)
        {
          const unsigned char* base = leaves.componentBase[c];
          const std::size_t stride = leaves.strideBytes;
          double total = 0.0;
          for (std::size_t k = 0; k < children; ++k)
          {
            const std::int64_t tuple = entry[k];
            if (tuple >= 0)
            {
              T leaf;
              std::memcpy(&leaf, base + static_cast<std::size_t>(tuple) * stride, sizeof(T));
              total += static_cast<double>(leaf);
            }
            else
            {
              total += static_cast<double>(computed[computedIndexOf(tuple) * nc + c]);
            }
          }
          computed[target * nc + c] = static_cast<T>(total / static_cast<double>(children));
        }
        continue;
      }
      std::fill(sum.begin(), sum.end(), 0.0);
      std::size_t used = 0;
      for (int pass = 0; pass < 2 && used == 0; ++pass)
      {
        // Pass 0: unmasked children only; pass 1 (all masked): every present child.
        for (std::size_t k = 0; k < children; ++k)
        {
          const std::size_t child = first + k;
          if (isAbsent(tree, child) || (pass == 0 && tree.masked && tree.masked[child]))
          {
            continue;
          }
          for (std::size_t c = 0; c < nc; ++c)
          {
            sum[c] += value(entry[k], c);
          }
          ++used;
        }
      }
      for (std::size_t c = 0; c < nc; ++c)
      {
        // No present child at all: nothing of this node is here.
        computed[target * nc + c] =
            used == 0 ? absentValue<T>() : static_cast<T>(sum[c] / static_cast<double>(used));
      }
    }
  }
  return computed;
}

template std::vector<float> restrictToCoarse<float>(const ForestDescription&, const ForestLayout&,
                                                    const FieldDescription&, const LeafTupleMap&);
template std::vector<double> restrictToCoarse<double>(const ForestDescription&, const ForestLayout&,
                                                      const FieldDescription&, const LeafTupleMap&);

} // namespace canopy
