#include "FaceSide.h"

namespace canopy
{

namespace
{

std::array<Vec3, 8> boxCorners(const Vec3& lo, const Vec3& hi)
{
  std::array<Vec3, 8> c;
  for (int k = 0; k < 8; ++k)
  {
    c[k] = {{(k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]}};
  }
  return c;
}

} // namespace

bool FaceSide::lodStops(const Vec3& lo, const Vec3& hi) const
{
  if (!options.view || !options.levelOfDetail)
  {
    return false;
  }
  return options.view->footprintInPixels(boxCorners(lo, hi)) <= options.pixelThreshold;
}

bool FaceSide::lodStops(const TreeAccess& t, const WalkNode& m) const
{
  if (!options.view || !options.levelOfDetail)
  {
    return false;
  }
  Vec3 lo;
  Vec3 hi;
  grid.nodeBounds(t, m.level, m.ijk, lo, hi);
  return lodStops(lo, hi);
}

const TreeAccess* FaceSide::neighbourAcross(const FacePosition& n, int axis, int side,
                                            Index3& across, bool& elsewhere) const
{
  const std::int64_t cells = grid.cellsPerRootAt(n.level);
  across = n.ijk;
  std::array<long, 3> root = n.root;
  across[axis] += side ? 1 : -1;
  if (across[axis] < 0)
  {
    across[axis] = cells - 1;
    root[axis] -= 1;
  }
  else if (across[axis] >= cells)
  {
    across[axis] = 0;
    root[axis] += 1;
  }
  const TreeAccess* tree = grid.treeAt(root[0], root[1], root[2]);
  elsewhere = !tree && grid.treeElsewhere(root[0], root[1], root[2]);
  return tree;
}

WalkNode FaceSide::descentStart(const TreeAccess* neighbour, const FacePosition& n, int axis,
                                const Index3& across) const
{
  if (neighbour != n.tree || !n.path)
  {
    return WalkNode{0, 0, {{0, 0, 0}}};
  }
  if (grid.branchFactor() == 2)
  {
    // The positions agree above their highest differing bit.
    const auto differing = static_cast<std::uint64_t>(across[axis] ^ n.ijk[axis]);
    int bits = 0;
    for (std::uint64_t d = differing; d; d >>= 1)
    {
      ++bits;
    }
    const int level = n.level - bits;
    if (level <= 0)
    {
      return WalkNode{0, 0, {{0, 0, 0}}};
    }
    const int shift = n.level - level;
    return WalkNode{
        n.path[level], level, {{n.ijk[0] >> shift, n.ijk[1] >> shift, n.ijk[2] >> shift}}};
  }
  for (int level = n.level - 1; level > 0; --level)
  {
    const std::int64_t scale = grid.cellsPerRootAt(n.level - level);
    if (across[axis] / scale == n.ijk[axis] / scale)
    {
      return WalkNode{
          n.path[level], level, {{n.ijk[0] / scale, n.ijk[1] / scale, n.ijk[2] / scale}}};
    }
  }
  return WalkNode{0, 0, {{0, 0, 0}}};
}

FaceState FaceSide::faceState(const FacePosition& n, int axis, int side,
                              const TreeAccess*& neighbour, WalkNode& m) const
{
  const FaceState otherRank = options.remoteFaces ? FaceState::Remote : FaceState::Covered;
  Index3 across;
  bool elsewhere = false;
  neighbour = neighbourAcross(n, axis, side, across, elsewhere);
  if (!neighbour)
  {
    return elsewhere ? otherRank : FaceState::Whole;
  }
  // Descend the neighbour tree towards `across` at level n.level.
  m = descentStart(neighbour, n, axis, across);
  while (true)
  {
    if (grid.hasMask() && grid.isMasked(neighbour->globalIndex(m.node)))
    {
      return grid.isAbsent(neighbour->globalIndex(m.node)) ? otherRank : FaceState::Whole;
    }
    if (m.level == n.level)
    {
      // Parts of the face show only where masked descendants of m touch it.
      return neighbour->isLeaf(m.node) || !neighbour->hasMaskedDescendant(m.node)
                 ? FaceState::Covered
                 : FaceState::Parts;
    }
    if (neighbour->isLeaf(m.node))
    {
      return FaceState::Covered;
    }
    // A topology fact only: level of detail on the way is coarserStopCovers'.
    m = childToward(*neighbour, m, n.level, across);
  }
}

bool FaceSide::coarserStopCovers(const FacePosition& n, int axis, int side) const
{
  if (!options.view || !options.levelOfDetail)
  {
    return false;
  }
  Index3 across;
  bool elsewhere = false;
  const TreeAccess* neighbour = neighbourAcross(n, axis, side, across, elsewhere);
  if (!neighbour)
  {
    return false; // the grid's boundary, or another rank's tree: nothing drawn here
  }
  WalkNode m = descentStart(neighbour, n, axis, across);
  // In n's own tree the descent starts at an ancestor of n, which the walk
  // entered without stopping (n was reached): the same rule, not asked again.
  bool ancestorOfN = neighbour == n.tree;
  for (; m.level < n.level; ancestorOfN = false)
  {
    if (grid.hasMask() && grid.isMasked(neighbour->globalIndex(m.node)))
    {
      return false; // a hole (or another rank's part) before any stop
    }
    if (neighbour->isLeaf(m.node))
    {
      return false; // faceState's Covered: never asked
    }
    if (!ancestorOfN && lodStops(*neighbour, m) && !neighbour->hasAbsentDescendant(m.node))
    {
      return true;
    }
    m = childToward(*neighbour, m, n.level, across);
  }
  return false;
}

} // namespace canopy
