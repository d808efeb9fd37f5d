// The dual of a tree grid, cell by cell: the recursive octree dual traversal of
// Schaefer and Warren ("Dual Marching Cubes", 2004), for 2D and 3D grids, branch
// factor 2 or 3, across root trees, extended to the domain's boundary.
//
// A dual cell joins the 2^d leaves around one vertex of the grid (every corner
// of any leaf): slot s of a cell holds the leaf on the upper side of the vertex
// along active axis i when bit i of s is set. Where levels differ a leaf fills
// several slots (the cell is degenerate). Schaefer and Warren's cellProc,
// faceProc, edgeProc and vertProc are one procedure here: proc(nodes, axes)
// takes the 2^|axes| nodes that meet across a shared element (nothing shared:
// one node, cellProc; one axis: two nodes across a face, faceProc; ...), and,
// while one of them is refined, replaces each by its children touching that
// element and calls itself on every group of those children that meets across
// a smaller element (with the same axes and every larger set). With branch
// factor f a node has f children per axis, so there are f - 1 inner boundaries
// per axis where binary trees have one; the recursion is otherwise the same.
// When every node of a group with all d axes is a leaf, the group is a dual cell.
//
// Trees: the root grid is one more level of the same recursion (neighbouring
// roots meet across faces, edges and vertices). Boundary: the root grid is
// ringed by Outside nodes, so the vertices on the domain's boundary get dual
// cells too; an Outside slot is later replaced by the boundary dual vertex of
// the leaf it mirrors (DualCellContour.h). Masked nodes and root cells without a
// tree are Hidden: never descended, and a dual cell with a Hidden slot is not
// contoured. Other ranks' parts are seen through their ghosts (ContourGhosts.h)
// when the traversal has them, else Hidden too.
//
// The work is split into tasks, one per cell of the ringed root grid: task P
// runs every top-level group whose lowest cell is P. Tasks are independent (they
// read the grid only) and deterministic.
//
// Tested by tests/unit/ContourTest.cxx: Contour2D.Watertight* and
// Contour3D.Watertight* (every contour edge inside the domain shared twice, on
// random forests with level jumps of one to five, binary and ternary; a group
// kind skipped fails them), *.LinearField* (no gap, no overlap: exact length
// and area).
#pragma once

#include "ContourGhosts.h"
#include "HyperTreeAccess.h"
#include "ViewVolume.h"

#include <array>
#include <cstdint>

namespace canopy
{

/// A node as the dual traversal sees it. No member initializers: the
/// traversal fills arrays of them at every step (value-initialize, DualNode{},
/// for zeros).
struct DualNode
{
  enum Kind : unsigned char
  {
    Inner,  ///< refined, visible: descended
    Leaf,   ///< a visible leaf: a dual vertex at its centre
    Hidden, ///< masked, absent or without a tree: cells touching it are dropped
    Outside ///< beyond the domain's boundary
  };
  const TreeAccess* tree;
  vtkIdType node; ///< local index in `tree` (a ghost: its index in ContourGhosts)
  int level;
  std::array<std::int64_t, 3> ijk; ///< integer position at `level`
  Kind kind;
  /// Outside only: bit 2i, below the domain along active axis i; bit 2i + 1, above.
  unsigned char outside;
  /// Another rank's: a ghost node (Leaf or Inner; `node` is its index in
  /// ContourGhosts, `tree` the local tree or a stand-in), or (Hidden) a part
  /// of another rank no ghost covers.
  unsigned char remote;
};

/// 2^d nodes, slot s's bit i the side along active axis i (only the slots of
/// the axes a group spans are used). Pointers into the traversal's own arrays,
/// valid during the visitor's call only: a group is passed down without
/// copying its nodes.
using DualGroup = std::array<const DualNode*, 8>;

class DualTraversal
{
public:
  /// `grid` is borrowed and must outlive the traversal. 2D and 3D grids only.
  /// `maximumLevel` >= 0: nodes at that level are leaves (holding their own,
  /// coarse, value): the dual of the coarser forest, crack-free by the same
  /// rule; -1: every level.
  /// `view` (borrowed, or nullptr): with `levelOfDetail`, a node whose box
  /// spans at most `pixelThreshold` pixels is a leaf too (one answer per node,
  /// whichever group asks: the coarser forest stays crack-free).
  explicit DualTraversal(const HyperTreeAccess& grid, int maximumLevel = -1,
                         const ViewVolume* view = nullptr, bool levelOfDetail = false,
                         double pixelThreshold = 1.0);

