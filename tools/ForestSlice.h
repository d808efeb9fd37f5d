// One MPI rank's share of a whole forest, for benchmarks that hand a
// single-process forest (tools/SyntheticForest) to several ranks.
#pragma once

#include <canopy/ForestDescription.h>

#include <cstddef>

namespace canopy::tools
{

/// Contiguous whole trees for `rank` of `ranks` (tree t goes to rank t * ranks / trees),
/// with every field narrowed to those trees' tuples. Needs breadth-first storage
/// (no slot maps, no absent nodes): fields of EveryNode centering are then in node
/// order and LeavesOnly ones in leaf order, tree after tree. With more than one
/// rank the other ranks' trees are marked as elsewhere (3D surfaces stay closed).
/// Throws std::invalid_argument for storage it cannot slice.
ForestDescription rankSlice(const ForestDescription& forest, int rank, int ranks);

/// Leaves of a description (nodes whose refinement byte is 0).
std::size_t countLeaves(const ForestDescription& forest);

/// Nodes of a description.
std::size_t countNodes(const ForestDescription& forest);

} // namespace canopy::tools
