// The full surface of a 1D or 2D tree: one cell (quad, or segment in 1D) per
// visible leaf, with no view to test. This is the case whose cost is the output
// itself (docs/benchmarks.md, "Full-resolution 2D"), so it has a walk of its
// own: each refined node computes its children's boundaries once (f + 1 per
// axis, with HyperTreeAccess::nodeBounds' formula, so every coordinate is the
// same bits), leaf children are written without descending, and the branch
// factor and the axes are compile-time constants.
//
// The cells come in the order of the shared walk (TreeTraversal.h: depth first,
// children in order), so AdaptiveSurfaceBuilder's output is the same cell for
// cell whichever walk wrote it.
#pragma once

#include "AdaptiveSurfaceBuilder.h"
#include "HyperTreeAccess.h"

#include <cstddef>

namespace canopy
{

/// What a tree's full surface holds.
struct FullSurfaceCount
{
  std::size_t cells = 0;
  std::size_t points = 0;
};

/// Writes the full surface of `tree` into `arrays` (room for `limit` cells and
/// `pointLimit` points: nothing is written past them; `pointBase`: the output's
/// index of arrays.points' first point, what the offsets count from) and returns
/// how many cells and points the tree has. Preconditions: grid.dimension() is 1
/// or 2, grid.branchFactor() is 2 or 3.
FullSurfaceCount writeFullSurface(const HyperTreeAccess& grid, const TreeAccess& tree,
                                  const SurfaceArrays& arrays, std::size_t limit,
                                  std::size_t pointLimit, std::size_t pointBase);

} // namespace canopy