  /// Other ranks' leaves to see where this grid has their parts (borrowed, or
  /// nullptr: those parts are Hidden). Set before any task runs.
  void setGhosts(const ContourGhosts* ghosts) { Ghosts = ghosts; }
  const ContourGhosts* ghosts() const { return Ghosts; }

  /// A leaf's id: its global index, or, for a ghost, the number of the grid's
  /// cells plus its ghost index (what ContourField reads).
  vtkIdType leafId(const DualNode& n) const
  {
    return n.remote ? Grid.numberOfCells() + n.node : n.tree->globalIndex(n.node);
  }

  /// The root node of root cell (i, j, k) (3D indices, inside the root grid),
  /// classified as the traversal classifies it.
  DualNode rootNode(const std::array<long, 3>& rootIJK) const
  {
    std::array<long, 3> p{{0, 0, 0}};
    for (int i = 0; i < D; ++i)
    {
      p[static_cast<std::size_t>(i)] =
          rootIJK[static_cast<std::size_t>(Axes[static_cast<std::size_t>(i)])];
    }
    return root(p);
  }
  /// Fills `out` with child c (VTK's child order) of the Inner node `n`.
  void childNode(DualNode& out, const DualNode& n, int c) const
  {
    const auto& digit = Grid.childDigits(c);
    std::array<std::int64_t, 3> ijk;
    for (std::size_t a = 0; a < 3; ++a)
    {
      ijk[a] = digit[a] < 0 ? n.ijk[a] : n.ijk[a] * F + digit[a];
    }
    if (n.remote)
    {
      classifyGhost(out, *n.tree, n.level + 1, ijk);
      return;
    }
    classify(out, *n.tree, n.tree->firstChild(n.node) + c, n.level + 1, ijk);
  }

  /// Whether a node is a leaf of the forest the traversal sees.
  bool isLeaf(const TreeAccess& tree, vtkIdType node, int level,
              const std::array<std::int64_t, 3>& ijk) const
  {
    // A node with other ranks' parts below is never a leaf before its own
    // leaves: no rank could draw it alone (ContourGhosts.h).
    return tree.isLeaf(node) || (!tree.hasAbsentDescendant(node) && coarseLeaf(tree, level, ijk));
  }
  /// Whether a node is a leaf by the maximum level or the level of detail.
  bool coarseLeaf(const TreeAccess& tree, int level, const std::array<std::int64_t, 3>& ijk) const
  {
    return (MaximumLevel >= 0 && level >= MaximumLevel) ||
           (View && LevelOfDetail && footprint(tree, level, ijk) <= PixelThreshold);
  }
  int maximumLevel() const { return MaximumLevel; }
  /// Whether the view makes nodes leaves too (a view with level of detail).
  bool levelOfDetail() const { return View && LevelOfDetail; }
  /// Whether a node's box touches a side of the domain along an active axis
  /// (it has boundary vertices).
  bool touchesDomainBoundary(const TreeAccess& tree, int level,
                             const std::array<std::int64_t, 3>& ijk) const
  {
    const std::int64_t last = Grid.cellsPerRootAt(level) - 1;
    for (int i = 0; i < D; ++i)
    {
      const std::size_t a = static_cast<std::size_t>(Axes[static_cast<std::size_t>(i)]);
      const auto lastRoot = static_cast<long>(Grid.rootCells()[a]) - 1;
      if ((tree.rootIJK[a] == 0 && ijk[a] == 0) ||
          (static_cast<long>(tree.rootIJK[a]) == lastRoot && ijk[a] == last))
      {
        return true;
      }
    }
    return false;
  }
  const ViewVolume* view() const { return View; }
  /// A node's box's extent on screen, in pixels.
  double footprint(const TreeAccess& tree, int level, const std::array<std::int64_t, 3>& ijk) const
  {
    std::array<double, 3> lo;
    std::array<double, 3> hi;
    Grid.nodeBounds(tree, level, ijk, lo, hi);
    std::array<Vec3, 8> corners;
    for (std::size_t c = 0; c < 8; ++c)
    {
      corners[c] = {{c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]}};
    }
    return View->footprintInPixels(corners);
  }

  int dimension() const { return D; }
  /// Tasks: cells of the root grid ringed by one layer of Outside cells (its
  /// lowest ring layer only: the groups of a task extend upwards).
  vtkIdType numberOfTasks() const { return Tasks; }

  /// Runs task `task`. The visitor's `bool enter(const DualGroup&, unsigned
  /// axes)` is called on every group with a refined node before it is
  /// descended (false: not descended; pruning); `void cell(const DualGroup&)`
  /// on every dual cell (all d axes, all slots terminal).
  template <typename Visitor>
  void runTask(vtkIdType task, Visitor& visitor) const;

