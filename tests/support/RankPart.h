// One rank's part of a whole forest split between ranks (PartitionedForest.h),
// held as a simulation would hold it: arrays with that rank's nodes only, other
// ranks' parts absent. Fields: "node" (every node) and "leaf" (leaves only), each
// node's value unique over the whole forest (wholeValue).
#pragma once

#include "PartitionedForest.h"

#include "canopy/ForestDescription.h"

#include <cstdint>
#include <vector>

namespace canopy::testing
{

/// The value the simulation keeps for a node of the whole forest: unique per node.
inline double wholeValue(std::size_t tree, std::size_t node)
{
  return 1000.0 * static_cast<double>(tree) + static_cast<double>(node) + 0.25;
}

struct RankPart
{
  std::vector<PartitionedTree> trees;
  std::vector<std::vector<std::int64_t>> slots; ///< depth-first slots, when asked
  std::vector<double> nodeValues;               ///< present nodes, in slot order
  std::vector<double> leafValues;               ///< present leaves, in slot order
  ForestDescription description;

  /// Rank `rank` of `ranks`; `depthFirstSlots`: the rank stores its nodes
  /// depth-first (a slot map), else breadth-first.
  RankPart(const ForestDescription& whole, int rank, int ranks, bool depthFirstSlots);
  RankPart(const RankPart&) = delete;
  RankPart& operator=(const RankPart&) = delete;
};

} // namespace canopy::testing
