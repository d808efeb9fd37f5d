#include "SolidSurfaceWalk.h"

#include "FaceEdgeVertices.h"

#include <stdexcept>
#include <utility>

namespace canopy
{

SolidSurfaceWalk::SolidSurfaceWalk(const HyperTreeAccess& grid, const TreeAccess& tree,
                                   const SurfaceOptions& options, CellSink& out)
    : SurfaceWalk(grid, tree, options, nullptr, out), faces{grid, options}, around(grid, tree)
{
  if (tree.memoRemote != static_cast<int>(options.remoteFaces))
  {
    // The memos answer "is another rank's part solid?" one way or the other.
    tree.exposeMemo.clear();
    tree.faceMemo.clear();
    tree.memoRemote = static_cast<int>(options.remoteFaces);
  }
}

WalkNode SolidSurfaceWalk::enterPath(int level, const Index3& ijk)
{
  WalkNode n{0, 0, {{0, 0, 0}}};
  while (true)
  {
    around.enter(n);
    if (n.level == level)
    {
      return n;
    }
    if (tree.isLeaf(n.node))
    {
      throw std::logic_error("a face this rank drew lies below one of its leaves");
    }
    const int child = grid.childToward(n.level, level, ijk);
    n = {tree.firstChild(n.node) + child, n.level + 1, grid.childPosition(n.ijk, child)};
  }
}

bool SolidSurfaceWalk::mayDrawBelow(const WalkNode& n)
{
  // None of a coarse node's faces, nor any inside it, can be exposed: it draws
  // nothing, whether descent stops there or not (a topology fact, kept).
  if (!options.memoize)
  {
    return mayExposeInside(n);
  }
  auto& memo = tree.exposeMemo;
  if (memo.empty())
  {
    memo.assign(static_cast<std::size_t>(tree.numberOfVertices), 0);
  }
  unsigned char& known = memo[static_cast<std::size_t>(n.node)];
  if (known == 0)
  {
    known = mayExposeInside(n) ? 2 : 1;
  }
  return known == 2;
}

void SolidSurfaceWalk::emitFace(int axis, int side, const WalkNode& n, const Vec3& lo,
                                const Vec3& hi, const Vec3& plo, const Vec3& phi, int pieceLevel,
                                const Index3& pieceIJK, vtkIdType global, bool inside)
{
  const int b = (axis + 1) % 3;
  const int c = (axis + 2) % 3;
  const double x = side ? hi[axis] : lo[axis];
  if (turnedAway(axis, side, x))
  {
    return;
  }
  Vec3 flo = plo;
  Vec3 fhi = phi;
  flo[axis] = fhi[axis] = x;
  // A visible node's face can still lie outside the view: a face with no
  // area inside the view volume is not drawn.
  if (options.view && options.cullOutsideView && !inside && !options.view->overlapsBox(flo, fhi))
  {
    return;
  }
  // Counter-clockwise seen from +axis (b x c); reversed on the low side, whose
  // outward normal is -axis.
  std::array<Vec3, 4> q = rectangleCorners(flo, fhi, b, c);
  if (!side)
  {
    std::swap(q[1], q[3]);
  }
  const unsigned remote = faceEdgeVertices(
      grid, n.level, n.ijk, pieceLevel, pieceIJK, axis, side, flo, fhi,
      [&](const SolidNeighbours::Direction& d) -> const SolidNeighbours::Neighbour&
      { return around.at(n.level, d); },
      [this](const TreeAccess& t, const WalkNode& m) { return roleAt(t, m); }, onEdge, scratch);
  recordShared(remote, b, c, flo, fhi);
  polygonAround(q, b, c, fhi, {{&onEdge[0], &onEdge[1], &onEdge[2], &onEdge[3]}}, polygon);
  const Rgb color =
      options.colors && out.takesContents() ? options.colors->mapCell(global) : Rgb{{0, 0, 0}};
  out.emit(polygon.data(), polygon.size(), global, n.level, options.colors ? &color : nullptr);
}

void SolidSurfaceWalk::draw(const WalkNode& n, const Vec3& lo, const Vec3& hi, vtkIdType global,
                            bool)
{
  std::uint32_t scratchState = 0;
  auto& memo = tree.faceMemo;
  if (options.memoize && memo.empty())
  {
    memo.assign(static_cast<std::size_t>(tree.numberOfVertices), 0);
  }
  std::uint32_t& known = options.memoize ? memo[static_cast<std::size_t>(n.node)] : scratchState;
  const bool lod = options.view && options.levelOfDetail;
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int side = 0; side < 2; ++side)
    {
      if (turnedAway(axis, side, side ? hi[axis] : lo[axis]))
      {
        continue; // not drawn, whatever lies across (remote faces: nothing to ask)
      }
      const int shift = 3 * (2 * axis + side);
      auto state = static_cast<FaceState>((known >> shift) & 7);
      if (state == FaceState::Unknown)
      {
        state = faces.stateOf(around.at(n.level, SolidNeighbours::faceDirection(axis, side)));
        known |= static_cast<std::uint32_t>(state) << shift;
      }
      // The memo holds the topology; the view may cover what it says shows.
      if ((state == FaceState::Whole || state == FaceState::Parts) && lod &&
          around.coarserStop(n.level, axis, side,
                             [this](const TreeAccess& t, const WalkNode& m)
                             { return lodStopsHere(t, m); }))
      {
        state = FaceState::Covered;
      }
      bool ask = state == FaceState::Remote;
      if (state == FaceState::Whole)
      {
        emitFace(axis, side, n, lo, hi, lo, hi, n.level, n.ijk, global, n.inherited);
      }
      else if (state == FaceState::Parts)
      {
        // Same-level neighbour, unmasked: exposed where its descendants touching
        // the face are masked; where they are another rank's, that rank says.
        const SolidNeighbours::Direction d = SolidNeighbours::faceDirection(axis, side);
        const TreeAccess& across = *around.at(n.level, d).tree;
        faces.exposedParts(
            across, around.walkNodeAt(n.level, d), axis, side,
            [&](const WalkNode& child)
            {
              Vec3 clo;
              Vec3 chi;
              grid.nodeBounds(across, child.level, child.ijk, clo, chi);
              // The piece is the face of n's cell facing the hole, at the hole's level.
              Index3 cell = child.ijk;
              const std::int64_t scale = grid.cellsPerRootAt(child.level - n.level);
              cell[axis] = side ? (n.ijk[axis] + 1) * scale - 1 : n.ijk[axis] * scale;
              emitFace(axis, side, n, lo, hi, clo, chi, child.level, cell, global, n.inherited);
            },
            [&](const WalkNode&) { ask = ask || options.remoteFaces; });
      }
      if (ask && out.keep)
      {
        const RemoteFace face{{{static_cast<std::int64_t>(tree.rootIJK[0]),
                                static_cast<std::int64_t>(tree.rootIJK[1]),
                                static_cast<std::int64_t>(tree.rootIJK[2])}},
                              n.level,
                              n.ijk,
                              axis,
                              side};
        out.keep->asked.push_back({face, global, n.inherited});
      }
    }
  }
}

bool SolidSurfaceWalk::mayExposeInside(const WalkNode& n)
{
  if (tree.hasMaskedDescendant(n.node))
  {
    return true;
  }
  using Kind = SolidNeighbours::Neighbour::Kind;
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int side = 0; side < 2; ++side)
    {
      const SolidNeighbours::Neighbour& across =
          around.at(n.level, SolidNeighbours::faceDirection(axis, side));
      switch (across.kind)
      {
      case Kind::Node:
        if (across.tree->hasMaskedDescendant(across.node))
        {
          return true;
        }
        break; // solid
      case Kind::CoarserLeaf:
        break; // solid
      case Kind::Elsewhere:
        if (options.remoteFaces)
        {
          return true;
        }
        break; // another rank's tree: solid
      default:
        return true; // the grid's border, a hole, another rank's part of the tree
      }
    }
  }
  return false;
}

} // namespace canopy
