// One rank's part of a whole forest split between ranks (PartitionedForest.h),
// held as a simulation would hold it: arrays with that rank's nodes only, other
// ranks' parts absent. Fields: "node" (every node) and "leaf" (leaves only), each
// node's value unique over the whole forest (wholeValue), and "hash" (every node,
// wholeHash).
#pragma once

#include "PartitionedForest.h"

#include <canopy/ForestDescription.h>

#include <cstdint>
#include <vector>

namespace canopy::testing
{

/// The value the simulation keeps for a node of the whole forest: unique per node.
inline double wholeValue(std::size_t tree, std::size_t node)
{
  return 1000.0 * static_cast<double>(tree) + static_cast<double>(node) + 0.25;
}

/// A pseudo-random value in [0, 1) per node of the whole forest (splitmix64 of
/// wholeValue): selecting a range of it picks scattered cells.
inline double wholeHash(std::size_t tree, std::size_t node)
{
  std::uint64_t x =
      static_cast<std::uint64_t>(wholeValue(tree, node) * 4.0) + 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  return static_cast<double>(x >> 11) / 9007199254740992.0;
}

struct RankPart
{
  std::vector<PartitionedTree> trees;
  std::vector<std::vector<std::int64_t>> slots; ///< depth-first slots, when asked
  std::vector<double> nodeValues;               ///< present nodes, in slot order
  std::vector<double> leafValues;               ///< present leaves, in slot order
  std::vector<double> hashValues;               ///< present nodes, in slot order
  ForestDescription description;

  /// Rank `rank` of `ranks`; `depthFirstSlots`: the rank stores its nodes
  /// depth-first (a slot map), else breadth-first.
  RankPart(const ForestDescription& whole, int rank, int ranks, bool depthFirstSlots);
  RankPart(const RankPart&) = delete;
  RankPart& operator=(const RankPart&) = delete;
};

} // namespace canopy::testing
