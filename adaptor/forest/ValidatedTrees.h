// Validation that skips the trees already validated at an earlier build: the
// step-to-step builder (GridBuilder) knows, from each tree's fingerprint, which
// trees have the same bytes (refinement, absent, slots) as when they were last
// validated, so their per-node checks need not run again.
#pragma once

#include "ForestLayout.h"

#include <algorithm>
#include <vector>

namespace canopy
{

struct ValidatedTrees
{
  /// The layout of the earlier build, same trees in the same order.
  const ForestLayout* previous = nullptr;
  /// Per tree: the same refinement and absent bytes as in `previous` (its
  /// TreeLayout still holds).
  std::vector<bool> unchanged;
  /// Every tree's storage slots are the same bytes as before.
  bool sameSlots = false;

  /// The slot maps' permutation check can be skipped: same shapes, same slots.
  bool slotsKnownValid() const
  {
    return sameSlots && std::all_of(unchanged.begin(), unchanged.end(), [](bool u) { return u; });
  }
};

// layoutForest (ForestLayout.h) takes the trees `known` marks unchanged as valid
// (their shape from the earlier layout); everything else is checked as usual.
// With every tree's shape and slots unchanged, the permutation check is skipped too.

} // namespace canopy
