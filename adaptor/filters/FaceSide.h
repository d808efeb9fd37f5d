// The other side of a 3D node's faces, in whichever tree holds it: what the
// face walk (SolidSurfaceWalk.h) asks about its drawn nodes' faces, and what a
// rank asks about the faces other ranks send it (AdaptiveSurfaceBuilder's
// answerRemoteFaces), so that both answer by the same rule.
//
// Across a face lies, at the node's level, a same-level position: outside the
// grid, in another rank's part, below a masked node (a hole), in a leaf as
// large or larger (covered), or a same-level unmasked node whose masked
// descendants may leave parts of the face exposed. That is a topology fact
// (stateOf), kept by the walk per node and face across camera moves. Level of
// detail is applied on top of it, never stored: a node on the way where the
// neighbour tree's walk stops (drawn as a solid) covers the face. The walk
// carries the positions and that question down the tree (SolidNeighbours.h);
// for another rank's face, whose node this rank does not have, they are looked
// for from the root of the tree across (across, coarserStopCovers).
#pragma once

#include "AdaptiveSurfaceBuilder.h"
#include "HyperTreeAccess.h"
#include "SolidNeighbours.h"
#include "TreeTraversal.h"
#include "Vec3.h"

#include <array>
#include <cstdint>

namespace canopy
{

using Index3 = std::array<std::int64_t, 3>;

/// What lies across a face of a 3D node, a topology fact (3 bits: the walk
/// keeps one per face of each node, SolidSurfaceWalk.h).
enum class FaceState : std::uint32_t
{
  Unknown = 0,
  Covered = 1, ///< nothing to draw: unmasked cells (or, without remote faces, another rank's)
  Whole = 2,   ///< the whole face is drawn: masked, or the grid's boundary
  Parts = 3,   ///< a same-level unmasked neighbour with masked descendants: parts may show
  Remote = 4   ///< (remote faces) another rank's part: the owner says what shows
};

/// A node as another rank's face gives it: its root cell, level and integer
/// position (no tree needed: the rank answering for the other side has none).
struct FacePosition
{
  std::array<long, 3> root;
  int level;
  Index3 ijk;
};

struct FaceSide
{
  const HyperTreeAccess& grid;
  const SurfaceOptions& options;

  /// Whether level of detail stops at a node whose box is [lo, hi] (its eight
  /// corners' footprint at most the pixel threshold), or at node m of tree t.
  bool lodStops(const Vec3& lo, const Vec3& hi) const;
  bool lodStops(const TreeAccess& t, const WalkNode& m) const;

  /// The tree holding the same-level position across a face (nullptr when
  /// outside the grid or without a tree here), and that position in its integer
  /// coordinates. `elsewhere`: the root cell's tree is on another rank.
  const TreeAccess* neighbourAcross(const FacePosition& n, int axis, int side, Index3& across,
                                    bool& elsewhere) const;

  /// What is at the same-level position across one face of n, looked for from
  /// the root of the tree there; `position`: that position in its tree.
  SolidNeighbours::Neighbour across(const FacePosition& n, int axis, int side,
                                    Index3& position) const;

  /// What lies across a face whose same-level position is `across`; for Parts,
  /// that position is an unmasked node. Another rank's part (an absent cell, or
  /// a tree elsewhere) is Remote with remote faces on, else Covered (solid:
  /// faces between ranks are inside the domain).
  FaceState stateOf(const SolidNeighbours::Neighbour& across) const;

  /// Whether the walk of the tree across a face of n stops for level of detail
  /// (SurfaceWalk's rule) at an unmasked node coarser than n on the way down
  /// to n's level, before any masked one: that node is drawn as a solid and the
  /// face is inside it. What stateOf says Whole or Parts is then covered. It
  /// depends on the view, so it is asked after the (topological) face memo,
  /// never stored in it. (The face walk asks SolidNeighbours::coarserStop.)
  bool coarserStopCovers(const FacePosition& n, int axis, int side) const;

  /// m: an unmasked node across a face (`axis`, `side` of the node we look
  /// from), at that node's level or finer. Calls masked(child) for each masked
  /// node touching the face that is not covered (an exposed piece) and
  /// absent(child) for each absent one (another rank's part), in child order.
  template <typename Masked, typename Absent>
  void exposedParts(const TreeAccess& t, const WalkNode& m, int axis, int side,
                    const Masked& masked, const Absent& absent) const
  {
    // Covered where the walk of t would stop (SurfaceWalk's rule): a leaf, a
    // node with nothing masked below, or a node level of detail draws whole
    // (never one with another rank's parts below it).
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
      const WalkNode child{first + c, m.level + 1, grid.childPosition(m.ijk, c)};
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

} // namespace canopy
