// What lies around a node of a 3D tree at its own level, across each of its six
// faces and twelve edges, carried down a depth-first walk (the 3D counterpart
// of EdgeVertices.h's PlaneNeighbours): a node's neighbour in a direction is its
// sibling, or a child of its parent's neighbour in the direction that leaves
// the parent, so finding it costs a step, not a descent from a common ancestor
// or a root. The face walk (SolidSurfaceWalk.h) asks them for what lies across
// its faces (FaceSide.h), whether a subtree can expose anything, and where the
// pieces meeting its faces' edges come from (FaceEdgeVertices.h).
//
// Neighbours are found when first asked for, and kept until a node at their
// level is entered: a walk asks about few of the nodes it enters.
#pragma once

#include "HyperTreeAccess.h"
#include "TreeTraversal.h"

#include <array>
#include <cstdint>
#include <vector>

namespace canopy
{

using Index3 = std::array<std::int64_t, 3>;

class SolidNeighbours
{
public:
  /// A same-level position around a node, as the trees have it.
  struct Neighbour
  {
    enum class Kind : unsigned char
    {
      Node,        ///< an unmasked node at that level: `tree`, `node`
      Border,      ///< outside the grid, or in a root cell without a tree anywhere
      Elsewhere,   ///< in a root cell whose tree is on another rank
      Hidden,      ///< in a masked node at that level or coarser (a hole)
      Absent,      ///< in an absent node: another rank's part of a split tree
      CoarserLeaf, ///< in an unmasked leaf coarser than that level
    };
    Kind kind;
    const TreeAccess* tree; ///< where it was found (nullptr: Border, Elsewhere)
    vtkIdType node;         ///< the node, or the masked node or leaf it lies in
  };
  /// Per axis -1, 0 or +1; not all 0.
  using Direction = std::array<int, 3>;

  /// Node `node` of `tree`: hidden (or absent) when masked.
  static Neighbour nodeAt(const HyperTreeAccess& grid, const TreeAccess& tree, vtkIdType node)
  {
    if (grid.hasMask())
    {
      const vtkIdType global = tree.globalIndex(node);
      if (grid.isMasked(global))
      {
        return {grid.isAbsent(global) ? Neighbour::Kind::Absent : Neighbour::Kind::Hidden, &tree,
                node};
      }
    }
    return {Neighbour::Kind::Node, &tree, node};
  }
  /// The root of the tree at root cell (i, j, k).
  static Neighbour rootAt(const HyperTreeAccess& grid, long i, long j, long k);
  /// Child `child` of `parent` where `parent` is a refined node; a leaf's or a
  /// hidden place's kind is carried down.
  static Neighbour childOf(const HyperTreeAccess& grid, const Neighbour& parent, int child)
  {
    if (parent.kind != Neighbour::Kind::Node)
    {
      return parent;
    }
    if (parent.tree->isLeaf(parent.node))
    {
      return {Neighbour::Kind::CoarserLeaf, parent.tree, parent.node};
    }
    return nodeAt(grid, *parent.tree, parent.tree->firstChild(parent.node) + child);
  }

  SolidNeighbours(const HyperTreeAccess& grid, const TreeAccess& tree);

  /// Call on entering node n of the tree, a child of the node entered last one
  /// level up (or the root).
  void enter(const WalkNode& n);

  /// The neighbour in direction d of the node entered last at `level`.
  const Neighbour& at(int level, const Direction& d)
  {
    Level& here = Levels[static_cast<std::size_t>(level)];
    const int k = index(d);
    if (here.known & (1u << k))
    {
      return here.around[static_cast<std::size_t>(k)];
    }
    return find(here, level, d, k);
  }

  /// The same neighbour's position in its tree, and as a node a walk enters.
  Index3 positionAt(int level, const Direction& d) const;
  WalkNode walkNodeAt(int level, const Direction& d)
  {
    return {at(level, d).node, level, positionAt(level, d)};
  }

  /// Whether, on the way down to the node entered last at `level`'s neighbour
  /// across its face (`axis`, `side`), a node stops(tree, node) says is drawn
  /// as a solid is met: an unmasked, refined node coarser than `level` that is
  /// not an ancestor of the node, before any masked node or leaf. Kept per face
  /// as at() keeps neighbours.
  template <typename Stops>
  bool coarserStop(int level, int axis, int side, Stops&& stops);

  static Direction faceDirection(int axis, int side)
  {
    Direction d{{0, 0, 0}};
    d[static_cast<std::size_t>(axis)] = side ? 1 : -1;
    return d;
  }

private:
  /// What is kept of a node on the walk's path. Constructed without zeroing
  /// its neighbours (the walk makes one set per tree): enter() sets what is read.
  struct Level
  {
    Level() {} // not `= default`: no value-initialization of `around`
    vtkIdType node;
    Index3 ijk;
    std::array<int, 3> digit; ///< its child digit per axis
    std::uint32_t known;      ///< bit index(d): around[index(d)] found
    std::uint32_t coverKnown; ///< bit 2 axis + side: covered's bit set
    std::uint32_t covered;
    std::array<Neighbour, 27> around;
  };

  static int index(const Direction& d) { return (d[0] + 1) + 3 * (d[1] + 1) + 9 * (d[2] + 1); }
  /// at()'s neighbour found and kept (k: index(d)).
  const Neighbour& find(Level& here, int level, const Direction& d, int k);

  const HyperTreeAccess& Grid;
  const TreeAccess& Tree;
  std::array<vtkIdType, 3> Weight{{0, 0, 0}}; ///< a child digit's weight in the child index
  std::vector<Level> Levels;
};

template <typename Stops>
bool SolidNeighbours::coarserStop(int level, int axis, int side, Stops&& stops)
{
  if (level == 0)
  {
    return false; // nothing is coarser than a root
  }
  Level& here = Levels[static_cast<std::size_t>(level)];
  const std::uint32_t bit = 1u << (2 * axis + side);
  if (here.coverKnown & bit)
  {
    return (here.covered & bit) != 0;
  }
  bool covered = false;
  const int digit = here.digit[static_cast<std::size_t>(axis)] + (side ? 1 : -1);
  // A sibling's way down starts at their parent, which the walk did not stop at.
  if (digit < 0 || digit >= Grid.branchFactor())
  {
    // The parent's way down, then the parent's neighbour (the way's last node).
    covered = coarserStop(level - 1, axis, side, stops);
    if (!covered)
    {
      const Direction d = faceDirection(axis, side);
      const Neighbour& p = at(level - 1, d);
      covered = p.kind == Neighbour::Kind::Node && !p.tree->isLeaf(p.node) &&
                stops(*p.tree, WalkNode{p.node, level - 1, positionAt(level - 1, d)});
    }
  }
  here.coverKnown |= bit;
  here.covered |= covered ? bit : 0u;
  return covered;
}

} // namespace canopy
