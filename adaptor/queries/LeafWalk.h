// One pass over the visible leaves of a rank's forest, in the description's own
// order: each present leaf with no masked ancestor (itself included), with its
// tree, level, storage slot and leaf ordinal, and its position on demand. Reads the
// refinement, mask and absent bytes only; keeps nothing between calls but scratch.
#pragma once

#include "LeafGeometry.h"

#include <canopy/ForestDescription.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace canopy
{

/// A refined node seen by the walk: what its children inherit.
struct WalkParent
{
  std::array<std::int64_t, 3> index;
  int level;
  bool hidden;
};

/// A visible leaf as the walk hands it over.
struct WalkLeaf
{
  std::size_t tree;
  std::size_t node;
  int level;
  /// Storage slot (EveryNode fields' tuple): the slot map's entry, or the present
  /// nodes before it (trees back to back, breadth-first).
  std::size_t slot;
  /// Present leaves before it in the walk (LeavesOnly fields' tuple with implicit slots).
  std::size_t leafOrdinal;
  const WalkParent* parent; ///< null for a root leaf
  std::size_t child;        ///< position within the parent

  std::array<std::int64_t, 3> index(const LeafGeometry& geometry) const
  {
    return parent ? geometry.childIndex(parent->index, child)
                  : std::array<std::int64_t, 3>{{0, 0, 0}};
  }
};

/// Calls visit(const WalkLeaf&) for every visible present leaf of `forest` (a
/// validated, non-block forest), trees in the description's order, each tree
/// breadth-first. `scratch` is reused from call to call.
template <typename Visit>
void walkVisibleLeaves(const ForestDescription& forest, const LeafGeometry& geometry,
                       std::vector<WalkParent>& scratch, Visit&& visit)
{
  const std::size_t children = geometry.children();
  std::size_t slot = 0;
  std::size_t leafOrdinal = 0;
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    const std::uint8_t* refined = tree.refinement;
    const std::uint8_t* masked = tree.masked;
    const std::uint8_t* absent = tree.absent;
    const std::int64_t* slots = tree.storageSlots;
    scratch.clear();
    // The root (never absent), then each refined node's children in order.
    WalkLeaf leaf{t, 0, 0, 0, 0, nullptr, 0};
    const bool rootHidden = masked && masked[0];
    if (refined[0])
    {
      scratch.push_back({{{0, 0, 0}}, 0, rootHidden});
    }
    else if (!rootHidden)
    {
      leaf.slot = slots ? static_cast<std::size_t>(slots[0]) : slot;
      leaf.leafOrdinal = leafOrdinal;
      visit(leaf);
    }
    leafOrdinal += refined[0] ? 0 : 1;
    ++slot;
    std::size_t parentAt = 0;
    std::size_t child = 0;
    for (std::size_t n = 1; n < tree.numberOfNodes; ++n)
    {
      const WalkParent* parent = &scratch[parentAt];
      const bool hidden = parent->hidden || (masked && masked[n]);
      if (refined[n])
      {
        const int level = parent->level + 1;
        const auto index = geometry.childIndex(parent->index, child);
        scratch.push_back({index, level, hidden}); // `parent` is not used after this
        ++slot;
      }
      else if (!(absent && absent[n]))
      {
        if (!hidden)
        {
          leaf.node = n;
          leaf.level = parent->level + 1;
          leaf.slot = slots ? static_cast<std::size_t>(slots[n]) : slot;
          leaf.leafOrdinal = leafOrdinal;
          leaf.parent = parent;
          leaf.child = child;
          visit(leaf);
        }
        ++slot;
        ++leafOrdinal;
      }
      if (++child == children)
      {
        child = 0;
        ++parentAt;
      }
    }
  }
}

} // namespace canopy