  /// The 3D axis of active axis i.
  int axis(int i) const { return Axes[static_cast<std::size_t>(i)]; }

private:
  /// Fills `n` in place (a node returned by value and copied is written and
  /// read back in pieces of other sizes: the stores stall the loads).
  void classify(DualNode& n, const TreeAccess& tree, vtkIdType node, int level,
                const std::array<std::int64_t, 3>& ijk) const
  {
    n.tree = &tree;
    n.node = node;
    n.level = level;
    n.ijk = ijk;
    n.outside = 0;
    n.remote = 0;
    const vtkIdType global = tree.globalIndex(node);
    if (Grid.isAbsent(global))
    {
      classifyGhost(n, tree, level, ijk);
      return;
    }
    n.kind = Grid.isMasked(global)
                 ? DualNode::Hidden
                 : (isLeaf(tree, node, level, ijk) ? DualNode::Leaf : DualNode::Inner);
  }

  /// Fills `n` with the ghost at a node of another rank's part (Hidden when
  /// no rank sent one).
  void classifyGhost(DualNode& n, const TreeAccess& tree, int level,
                     const std::array<std::int64_t, 3>& ijk) const
  {
    n.tree = &tree;
    n.level = level;
    n.ijk = ijk;
    n.outside = 0;
    n.remote = 1;
    std::int64_t ghost = Ghosts ? Ghosts->find(tree, level, ijk) : -1;
    if (ghost < 0 && Ghosts)
    {
      // This grid may split another rank's part finer than that rank's
      // leaves: the node is then inside a ghost leaf of a coarser level,
      // which fills its slot as a coarse leaf fills several.
      std::array<std::int64_t, 3> up = ijk;
      for (int l = level - 1; l >= 0 && ghost < 0; --l)
      {
        for (int i = 0; i < D; ++i)
        {
          up[static_cast<std::size_t>(Axes[static_cast<std::size_t>(i)])] /= F;
        }
        ghost = Ghosts->find(tree, l, up);
        if (ghost >= 0)
        {
          if (!Ghosts->isLeaf(ghost) && (Ghosts->mixed(ghost) || !coarseLeaf(tree, l, up)))
          {
            ghost = -1; // an inner node that did not send this part: unknown
            break;
          }
          n.level = l;
          n.ijk = up;
        }
      }
    }
    n.node = static_cast<vtkIdType>(ghost);
    if (ghost < 0)
    {
      n.kind = DualNode::Hidden;
      return;
    }
    n.kind = Ghosts->isLeaf(ghost) || (!Ghosts->mixed(ghost) && coarseLeaf(tree, n.level, n.ijk))
                 ? DualNode::Leaf
                 : DualNode::Inner;
  }

  /// Fills `out` with the child of the refined node `n` with digit digits[i]
  /// along active axis i.
  void child(DualNode& out, const DualNode& n, const std::array<int, 3>& digits) const
  {
    int c = 0;
    for (int i = D; i-- > 0;)
    {
      c = c * F + digits[static_cast<std::size_t>(i)];
    }
    childNode(out, n, c);
  }

  /// The root node at ringed root position p (per active axis, -1 .. n).
  DualNode root(const std::array<long, 3>& p) const;

  template <typename Visitor>
  void proc(const DualGroup& n, unsigned axes, Visitor& visitor) const;

  const HyperTreeAccess& Grid;
  int D = 0;
  int F = 2;
  int MaximumLevel = -1;
  const ViewVolume* View = nullptr;
  const ContourGhosts* Ghosts = nullptr;
  bool LevelOfDetail = false;
  double PixelThreshold = 1.0;
  std::array<int, 3> Axes{{0, 1, 2}};
  std::array<long, 3> Roots{{1, 1, 1}}; ///< root cells per active axis
  vtkIdType Tasks = 0;
};

template <typename Visitor>
void DualTraversal::runTask(vtkIdType task, Visitor& visitor) const
{
  // Task -> its cell P in the ringed grid (-1 .. n - 1 per axis), first axis fastest.
  std::array<long, 3> p{{0, 0, 0}};
  vtkIdType rest = task;
  for (int i = 0; i < D; ++i)
  {
    const long ringed = Roots[static_cast<std::size_t>(i)] + 1;
    p[static_cast<std::size_t>(i)] = static_cast<long>(rest % ringed) - 1;
    rest /= ringed;
  }
  const unsigned full = (1u << D) - 1;
  for (unsigned span = 0; span <= full; ++span)
  {
    // A group extends from P upwards along the axes it spans; along the others
    // P must be inside the root grid (else the whole group is outside).
    bool inside = true;
    for (int i = 0; i < D; ++i)
    {
      inside = inside && ((span >> i) & 1 || p[static_cast<std::size_t>(i)] >= 0);
    }
    if (!inside)
    {
      continue;
    }
    std::array<DualNode, 8> roots;
    DualGroup group{};
    bool anyInside = false;
    for (unsigned s = 0; s <= full; ++s)
    {
      if ((s & ~span) != 0)
      {
        continue;
      }
      std::array<long, 3> q = p;
      for (int i = 0; i < D; ++i)
      {
        q[static_cast<std::size_t>(i)] += (s >> i) & 1;
      }
      roots[s] = root(q);
      group[s] = &roots[s];
      anyInside = anyInside || roots[s].kind != DualNode::Outside;
    }
    if (anyInside)
    {
      proc(group, span, visitor);
    }
  }
}

