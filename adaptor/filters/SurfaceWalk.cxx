#include "SurfaceWalk.h"

#include "GridSection.h"

namespace canopy
{

SurfaceWalk::SurfaceWalk(const HyperTreeAccess& grid, const TreeAccess& tree,
                         const SurfaceOptions& options, const GridSection* region, CellSink& out)
    : grid(grid), tree(tree), options(options), region(region), out(out),
      decisions(deepestLevel(grid, tree))
{
}

void SurfaceWalk::walk()
{
  Vec3 lo{{0, 0, 0}};
  Vec3 hi{{0, 0, 0}};
  walkTree(grid, tree, [&](WalkNode& n) { return enter(n, lo, hi); });
}

WalkStep SurfaceWalk::enter(WalkNode& n, Vec3& lo, Vec3& hi)
{
  entered(n);
  // The global index costs a virtual call for explicit indices: only when needed.
  vtkIdType global = -1;
  if (grid.hasMask())
  {
    global = tree.globalIndex(n.node);
    if (grid.isMasked(global))
    {
      return WalkStep::Skip;
    }
  }
  const bool leaf = tree.isLeaf(n.node);
  if (!leaf && !mayDrawBelow(n))
  {
    return WalkStep::Skip;
  }
  // The box is needed to cull and to emit, not to count a full surface.
  bool haveBox = false;
  if (options.view)
  {
    grid.nodeBounds(tree, n.level, n.ijk, lo, hi);
    haveBox = true;
    if (!visible(lo, hi, n.inherited))
    {
      return WalkStep::Skip;
    }
  }
  // A node with absent descendants is never drawn whole: other ranks draw
  // their parts of it, so every pixel keeps exactly one owner.
  const bool stop = leaf || (haveBox && lodStopsHere(tree, n));
  if (!stop)
  {
    return WalkStep::Descend;
  }
  if (out.takesContents())
  {
    if (global < 0)
    {
      global = tree.globalIndex(n.node);
    }
    if (!haveBox)
    {
      grid.nodeBounds(tree, n.level, n.ijk, lo, hi);
    }
  }
  draw(n, lo, hi, global, leaf);
  return WalkStep::Skip;
}

bool SurfaceWalk::visible(const Vec3& lo, const Vec3& hi, bool& inside) const
{
  if (!options.view || !options.cullOutsideView || inside)
  {
    return true;
  }
  if (region)
  {
    return region->overlaps(lo, hi);
  }
  switch (options.view->classifyBox(lo, hi))
  {
  case ViewVolume::BoxSide::Outside:
    return false;
  case ViewVolume::BoxSide::Inside:
    inside = true;
    return true;
  default:
    return options.view->overlapsBox(lo, hi);
  }
}

bool SurfaceWalk::lodStopsHere(const TreeAccess& t, const WalkNode& m)
{
  if (!options.view || !options.levelOfDetail)
  {
    return false;
  }
  auto rule = [&](const WalkNode& x)
  {
    if (t.hasAbsentDescendant(x.node))
    {
      return false;
    }
    Vec3 lo;
    Vec3 hi;
    grid.nodeBounds(t, x.level, x.ijk, lo, hi);
    return footprintStops(lo, hi);
  };
  return &t == &tree ? decisions.get(grid, m, rule) : rule(m);
}

EdgeRole SurfaceWalk::roleAt(const TreeAccess& t, const WalkNode& m)
{
  const vtkIdType global = t.globalIndex(m.node);
  if (grid.hasMask() && grid.isMasked(global))
  {
    return grid.isAbsent(global) ? EdgeRole::Remote : EdgeRole::Hidden;
  }
  if (t.isLeaf(m.node))
  {
    return EdgeRole::Drawn;
  }
  return lodStopsHere(t, m) ? EdgeRole::Drawn : EdgeRole::Descend;
}

void SurfaceWalk::recordShared(unsigned remote, int u, int v, const Vec3& lo, const Vec3& hi)
{
  if (!remote || !out.keep)
  {
    return;
  }
  for (int e = 0; e < 4; ++e)
  {
    if (remote & (1u << e))
    {
      out.keep->shared.push_back(sharedEdgeOf(e, u, v, lo, hi));
    }
  }
  out.keep->sharedCells.push_back(static_cast<std::uint32_t>(out.keep->cellIds.size()));
}

} // namespace canopy
