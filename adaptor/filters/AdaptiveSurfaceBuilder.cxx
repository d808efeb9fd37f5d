// The adaptive surface's traversal (AdaptiveSurfaceBuilder.h says what it
// computes and why). Longer than the project's usual file (about 900 lines) on
// purpose: the walk (TreeWalk) and the face queries (FaceSide) are one algorithm
// sharing the walk's node frames and ancestor paths; split, those internals
// would have to become a header of their own for no other user.
#include "AdaptiveSurfaceBuilder.h"

#include "EdgeVertices.h"
#include "FullSurfaceWalk.h"
#include "GridSection.h"
#include "SiblingDecisions.h"
#include "TreeProgress.h"
#include "TreeTraversal.h"

#include <vtkSMPTools.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace canopy
{

namespace
{

/// A node of the walk; its inherited bit: strictly inside the view volume (3D),
/// and so are its descendants and faces.
using NodeFrame = WalkNode;

/// Lower corner and upper corner of a node.
void nodeBox(const HyperTreeAccess& grid, const TreeAccess& tree, const NodeFrame& n, Vec3& lo,
             Vec3& hi)
{
  grid.nodeBounds(tree, n.level, n.ijk, lo, hi);
}

std::array<Vec3, 8> boxCorners(const Vec3& lo, const Vec3& hi)
{
  std::array<Vec3, 8> c;
  for (int k = 0; k < 8; ++k)
  {
    c[k] = {{(k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]}};
  }
  return c;
}

/// Child position -> per-axis digit: active axes in increasing order, first fastest.
Index3 childIndex(const NodeFrame& parent, int child, const HyperTreeAccess& grid)
{
  return grid.childPosition(parent.ijk, child);
}

/// Where cells go: counted in the first pass, written in place in the second,
/// so the output is allocated once and never grown or copied.
struct CellSink
{
  SurfaceArrays arrays{nullptr, nullptr, nullptr, nullptr};
  std::size_t next = 0;      ///< cells so far
  std::size_t nextPoint = 0; ///< points so far
  bool counting = true;
  std::size_t limit = 0;      ///< writing: cells the buffer holds (never written past)
  std::size_t pointLimit = 0; ///< writing: points the buffer holds
  std::size_t pointBase = 0;  ///< writing: the output's index of this buffer's first point
  /// Counting into a tree's own buffer (3D: the output is small next to the
  /// walk, so it is walked once and copied, not walked twice).
  TreeCells* keep = nullptr;
};

/// A cell of `count` points (4 or more: a flat piece; 2: a segment of a 1D grid).
/// `color`: the cell's RGB (nullptr without a colour map).
void emitCell(CellSink& out, const Vec3* points, std::size_t count, vtkIdType cellId, int level,
              const Rgb* color)
{
  if (out.keep)
  {
    for (std::size_t k = 0; k < count; ++k)
    {
      out.keep->points.insert(out.keep->points.end(), points[k].begin(), points[k].end());
    }
    out.keep->sizes.push_back(static_cast<std::uint32_t>(count));
    out.keep->cellIds.push_back(cellId);
    out.keep->levels.push_back(static_cast<unsigned char>(level));
    if (color)
    {
      out.keep->colors.insert(
          out.keep->colors.end(),
          {colorByte((*color)[0]), colorByte((*color)[1]), colorByte((*color)[2])});
    }
  }
  else if (!out.counting && out.next < out.limit && out.nextPoint + count <= out.pointLimit)
  {
    double* p = out.arrays.points + 3 * out.nextPoint;
    for (std::size_t k = 0; k < count; ++k)
    {
      *p++ = points[k][0];
      *p++ = points[k][1];
      *p++ = points[k][2];
    }
    out.arrays.offsets[out.next] = static_cast<vtkIdType>(out.pointBase + out.nextPoint);
    out.arrays.cellIds[out.next] = cellId;
    out.arrays.levels[out.next] = static_cast<unsigned char>(level);
    if (color && out.arrays.colors)
    {
      unsigned char* rgb = out.arrays.colors + 3 * out.next;
      for (int k = 0; k < 3; ++k)
      {
        rgb[k] = colorByte((*color)[k]);
      }
    }
  }
  ++out.next;
  out.nextPoint += count;
}

template <std::size_t N>
void emitCell(CellSink& out, const std::array<Vec3, N>& corners, vtkIdType cellId, int level,
              const Rgb* color)
{
  emitCell(out, corners.data(), N, cellId, level, color);
}

/// What lies across a face of a 3D node, a topology fact.
enum FaceState : std::uint32_t
{
  Unknown = 0,
  Covered = 1, ///< nothing to draw: unmasked cells (or, without remote faces, another rank's)
  Whole = 2,   ///< the whole face is drawn: masked, or the grid's boundary
  Parts = 3,   ///< a same-level unmasked neighbour with masked descendants: parts may show
  Remote = 4   ///< (remote faces) another rank's part: the owner says what shows
};

/// A node as the face queries see it: its root cell, level and integer
/// position (no tree needed: the rank answering for the other side has none).
/// The walk that owns the node also gives its tree and its ancestors (path[l]:
/// the ancestor at level l < level), so that a neighbour in the same tree is
/// found from their common ancestor rather than from the root.
struct FacePosition
{
  std::array<long, 3> root;
  int level;
  Index3 ijk;
  const TreeAccess* tree = nullptr;
  const vtkIdType* path = nullptr;
};

/// The other side of a node's faces, in whichever tree holds it: shared by the
/// walk (its own faces) and by a rank answering another rank's remote faces.
struct FaceSide
{
  const HyperTreeAccess& grid;
  const SurfaceOptions& options;

  bool lodStops(const Vec3& lo, const Vec3& hi) const
  {
    if (!options.view || !options.levelOfDetail)
    {
      return false;
    }
    // The box's distinct corners only: a flat box has 4 (2D), a segment 2 (1D).
    const auto& axes = grid.activeAxes();
    const double pixels =
        grid.dimension() == 3 ? options.view->footprintInPixels(boxCorners(lo, hi))
        : grid.dimension() == 2
            ? options.view->footprintInPixels(rectangleCorners(lo, hi, axes[0], axes[1]))
            : options.view->footprintInPixels(segmentEnds(lo, hi, axes[0]));
    return pixels <= options.pixelThreshold;
  }

  bool lodStops(const TreeAccess& t, const NodeFrame& m) const
  {
    if (!options.view || !options.levelOfDetail)
    {
      return false;
    }
    Vec3 mlo;
    Vec3 mhi;
    nodeBox(grid, t, m, mlo, mhi);
    return lodStops(mlo, mhi);
  }

  /// The tree holding the same-level position across a face (nullptr when
  /// outside the grid or without a tree here), and that position in its integer
  /// coordinates. `elsewhere`: the root cell's tree is on another rank.
  const TreeAccess* neighbourAcross(const FacePosition& n, int axis, int side, Index3& across,
                                    bool& elsewhere) const
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

  /// The child of m on the way down to position `target` at level `level`.
  NodeFrame childToward(const TreeAccess& t, const NodeFrame& m, int level,
                        const Index3& target) const
  {
    const int child = grid.childToward(m.level, level, target);
    return {t.firstChild(m.node) + child, m.level + 1, childIndex(m, child, grid)};
  }

  /// Where the descent in `neighbour` towards `across` (at n's level) starts:
  /// the root, or, in n's own tree with n's ancestors known, their deepest
  /// ancestor in common (unmasked, as every ancestor of a visited node is).
  NodeFrame descentStart(const TreeAccess* neighbour, const FacePosition& n, int axis,
                         const Index3& across) const
  {
    if (neighbour != n.tree || !n.path)
    {
      return NodeFrame{0, 0, {{0, 0, 0}}};
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
        return NodeFrame{0, 0, {{0, 0, 0}}};
      }
      const int shift = n.level - level;
      return NodeFrame{
          n.path[level], level, {{n.ijk[0] >> shift, n.ijk[1] >> shift, n.ijk[2] >> shift}}};
    }
    for (int level = n.level - 1; level > 0; --level)
    {
      const std::int64_t scale = grid.cellsPerRootAt(n.level - level);
      if (across[axis] / scale == n.ijk[axis] / scale)
      {
        return NodeFrame{
            n.path[level], level, {{n.ijk[0] / scale, n.ijk[1] / scale, n.ijk[2] / scale}}};
      }
    }
    return NodeFrame{0, 0, {{0, 0, 0}}};
  }

  /// What lies across one face of n; for Parts, the same-level neighbour `m` in
  /// `neighbour`. Another rank's part (an absent cell, or a tree elsewhere) is
  /// Remote with remote faces on, else Covered (solid: faces between ranks are
  /// inside the domain).
  FaceState faceState(const FacePosition& n, int axis, int side, const TreeAccess*& neighbour,
                      NodeFrame& m) const
  {
    const FaceState otherRank = options.remoteFaces ? Remote : Covered;
    Index3 across;
    bool elsewhere = false;
    neighbour = neighbourAcross(n, axis, side, across, elsewhere);
    if (!neighbour)
    {
      return elsewhere ? otherRank : Whole;
    }
    // Descend the neighbour tree towards `across` at level n.level.
    m = descentStart(neighbour, n, axis, across);
    while (true)
    {
      if (grid.hasMask() && grid.isMasked(neighbour->globalIndex(m.node)))
      {
        return grid.isAbsent(neighbour->globalIndex(m.node)) ? otherRank : Whole;
      }
      if (m.level == n.level)
      {
        // Parts of the face show only where masked descendants of m touch it.
        return neighbour->isLeaf(m.node) || !neighbour->hasMaskedDescendant(m.node) ? Covered
                                                                                    : Parts;
      }
      if (neighbour->isLeaf(m.node))
      {
        return Covered;
      }
      // A topology fact only: level of detail on the way is coarserStopCovers'.
      m = childToward(*neighbour, m, n.level, across);
    }
  }

  /// Whether the walk of the tree across a face of n stops for level of detail
  /// (TreeWalk::enter's rule) at an unmasked node coarser than n on the way down
  /// to n's level, before any masked one: that node is drawn as a solid and the
  /// face is inside it. What faceState says Whole or Parts is then covered. It
  /// depends on the view, so it is asked after the (topological) face memo,
  /// never stored in it.
  bool coarserStopCovers(const FacePosition& n, int axis, int side) const
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
    NodeFrame m = descentStart(neighbour, n, axis, across);
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

  /// m: an unmasked node across a face (`axis`, `side` of the node we look
  /// from), at that node's level or finer. Calls masked(child) for each masked
  /// node touching the face that is not covered (an exposed piece) and
  /// absent(child) for each absent one (another rank's part), in child order.
  template <typename Masked, typename Absent>
  void exposedParts(const TreeAccess& t, const NodeFrame& m, int axis, int side,
                    const Masked& masked, const Absent& absent) const
  {
    // Covered where the walk of t would stop (TreeWalk::enter): a leaf, a node
    // with nothing masked below, or a node level of detail draws whole (never
    // one with another rank's parts below it).
    if (t.isLeaf(m.node) || !t.hasMaskedDescendant(m.node) ||
        (lodStops(t, m) && !t.hasAbsentDescendant(m.node)))
    {
      return;
    }
    const int f = grid.branchFactor();
    const vtkIdType first = t.firstChild(m.node);
    for (int c = 0; c < grid.childrenPerNode(); ++c)
    {
      // Only children touching the face: on the near side along `axis`.
      if (grid.childDigits(c)[axis] != (side ? 0 : f - 1))
      {
        continue;
      }
      const NodeFrame child{first + c, m.level + 1, childIndex(m, c, grid)};
      const vtkIdType global = t.globalIndex(child.node);
      if (grid.hasMask() && grid.isMasked(global))
      {
        if (grid.isAbsent(global))
        {
          absent(child);
        }
        else
        {
          masked(child);
        }
        continue;
      }
      exposedParts(t, child, axis, side, masked, absent);
    }
  }
};

/// Shared traversal state of one tree.
struct TreeWalk
{
  const HyperTreeAccess& grid;
  const TreeAccess& tree;
  const SurfaceOptions& options;
  const GridSection* region; ///< 1D and 2D culling, when a view is given
  CellSink& out;
  FaceSide faces{grid, options};

  bool lodStops(const Vec3& lo, const Vec3& hi) const { return faces.lodStops(lo, hi); }

  /// path[l]: the node last entered at level l; in a depth-first walk, the
  /// ancestor at level l of the node being entered (for l below its level).
  std::vector<vtkIdType> path =
      std::vector<vtkIdType>(static_cast<std::size_t>(grid.maxLevel()) + 1, 0);

  FacePosition positionOf(const NodeFrame& n) const
  {
    return {{{static_cast<long>(tree.rootIJK[0]), static_cast<long>(tree.rootIJK[1]),
              static_cast<long>(tree.rootIJK[2])}},
            n.level,
            n.ijk,
            &tree,
            path.data()};
  }

  /// `inside`: set when the whole box is inside the view (3D; then neither it
  /// nor its descendants or faces need another test).
  bool visible(const Vec3& lo, const Vec3& hi, bool& inside) const
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

  /// The shared walk (TreeTraversal.h); its inherited bit is "inside the view".
  void walk()
  {
    Vec3 lo{{0, 0, 0}};
    Vec3 hi{{0, 0, 0}};
    const bool solid3D = grid.dimension() == 3;
    if (solid3D && tree.memoRemote != static_cast<int>(options.remoteFaces))
    {
      // The memos answer "is another rank's part solid?" one way or the other.
      tree.exposeMemo.clear();
      tree.faceMemo.clear();
      tree.memoRemote = static_cast<int>(options.remoteFaces);
    }
    if (grid.dimension() == 2)
    {
      plane =
          std::make_unique<PlaneNeighbours>(grid, tree, grid.activeAxes()[0], grid.activeAxes()[1]);
    }
    walkTree(grid, tree, [&](NodeFrame& n) { return enter(n, solid3D, lo, hi); });
  }

  WalkStep enter(NodeFrame& n, bool solid3D, Vec3& lo, Vec3& hi)
  {
    path[static_cast<std::size_t>(n.level)] = n.node;
    if (plane)
    {
      plane->enter(n);
    }
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
    // 3D, a leaf: its faces are looked at when it is drawn, once.
    const bool leaf = tree.isLeaf(n.node);
    // 3D, a coarse node none of whose faces, nor any inside it, can be exposed
    // draws nothing, whether descent stops there or not (a topology fact).
    if (solid3D && !leaf && !mayExpose(n))
    {
      return WalkStep::Skip;
    }
    // The box is needed to cull and to emit, not to count a full surface.
    bool haveBox = false;
    if (options.view)
    {
      nodeBox(grid, tree, n, lo, hi);
      haveBox = true;
      if (!visible(lo, hi, n.inherited))
      {
        return WalkStep::Skip;
      }
    }
    // A node with absent descendants is never drawn whole: other ranks draw
    // their parts of it, so every pixel keeps exactly one owner.
    const bool stop = leaf || (haveBox && lodStopsHere(tree, n));
    if (stop)
    {
      if (!out.counting || out.keep)
      {
        if (global < 0)
        {
          global = tree.globalIndex(n.node);
        }
        if (!haveBox)
        {
          nodeBox(grid, tree, n, lo, hi);
        }
      }
      if (grid.dimension() == 1)
      {
        const Rgb color = colorOf(n, global, leaf);
        emitCell(out, segmentEnds(lo, hi, grid.activeAxes()[0]), global, n.level,
                 options.colors ? &color : nullptr);
      }
      else if (grid.dimension() == 2)
      {
        const Rgb color = colorOf(n, global, leaf);
        emitPlaneQuad(n, lo, hi, global, options.colors ? &color : nullptr);
      }
      else
      {
        emitExposedFaces(n, lo, hi, global);
      }
      return WalkStep::Skip;
    }
    return WalkStep::Descend;
  }

  bool mayExpose(const NodeFrame& n) const
  {
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

  /// A 2D node's quad, with the corners of finer neighbours on its edges.
  void emitPlaneQuad(const NodeFrame& n, const Vec3& lo, const Vec3& hi, vtkIdType global,
                     const Rgb* color)
  {
    const int u = grid.activeAxes()[0];
    const int v = grid.activeAxes()[1];
    const unsigned remote = rectangleEdgeVertices(
        grid, n, plane->at(n.level), u, v, lo, hi, -1, nullptr,
        [this](const TreeAccess& t, const NodeFrame& m) { return planarRole(t, m); }, onEdge,
        scratch);
    recordShared(remote, u, v, lo, hi);
    polygonAround(rectangleCorners(lo, hi, u, v), u, v, hi,
                  {{&onEdge[0], &onEdge[1], &onEdge[2], &onEdge[3]}}, polygon);
    emitCell(out, polygon.data(), polygon.size(), global, n.level, color);
  }

  /// Keeps the edges (bits of `remote`) of the piece about to be emitted along
  /// which another rank's part was met, and the piece, for the ranks' exchange.
  void recordShared(unsigned remote, int u, int v, const Vec3& lo, const Vec3& hi)
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

  /// What this walk does at a node of a 1D or 2D tree (enter's rule, culling
  /// aside: a culled neighbour draws nothing to meet), for EdgeVertices.h.
  EdgeRole planarRole(const TreeAccess& t, const NodeFrame& m)
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

  /// Whether level of detail stops at the refined, unmasked node m of tree t:
  /// it spans at most the threshold and has no absent descendant (other ranks
  /// draw their parts of it). Kept for the walk's own tree (SiblingDecisions.h).
  bool lodStopsHere(const TreeAccess& t, const NodeFrame& m)
  {
    if (!options.view || !options.levelOfDetail)
    {
      return false;
    }
    auto rule = [&](const NodeFrame& x)
    { return !t.hasAbsentDescendant(x.node) && faces.lodStops(t, x); };
    return &t == &tree ? decisions.get(grid, m, rule) : rule(m);
  }

  SiblingDecisions decisions{grid.maxLevel()}; ///< level of detail's, kept (lodStopsHere)
  std::unique_ptr<PlaneNeighbours> plane{};    ///< 2D: the nodes across each node's edges
  EdgeScratch scratch{};                       ///< the edge searches' memory
  std::array<std::vector<double>, 4> onEdge{}; ///< emitPlaneQuad's scratch
  std::vector<Vec3> polygon{};                 ///< the same

  /// A drawn 1D or 2D node's colour: a leaf's own, a coarser node's the average
  /// of its leaves' (only when it is written: counting needs none).
  Rgb colorOf(const NodeFrame& n, vtkIdType global, bool leaf) const
  {
    if (!options.colors || (out.counting && !out.keep))
    {
      return Rgb{{0, 0, 0}};
    }
    if (leaf)
    {
      return options.colors->mapCell(global);
    }
    return averageColor(grid, tree, n, grid.dimension(), *options.colors, EveryChild{});
  }

  /// Whether the face normal to `axis` on side `side` at coordinate x is turned
  /// away from the camera and back faces are skipped.
  bool turnedAway(int axis, int side, double x) const
  {
    if (!options.view || !options.skipBackFaces)
    {
      return false;
    }
    const double outward = side ? 1.0 : -1.0;
    const double facing = options.view->parallel()
                              ? outward * options.view->directionOfProjection()[axis]
                              : outward * (x - options.view->position()[axis]);
    return facing >= 0;
  }

  /// Face of [lo, hi] (the box of node n, drawn) normal to `axis` on side
  /// `side` (0 low, 1 high), restricted on the two other axes to [plo, phi] (the
  /// face of n's cell at `pieceLevel`, `pieceIJK`: n's own, or a finer one
  /// inside it facing a finer hole), outward-oriented, with the corners of the
  /// pieces meeting its edges (EdgeVertices.h). `ancestors`: n's (path[l] at
  /// level l), or nullptr.
  void emitFace(int axis, int side, const NodeFrame& n, const Vec3& lo, const Vec3& hi,
                const Vec3& plo, const Vec3& phi, int pieceLevel, const Index3& pieceIJK,
                vtkIdType global, bool inside, const vtkIdType* ancestors)
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
        grid, tree, ancestors, n.level, n.ijk, pieceLevel, pieceIJK, axis, side, flo, fhi,
        [this](const TreeAccess& t, const NodeFrame& m) { return solidRole(t, m); }, onEdge,
        scratch);
    recordShared(remote, b, c, flo, fhi);
    polygonAround(q, b, c, fhi, {{&onEdge[0], &onEdge[1], &onEdge[2], &onEdge[3]}}, polygon);
    const Rgb color = options.colors && (!out.counting || out.keep)
                          ? options.colors->mapCell(global)
                          : Rgb{{0, 0, 0}};
    emitCell(out, polygon.data(), polygon.size(), global, n.level,
             options.colors ? &color : nullptr);
  }

  /// What this walk does at a node of a 3D tree (enter's rule; culling aside,
  /// and a subtree with nothing to expose is walked like any), for EdgeVertices.h.
  EdgeRole solidRole(const TreeAccess& t, const NodeFrame& m)
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

  /// For each of the six faces of a node where descent stopped: the parts not
  /// covered by unmasked (or solid-by-level-of-detail) nodes on the other side;
  /// with remote faces, the faces whose other side is partly another rank's are
  /// kept to ask that rank.
  void emitExposedFaces(const NodeFrame& n, const Vec3& lo, const Vec3& hi, vtkIdType global)
  {
    std::uint32_t scratch = 0;
    auto& memo = tree.faceMemo;
    if (options.memoize && memo.empty())
    {
      memo.assign(static_cast<std::size_t>(tree.numberOfVertices), 0);
    }
    std::uint32_t& known = options.memoize ? memo[static_cast<std::size_t>(n.node)] : scratch;
    const FacePosition position = positionOf(n);
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
        const TreeAccess* neighbour = nullptr;
        NodeFrame m{0, 0, {{0, 0, 0}}};
        if (state == Unknown)
        {
          state = faces.faceState(position, axis, side, neighbour, m);
          known |= static_cast<std::uint32_t>(state) << shift;
        }
        // The memo holds the topology; the view may cover what it says shows.
        if ((state == Whole || state == Parts) && faces.coarserStopCovers(position, axis, side))
        {
          state = Covered;
        }
        else if (state == Parts && !neighbour)
        {
          faces.faceState(position, axis, side, neighbour, m); // the neighbour itself
        }
        bool ask = state == Remote;
        if (state == Whole)
        {
          emitFace(axis, side, n, lo, hi, lo, hi, n.level, n.ijk, global, n.inherited, path.data());
        }
        else if (state == Parts)
        {
          // Same-level neighbour, unmasked: exposed where its descendants touching
          // the face are masked; where they are another rank's, that rank says.
          faces.exposedParts(
              *neighbour, m, axis, side,
              [&](const NodeFrame& child)
              {
                Vec3 clo;
                Vec3 chi;
                nodeBox(grid, *neighbour, child, clo, chi);
                // The piece is the face of n's cell facing the hole, at the hole's level.
                Index3 cell = child.ijk;
                const std::int64_t scale = grid.cellsPerRootAt(child.level - n.level);
                cell[axis] = side ? (n.ijk[axis] + 1) * scale - 1 : n.ijk[axis] * scale;
                emitFace(axis, side, n, lo, hi, clo, chi, child.level, cell, global, n.inherited,
                         path.data());
              },
              [&](const NodeFrame&) { ask = ask || options.remoteFaces; });
        }
        if (ask && out.keep)
        {
          const RemoteFace face{
              {{position.root[0], position.root[1], position.root[2]}}, n.level, n.ijk, axis, side};
          out.keep->asked.push_back({face, global, n.inherited});
        }
      }
    }
  }

  /// 3D: whether any face inside an unmasked node's subtree can be exposed:
  /// yes if something below it is masked or a neighbour region across one of
  /// its faces is not solid (absent, masked, or with masked parts).
  bool mayExposeInside(const NodeFrame& n) const
  {
    if (tree.hasMaskedDescendant(n.node))
    {
      return true;
    }
    for (int axis = 0; axis < 3; ++axis)
    {
      for (int side = 0; side < 2; ++side)
      {
        Index3 across;
        bool elsewhere = false;
        const FacePosition position = positionOf(n);
        const TreeAccess* neighbour =
            faces.neighbourAcross(position, axis, side, across, elsewhere);
        if (!neighbour)
        {
          if (elsewhere && !options.remoteFaces)
          {
            continue; // another rank's tree: solid
          }
          return true;
        }
        NodeFrame m = faces.descentStart(neighbour, position, axis, across);
        while (true)
        {
          if (grid.hasMask() && grid.isMasked(neighbour->globalIndex(m.node)))
          {
            return true;
          }
          if (m.level == n.level || neighbour->isLeaf(m.node))
          {
            if (neighbour->hasMaskedDescendant(m.node))
            {
              return true;
            }
            break; // solid
          }
          m = faces.childToward(*neighbour, m, n.level, across);
        }
      }
    }
    return false;
  }
};

} // namespace