template <typename Visitor>
void DualTraversal::proc(const DualGroup& n, unsigned axes, Visitor& visitor) const
{
  const unsigned full = (1u << D) - 1;
  const unsigned free = full & ~axes;
  bool refined = false;
  for (unsigned s = 0; s <= full && !refined; ++s)
  {
    refined = (s & free) == 0 && n[s]->kind == DualNode::Inner;
  }
  if (!refined)
  {
    if (axes == full)
    {
      visitor.cell(n);
    }
    return;
  }
  if (!visitor.enter(n, axes))
  {
    return;
  }
  // The children the groups below are made of, classified once: of each
  // refined node, those touching the shared element (f^|free| of them).
  // Indexed in mixed radix: per axis the side bit (shared axes) or the digit
  // (free axes), first axis fastest.
  std::array<int, 3> stride{{0, 0, 0}};
  int size = 1;
  for (int i = 0; i < D; ++i)
  {
    stride[static_cast<std::size_t>(i)] = size;
    size *= (axes >> i) & 1 ? 2 : F;
  }
  std::array<DualNode, 27> children;
  for (int at = 0; at < size; ++at)
  {
    unsigned s = 0;
    std::array<int, 3> digits{{0, 0, 0}};
    int rest = at;
    for (int i = 0; i < D; ++i)
    {
      const int radix = (axes >> i) & 1 ? 2 : F;
      const int code = rest % radix;
      rest /= radix;
      if ((axes >> i) & 1)
      {
        s |= static_cast<unsigned>(code) << i;
        // The children touching the shared element: the last along the axis
        // on its lower side, the first on its upper side.
        digits[static_cast<std::size_t>(i)] = code ? 0 : F - 1;
      }
      else
      {
        digits[static_cast<std::size_t>(i)] = code;
      }
    }
    if (n[s]->kind == DualNode::Inner)
    {
      child(children[static_cast<std::size_t>(at)], *n[s], digits);
    }
  }
  // Every set of free axes the children's groups add, the empty set first
  // (the same element, one level down), then each larger one.
  for (unsigned added = 0; added <= free; ++added)
  {
    if ((added & ~free) != 0)
    {
      continue;
    }
    const unsigned spans = axes | added;
    // Position of the group among the children along each free axis: an
    // added axis has f - 1 inner boundaries, any other free axis f children.
    std::array<int, 3> at{{0, 0, 0}};
    for (;;)
    {
      DualGroup m{};
      bool inner = false;
      for (unsigned s = 0; s <= full; ++s)
      {
        if ((s & ~spans) != 0)
        {
          continue;
        }
        const DualNode* parent = n[s & axes];
        if (parent->kind != DualNode::Inner)
        {
          m[s] = parent;
          continue;
        }
        int index = 0;
        for (int i = 0; i < D; ++i)
        {
          const unsigned bit = 1u << i;
          const std::size_t ui = static_cast<std::size_t>(i);
          const int code =
              (axes & bit) ? ((s & bit) ? 1 : 0) : at[ui] + ((added & bit) && (s & bit) ? 1 : 0);
          index += code * stride[ui];
        }
        m[s] = &children[static_cast<std::size_t>(index)];
        inner = inner || m[s]->kind == DualNode::Inner;
      }
      // What proc would do with a group of leaves, without the call.
      if (inner)
      {
        proc(m, spans, visitor);
      }
      else if (spans == full)
      {
        visitor.cell(m);
      }
      // Next position (first free axis fastest).
      int i = 0;
      for (; i < D; ++i)
      {
        const unsigned bit = 1u << i;
        if (!(free & bit))
        {
          continue;
        }
        const int limit = (added & bit) ? F - 1 : F;
        if (++at[static_cast<std::size_t>(i)] < limit)
        {
          break;
        }
        at[static_cast<std::size_t>(i)] = 0;
      }
      if (i == D)
      {
        break;
      }
    }
  }
}

} // namespace canopy
