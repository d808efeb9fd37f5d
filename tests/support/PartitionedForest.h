// A whole forest split between ranks the way p4est partitions: leaves in Morton
// (depth-first, child order) order across all trees, each rank a contiguous
// range. Each rank's part is described as Canopy expects it: the trees the rank
// has leaves in, down to its own leaves, every other rank's part as an absent
// leaf at its coarsest node.
#pragma once

#include <canopy/ForestDescription.h>

#include <cstdint>
#include <vector>

namespace canopy::testing
{

/// One rank's part of one tree.
struct PartitionedTree
{
  std::int64_t rootIndex = 0;
  std::vector<std::uint8_t> refinement; ///< breadth-first, as in TreeDescription
  std::vector<std::uint8_t> absent;     ///< breadth-first, nonzero = another rank's
  std::vector<std::size_t> wholeNode;   ///< local node -> breadth-first node of the whole tree
  std::size_t wholeTree = 0;            ///< position of the tree in the whole forest
};

/// Rank `rank`'s part of `whole` split over `ranks` ranks (leaves [N r / k, N (r+1) / k)
/// in Morton order). Trees the rank has no leaf in are left out.
std::vector<PartitionedTree> partitionForRank(const ForestDescription& whole, int rank, int ranks);

/// Number of leaves of the whole forest each rank owns, in rank order.
std::vector<std::size_t> leavesPerRank(const ForestDescription& whole, int ranks);

} // namespace canopy::testing