void copyKeptCells(const std::vector<TreeCells>& kept, const std::vector<std::size_t>& cellOffsets,
                   const std::vector<std::size_t>& pointOffsets, const SurfaceArrays& arrays)
{
  // A copy: not worth reporting progress or stopping.
  vtkSMPTools::For(
      0, static_cast<vtkIdType>(kept.size()),
      [&](vtkIdType begin, vtkIdType end)
      {
        for (vtkIdType i = begin; i < end; ++i)
        {
          const TreeCells& cells = kept[static_cast<std::size_t>(i)];
          const std::size_t first = cellOffsets[static_cast<std::size_t>(i)];
          std::size_t point = pointOffsets[static_cast<std::size_t>(i)];
          std::copy(cells.points.begin(), cells.points.end(), arrays.points + 3 * point);
          vtkIdType* offset = arrays.offsets + first;
          for (std::uint32_t size : cells.sizes)
          {
            *offset++ = static_cast<vtkIdType>(point);
            point += size;
          }
          std::copy(cells.cellIds.begin(), cells.cellIds.end(), arrays.cellIds + first);
          std::copy(cells.levels.begin(), cells.levels.end(), arrays.levels + first);
          if (arrays.colors)
          {
            std::copy(cells.colors.begin(), cells.colors.end(), arrays.colors + 3 * first);
          }
        }
      });
  arrays.offsets[cellOffsets.empty() ? 0 : cellOffsets.back()] =
      static_cast<vtkIdType>(pointOffsets.empty() ? 0 : pointOffsets.back());
}

