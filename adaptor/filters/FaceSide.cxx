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

SolidNeighbours::Neighbour FaceSide::across(const FacePosition& n, int axis, int side,
                                            Index3& position) const
{
  using Neighbour = SolidNeighbours::Neighbour;
  bool elsewhere = false;
  const TreeAccess* tree = neighbourAcross(n, axis, side, position, elsewhere);
  if (!tree)
  {
    return {elsewhere ? Neighbour::Kind::Elsewhere : Neighbour::Kind::Border, nullptr, 0};
  }
  // Down from the root towards the position, until a masked node or a leaf.
  Neighbour m = SolidNeighbours::nodeAt(grid, *tree, 0);
  for (int level = 0; level < n.level && m.kind == Neighbour::Kind::Node; ++level)
  {
    m = SolidNeighbours::childOf(grid, m, grid.childToward(level, n.level, position));
  }
  return m;
}

FaceState FaceSide::stateOf(const SolidNeighbours::Neighbour& across) const
{
  using Kind = SolidNeighbours::Neighbour::Kind;
  const FaceState otherRank = options.remoteFaces ? FaceState::Remote : FaceState::Covered;
  switch (across.kind)
  {
  case Kind::Border:
  case Kind::Hidden:
    return FaceState::Whole;
  case Kind::Elsewhere:
  case Kind::Absent:
    return otherRank;
  case Kind::CoarserLeaf:
    return FaceState::Covered;
  default:
    // Parts of the face show only where masked descendants of the node touch it.
    return across.tree->isLeaf(across.node) || !across.tree->hasMaskedDescendant(across.node)
               ? FaceState::Covered
               : FaceState::Parts;
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
  for (WalkNode m{0, 0, {{0, 0, 0}}}; m.level < n.level;)
  {
    if (grid.hasMask() && grid.isMasked(neighbour->globalIndex(m.node)))
    {
      return false; // a hole (or another rank's part) before any stop
    }
    if (neighbour->isLeaf(m.node))
    {
      return false; // stateOf's Covered: never asked
    }
    if (lodStops(*neighbour, m) && !neighbour->hasAbsentDescendant(m.node))
    {
      return true;
    }
    const int child = grid.childToward(m.level, n.level, across);
    m = {neighbour->firstChild(m.node) + child, m.level + 1, grid.childPosition(m.ijk, child)};
  }
  return false;
}

} // namespace canopy
