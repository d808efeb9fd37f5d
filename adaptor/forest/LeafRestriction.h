// Coarse values of leaves-only fields, by volume-weighted restriction.
//
// A simulation that stores values only on leaves still gets a complete
// vtkHyperTreeGrid: every coarse node shows the volume average of its unmasked
// children (all present children if all are masked), computed bottom-up.
// Children of a node split it into equal volumes, so the volume average is the
// plain mean. Absent children (another rank's part of a split tree) have no
// value here and are left out. These coarse values are what level-of-detail
// rendering shows.
#pragma once

#include "CellSlots.h"
#include "ForestLayout.h"
#include <canopy/ForestDescription.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace canopy
{

/// For every cell: the leaf tuple it reads (>= 0), or a computed tuple
/// (computedEntry(i)): 0 is the absent cells' fill, 1 + c the c-th coarse node.
/// Leaves and coarse nodes are each numbered in slot order.
struct LeafTupleMap
{
  std::shared_ptr<const IndexTable> cellToTuple;
  std::size_t numberOfCoarse = 0;

  static LeafTupleMap build(const ForestDescription& forest, const ForestLayout& layout,
                            const CellSlots& slots);
};

/// The computed tuples of one leaves-only field, AoS: the absent fill (NaN) first,
/// then the volume averages of the coarse nodes (indexed as in LeafTupleMap).
template <typename T>
std::vector<T> restrictToCoarse(const ForestDescription& forest, const ForestLayout& layout,
                                const FieldDescription& field, const LeafTupleMap& map);

extern template std::vector<float> restrictToCoarse<float>(const ForestDescription&,
                                                           const ForestLayout&,
                                                           const FieldDescription&,
                                                           const LeafTupleMap&);
extern template std::vector<double> restrictToCoarse<double>(const ForestDescription&,
                                                             const ForestLayout&,
                                                             const FieldDescription&,
                                                             const LeafTupleMap&);

} // namespace canopy