AdaptiveSurfaceBuilder::AdaptiveSurfaceBuilder(const HyperTreeAccess& grid,
                                               const SurfaceOptions& options,
                                               std::vector<TreeCells>* buffers,
                                               const ProgressShare& progress)
    : Grid(grid), Options(options), Progress(progress), Lent(buffers)
{
  if (Lent)
  {
    Kept.swap(*Lent);
  }
  if (Grid.dimension() < 3 && Options.view && Options.cullOutsideView)
  {
    Region =
        std::make_unique<GridSection>(Grid, Options.view->halfSpaces(), Options.view->anchor());
  }
}

AdaptiveSurfaceBuilder::~AdaptiveSurfaceBuilder()
{
  if (Lent)
  {
    Lent->swap(Kept);
  }
}

bool AdaptiveSurfaceBuilder::fullPlanarSurface() const
{
  return Grid.dimension() < 3 && Grid.branchFactor() <= 3 &&
         (!Options.view || (!Options.cullOutsideView && !Options.levelOfDetail));
}

std::size_t AdaptiveSurfaceBuilder::count()
{
  const auto& trees = Grid.trees();
  std::vector<std::size_t> counts(trees.size(), 0);
  std::vector<std::size_t> pointCounts(trees.size(), 0);
  // A full 1D/2D surface has one cell per visible leaf: a kept access knows how
  // many per tree, so one walk (the writing one) suffices.
  const bool known = std::all_of(trees.begin(), trees.end(),
                                 [](const TreeAccess& t) { return t.visibleLeaves >= 0; });
  CountWalked = false;
  // Cells are kept to be copied (3D: the output is small next to the walk), or
  // to take the vertices other ranks put on their edges (2D, split grids).
  const bool keep = Grid.dimension() == 3 || (Grid.dimension() == 2 && Options.sharedVertices);
  if (!keep)
  {
    Kept.clear(); // buffers lent from an execution that kept its cells: not used here
  }
  if (fullPlanarSurface() && known && !keep)
  {
    std::transform(trees.begin(), trees.end(), counts.begin(),
                   [](const TreeAccess& t) { return static_cast<std::size_t>(t.visibleLeaves); });
    // Their points, once per topology: a walk that writes nothing.
    CountWalked = std::any_of(trees.begin(), trees.end(),
                              [](const TreeAccess& t) { return t.fullSurfacePoints < 0; });
    forEachTree(CountWalked ? Progress.part(0, 0.5) : ProgressShare{},
                static_cast<vtkIdType>(trees.size()),
                [&](vtkIdType t)
                {
                  const TreeAccess& tree = trees[static_cast<std::size_t>(t)];
                  if (tree.fullSurfacePoints < 0)
                  {
                    const SurfaceArrays none{nullptr, nullptr, nullptr, nullptr};
                    tree.fullSurfacePoints =
                        static_cast<vtkIdType>(writeFullSurface(Grid, tree, none, 0, 0, 0).points);
                  }
                  pointCounts[static_cast<std::size_t>(t)] =
                      static_cast<std::size_t>(tree.fullSurfacePoints);
                });
  }
  else
  {
    if (keep)
    {
      // Cleared, not freed: lent buffers keep their capacity.
      Kept.resize(trees.size());
      for (TreeCells& cells : Kept)
      {
        cells.points.clear();
        cells.sizes.clear();
        cells.cellIds.clear();
        cells.levels.clear();
        cells.colors.clear();
        cells.asked.clear();
        cells.shared.clear();
        cells.sharedCells.clear();
      }
    }
    // Kept cells (3D) are only copied afterwards: then this walk is all the work.
    CountWalked = true;
    forEachTree(
        Kept.empty() ? Progress.part(0, 0.5) : Progress, static_cast<vtkIdType>(trees.size()),
        [&](vtkIdType t)
        {
          CellSink sink;
          sink.keep = Kept.empty() ? nullptr : &Kept[static_cast<std::size_t>(t)];
          TreeWalk walk{Grid, trees[static_cast<std::size_t>(t)], Options, Region.get(), sink};
          walk.walk();
          counts[static_cast<std::size_t>(t)] = sink.next;
          pointCounts[static_cast<std::size_t>(t)] = sink.nextPoint;
        });
  }
  AskedAt.clear();
  for (std::size_t t = 0; t < Kept.size(); ++t)
  {
    for (std::size_t k = 0; k < Kept[t].asked.size(); ++k)
    {
      AskedAt.emplace_back(t, k);
    }
  }
  computeOffsets(counts, pointCounts);
  return Offsets.back();
}

