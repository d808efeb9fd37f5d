// One pass over a field's visible leaves that feeds every query on it: the totals
// in locals (registers), the ranges' and histograms' counts in place, the extremes'
// leaves located only for values at or beyond the extreme so far.
#pragma once

#include "FieldPartial.h"
#include "LeafGeometry.h"
#include "LeafWalk.h"

#include <canopy/ForestDescription.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace canopy
{

/// Reads component `component` of `field` (a non-block layout) as T at each visible
/// leaf of `forest` and adds it to `partial` (empty so far) for `queries`.
/// `ordinalOfSlot`: leaves-only fields with a slot map, the leaf's tuple by slot.
template <typename T>
void passOverField(const ForestDescription& forest, const LeafGeometry& geometry,
                   const FieldDescription& field, int component, const FieldQuerySet& queries,
                   const std::vector<std::size_t>& ordinalOfSlot, int rank,
                   std::vector<WalkParent>& scratch, FieldPartial& partial)
{
  const auto c = static_cast<std::size_t>(component);
  const std::size_t valueSize = sizeof(T);
  // One addressing form: base + tuple * stride, or an address per tuple.
  const unsigned char* base = nullptr;
  std::size_t stride = 0;
  const void* const* addresses = field.layout == Layout::Indirect ? field.tupleAddresses : nullptr;
  if (field.layout == Layout::SoA)
  {
    base = static_cast<const unsigned char*>(field.componentData[c]);
    stride = valueSize;
  }
  else if (field.layout != Layout::Indirect)
  {
    base = static_cast<const unsigned char*>(field.data);
    base = base ? base + c * valueSize : base;
    stride = field.layout == Layout::Strided
                 ? field.tupleStrideBytes
                 : static_cast<std::size_t>(field.components) * valueSize;
  }
  const bool leavesOnly = field.centering == Centering::LeavesOnly;
  const bool mapped = leavesOnly && !ordinalOfSlot.empty();

  FieldPartial::Totals totals;
  double lowest = std::numeric_limits<double>::infinity();
  double highest = -std::numeric_limits<double>::infinity();
  std::int64_t lowestRoot = 0;
  std::int64_t highestRoot = 0;
  const std::size_t ranges = queries.ranges.size();
  const std::size_t histograms = queries.histograms.size();
  std::int64_t* rangeCounts = partial.rangeCounts();
  double* rangeVolumes = partial.rangeVolumes();

  walkVisibleLeaves(
      forest, geometry, scratch,
      // Inlined into the walk (GCC declines otherwise): the totals then stay in registers.
      [&](const WalkLeaf& leaf) __attribute__((always_inline)) {
        const std::size_t tuple = !leavesOnly ? leaf.slot
                                  : mapped    ? ordinalOfSlot[leaf.slot]
                                              : leaf.leafOrdinal;
        const unsigned char* at =
            addresses ? static_cast<const unsigned char*>(addresses[tuple]) + c * valueSize
                      : base + tuple * stride;
        T stored;
        std::memcpy(&stored, at, sizeof(T));
        const auto value = static_cast<double>(stored);
        if (!std::isfinite(value))
        {
          ++totals.nonFinite;
          return;
        }
        const double volume = geometry.volume(leaf.tree, leaf.level);
        ++totals.finite;
        totals.sum += value;
        totals.volume += volume;
        totals.integral += value * volume;
        totals.squares += value * value * volume;
        // A tie within a tree never wins: the walk visits a tree in the tie rule's own
        // order (breadth-first); it wins from a tree of a smaller root index.
        const bool lower =
            value < lowest || (value == lowest && forest.trees[leaf.tree].rootIndex < lowestRoot);
        const bool higher = value > highest ||
                            (value == highest && forest.trees[leaf.tree].rootIndex < highestRoot);
        if (lower || higher)
        {
          const CellKey key{forest.trees[leaf.tree].rootIndex, leaf.level, leaf.index(geometry),
                            forest.branchFactor};
          for (const bool maximum : {false, true})
          {
            if ((maximum ? higher : lower) && partial.offer(value, key, rank, maximum))
            {
              partial.setCentre(geometry.centre(key.rootIndex, leaf.level, key.index), maximum);
            }
          }
          lowest = partial.minimum().value;
          lowestRoot = partial.minimum().key.rootIndex;
          highest = partial.maximum().value;
          highestRoot = partial.maximum().key.rootIndex;
        }
        for (std::size_t r = 0; r < ranges; ++r)
        {
          if (queries.ranges[r][0] <= value && value <= queries.ranges[r][1])
          {
            ++rangeCounts[r];
            rangeVolumes[r] += volume;
          }
        }
        for (std::size_t h = 0; h < histograms; ++h)
        {
          partial.histogramCounts(h)[FieldPartial::binOf(queries.histograms[h], value)] += 1;
        }
      });
  partial.addTotals(totals);
}

} // namespace canopy