void AdaptiveSurfaceBuilder::computeOffsets(const std::vector<std::size_t>& counts,
                                            const std::vector<std::size_t>& pointCounts)
{
  // Trees write at prefix-sum offsets: the output order is the tree order, the
  // same for any number of threads.
  Offsets.assign(counts.size() + 1, 0);
  PointOffsets.assign(counts.size() + 1, 0);
  for (std::size_t t = 0; t < counts.size(); ++t)
  {
    Offsets[t + 1] = Offsets[t] + counts[t];
    PointOffsets[t + 1] = PointOffsets[t] + pointCounts[t];
  }
}

std::vector<RemoteFace> AdaptiveSurfaceBuilder::remoteFaces() const
{
  std::vector<RemoteFace> faces;
  faces.reserve(AskedAt.size());
  for (const auto& [t, k] : AskedAt)
  {
    faces.push_back(Kept[t].asked[k].face);
  }
  return faces;
}

std::vector<RemotePiece>
AdaptiveSurfaceBuilder::answerRemoteFaces(const std::vector<RemoteFace>& faces) const
{
  // The other side of each face, in the trees this rank has: what it masks
  // there shows; what it does not have (absent, or no tree) another rank answers.
  std::vector<RemotePiece> pieces;
  const FaceSide side{Grid, Options};
  for (std::size_t q = 0; q < faces.size(); ++q)
  {
    const RemoteFace& f = faces[q];
    const FacePosition n{{{static_cast<long>(f.root[0]), static_cast<long>(f.root[1]),
                           static_cast<long>(f.root[2])}},
                         static_cast<int>(f.level),
                         f.ijk};
    const int axis = static_cast<int>(f.axis);
    const int towards = static_cast<int>(f.side);
    if (axis < 0 || axis > 2 || f.level < 0 || f.level > Grid.maxLevel())
    {
      continue; // not a face of a grid like this one: nothing of it is here
    }
    Index3 across;
    bool elsewhere = false;
    if (!side.neighbourAcross(n, axis, towards, across, elsewhere))
    {
      continue; // no tree here on the other side
    }
    const TreeAccess* neighbour = nullptr;
    NodeFrame m{0, 0, {{0, 0, 0}}};
    const FaceState state = side.faceState(n, axis, towards, neighbour, m);
    if ((state == Whole || state == Parts) && side.coarserStopCovers(n, axis, towards))
    {
      continue; // this rank draws a coarser node there whole: the face is inside it
    }
    if (state == Whole)
    {
      pieces.push_back({q, true, {{0, 0, 0}}, {{0, 0, 0}}});
    }
    else if (state == Parts)
    {
      side.exposedParts(
          *neighbour, m, axis, towards,
          [&](const NodeFrame& child)
          {
            RemotePiece piece{q, false, {{0, 0, 0}}, {{0, 0, 0}}, child.level, child.ijk};
            nodeBox(Grid, *neighbour, child, piece.lo, piece.hi);
            pieces.push_back(piece);
          },
          [](const NodeFrame&) {});
    }
  }
  return pieces;
}

void AdaptiveSurfaceBuilder::addRemotePieces(const std::vector<RemotePiece>& pieces)
{
  const auto& trees = Grid.trees();
  for (const RemotePiece& piece : pieces)
  {
    if (piece.face >= AskedAt.size())
    {
      throw std::invalid_argument("a remote piece answers a face that was not asked");
    }
    const auto [t, k] = AskedAt[piece.face];
    const AskedFace& asked = Kept[t].asked[k];
    CellSink sink;
    sink.keep = &Kept[t];
    TreeWalk walk{Grid, trees[t], Options, Region.get(), sink};
    const NodeFrame n{0, static_cast<int>(asked.face.level), asked.face.ijk};
    const int axis = static_cast<int>(asked.face.axis);
    const int side = static_cast<int>(asked.face.side);
    Vec3 lo;
    Vec3 hi;
    nodeBox(Grid, trees[t], n, lo, hi);
    // The piece's cell on this side: n, or the cell of n facing the owner's hole.
    Index3 cell = n.ijk;
    int level = n.level;
    if (!piece.whole)
    {
      if (piece.level < n.level || piece.level > Grid.maxLevel())
      {
        throw std::invalid_argument("a remote piece is coarser than its face, or too deep");
      }
      level = static_cast<int>(piece.level);
      const std::int64_t scale = Grid.cellsPerRootAt(level - n.level);
      cell = piece.ijk;
      cell[axis] = side ? (n.ijk[axis] + 1) * scale - 1 : n.ijk[axis] * scale;
    }
    walk.emitFace(axis, side, n, lo, hi, piece.whole ? lo : piece.lo, piece.whole ? hi : piece.hi,
                  level, cell, asked.global, asked.inside, nullptr);
  }
  std::vector<std::size_t> counts(Kept.size());
  std::vector<std::size_t> pointCounts(Kept.size());
  for (std::size_t t = 0; t < Kept.size(); ++t)
  {
    counts[t] = Kept[t].cellIds.size();
    pointCounts[t] = Kept[t].points.size() / 3;
  }
  computeOffsets(counts, pointCounts);
}

std::vector<SharedEdge> AdaptiveSurfaceBuilder::sharedEdges() const
{
  std::vector<SharedEdge> edges;
  for (const TreeCells& cells : Kept)
  {
    edges.insert(edges.end(), cells.shared.begin(), cells.shared.end());
  }
  return edges;
}

void AdaptiveSurfaceBuilder::addSharedVertices(const SharedVertices& shared)
{
  std::vector<std::size_t> counts(Kept.size());
  std::vector<std::size_t> pointCounts(Kept.size());
  vtkSMPTools::For(0, static_cast<vtkIdType>(Kept.size()),
                   [&](vtkIdType begin, vtkIdType end)
                   {
                     for (vtkIdType t = begin; t < end; ++t)
                     {
                       TreeCells& cells = Kept[static_cast<std::size_t>(t)];
                       insertSharedVertices(cells, cells.sharedCells, shared);
                       counts[static_cast<std::size_t>(t)] = cells.cellIds.size();
                       pointCounts[static_cast<std::size_t>(t)] = cells.points.size() / 3;
                     }
                   });
  computeOffsets(counts, pointCounts);
}

void AdaptiveSurfaceBuilder::write(const SurfaceArrays& arrays) const
{
  const auto& trees = Grid.trees();
  if (!Kept.empty())
  {
    copyKeptCells(Kept, Offsets, PointOffsets, arrays);
    return;
  }
  const bool full = fullPlanarSurface();
  std::atomic<bool> mismatch{false};
  // The second half of the work, or all of it when count() did not walk.
  forEachTree(
      CountWalked ? Progress.part(0.5, 1) : Progress, static_cast<vtkIdType>(trees.size()),
      [&](vtkIdType t)
      {
        const std::size_t first = Offsets[static_cast<std::size_t>(t)];
        const std::size_t firstPoint = PointOffsets[static_cast<std::size_t>(t)];
        CellSink sink;
        sink.counting = false;
        sink.limit = Offsets[static_cast<std::size_t>(t) + 1] - first;
        sink.pointLimit = PointOffsets[static_cast<std::size_t>(t) + 1] - firstPoint;
        sink.pointBase = firstPoint;
        sink.arrays = {arrays.points + 3 * firstPoint, arrays.offsets + first,
                       arrays.cellIds + first, arrays.levels + first,
                       arrays.colors ? arrays.colors + 3 * first : nullptr};
        const TreeAccess& tree = trees[static_cast<std::size_t>(t)];
        if (full)
        {
          const FullSurfaceCount written =
              writeFullSurface(Grid, tree, sink.arrays, sink.limit, sink.pointLimit, firstPoint);
          sink.next = written.cells;
          sink.nextPoint = written.points;
          // Every cell of a full surface is a leaf: its own colour.
          for (std::size_t i = 0;
               Options.colors && sink.arrays.colors && i < std::min(sink.next, sink.limit); ++i)
          {
            const Rgb c = Options.colors->mapCell(sink.arrays.cellIds[i]);
            for (int k = 0; k < 3; ++k)
            {
              sink.arrays.colors[3 * i + k] = colorByte(c[k]);
            }
          }
        }
        else
        {
          TreeWalk walk{Grid, tree, Options, Region.get(), sink};
          walk.walk();
        }
        if (sink.next != sink.limit || sink.nextPoint != sink.pointLimit)
        {
          mismatch = true; // never expected: counts come from the same topology
        }
      });
  if (mismatch)
  {
    throw std::logic_error("the surface's cell count changed between counting and writing");
  }
  arrays.offsets[cells()] = static_cast<vtkIdType>(points());
}

} // namespace canopy
