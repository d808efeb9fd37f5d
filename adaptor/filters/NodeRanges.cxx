#include "NodeRanges.h"

#include "LeafGradient.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace canopy
{

namespace
{

struct Pending
{
  vtkIdType node;
  int level;
  std::array<std::int64_t, 3> ijk;
  bool childrenDone;
};

} // namespace

bool NodeRanges::rangesInReverse(const HyperTreeAccess& grid, const ContourField& field,
                                 const TreeAccess& tree, std::vector<ValueRange>& ranges)
{
  const int children = grid.childrenPerNode();
  for (vtkIdType v = tree.numberOfVertices; v-- > 0;)
  {
    const vtkIdType global = tree.globalIndex(v);
    if (grid.isMasked(global) || grid.isAbsent(global))
    {
      continue; // hidden: empty (its descendants' ranges are never read)
    }
    ValueRange& range = ranges[static_cast<std::size_t>(v)];
    const double own = field(global);
    if (tree.isLeaf(v))
    {
      range.low = range.high = own;
      continue;
    }
    const vtkIdType first = tree.firstChild(v);
    if (first <= v)
    {
      return false; // children before their parent: not VTK's usual numbering
    }
    for (int c = 0; c < children; ++c)
    {
      range.add(ranges[static_cast<std::size_t>(first + c)]);
    }
    // Its own value last, as the walk adds it: a NaN coarse value (an average
    // over a NaN leaf) then leaves the children's range as it is.
    range.add({own, own});
  }
  return true;
}

void NodeRanges::walkFromRoot(const HyperTreeAccess& grid, const DualTraversal& dual,
                              const ContourField& field, const LeafGradient& gradient,
                              const TreeAccess& tree, bool boundaryOnly,
                              std::vector<ValueRange>& ranges)
{
  // Post-order without recursion: a node's range once its children's are known.
  std::vector<Pending> stack{{0, 0, {{0, 0, 0}}, false}};
  while (!stack.empty())
  {
    const Pending p = stack.back();
    stack.pop_back();
    const vtkIdType global = tree.globalIndex(p.node);
    if (grid.isMasked(global) || grid.isAbsent(global) ||
        (boundaryOnly && !dual.touchesDomainBoundary(tree, p.level, p.ijk)))
    {
      continue; // hidden: empty; or inside, as the reverse pass left it
    }
    ValueRange& range = ranges[static_cast<std::size_t>(p.node)];
    if (dual.isLeaf(tree, p.node, p.level, p.ijk))
    {
      range.low = range.high = field(global);
      widenAtBoundary(grid, dual, gradient, tree, p.node, p.level, p.ijk, range);
      continue;
    }
    const vtkIdType first = tree.firstChild(p.node);
    if (p.childrenDone)
    {
      range = ValueRange{};
      for (int c = 0; c < grid.childrenPerNode(); ++c)
      {
        range.add(ranges[static_cast<std::size_t>(first + c)]);
      }
      // Its own value too, last (a NaN one then changes nothing): with level
      // of detail a node may be drawn as a leaf, and a simulation's coarse
      // value need not lie within its leaves' range.
      const double own = field(global);
      range.add({own, own});
      continue;
    }
    stack.push_back({p.node, p.level, p.ijk, true});
    for (int c = 0; c < grid.childrenPerNode(); ++c)
    {
      stack.push_back({first + c, p.level + 1, grid.childPosition(p.ijk, c), false});
    }
  }
}

NodeRanges::NodeRanges(const HyperTreeAccess& grid, const DualTraversal& dual,
                       const ContourField& field, const ProgressShare& progress,
                       bool reverseWhenPossible)
    : Ranges(grid.trees().size())
{
  const auto& trees = grid.trees();
  const LeafGradient gradient(grid, dual, field);
  // Without a maximum level, a view's level of detail or other ranks' leaves,
  // a node is a leaf exactly when its tree says so: each tree's nodes from the
  // last to the first (children after parents), then its leaves on the
  // domain's boundary widened. Otherwise, a walk from the root.
  const bool reverse =
      reverseWhenPossible && dual.maximumLevel() < 0 && !dual.levelOfDetail() && !dual.ghosts();
  forEachTree(progress, static_cast<vtkIdType>(trees.size()),
              [&](vtkIdType t)
              {
                const TreeAccess& tree = trees[static_cast<std::size_t>(t)];
                auto& ranges = Ranges[static_cast<std::size_t>(t)];
                ranges.assign(static_cast<std::size_t>(tree.numberOfVertices), ValueRange{});
                if (reverse)
                {
                  // The forest as it is: no node is a leaf but the tree's own,
                  // so no level or position is needed but along the boundary.
                  if (rangesInReverse(grid, field, tree, ranges))
                  {
                    // Then the leaves on the domain's boundary, and their ancestors.
                    walkFromRoot(grid, dual, field, gradient, tree, true, ranges);
                    return;
                  }
                  ranges.assign(static_cast<std::size_t>(tree.numberOfVertices), ValueRange{});
                }
                walkFromRoot(grid, dual, field, gradient, tree, false, ranges);
              });
  if (progress.stopped())
  {
    // Partial ranges could prune what they have not seen: prune nothing.
    for (auto& tree : Ranges)
    {
      for (ValueRange& range : tree)
      {
        range.low = -std::numeric_limits<double>::infinity();
        range.high = std::numeric_limits<double>::infinity();
      }
    }
  }
}

void NodeRanges::widenAtBoundary(const HyperTreeAccess& grid, const DualTraversal& dual,
                                 const LeafGradient& gradient, const TreeAccess& tree,
                                 vtkIdType node, int level, const std::array<std::int64_t, 3>& ijk,
                                 ValueRange& range)
{
  // The sides of the domain the leaf touches, per active axis.
  const std::int64_t cells = grid.cellsPerRootAt(level);
  bool touches = false;
  std::array<std::array<bool, 2>, 3> sides{};
  for (int i = 0; i < dual.dimension(); ++i)
  {
    const std::size_t a = static_cast<std::size_t>(dual.axis(i));
    const long roots = static_cast<long>(grid.rootCells()[a]);
    sides[a][0] = tree.rootIJK[a] == 0 && ijk[a] == 0;
    sides[a][1] = static_cast<long>(tree.rootIJK[a]) == roots - 1 && ijk[a] == cells - 1;
    touches = touches || sides[a][0] || sides[a][1];
  }
  if (!touches)
  {
    return;
  }
  // Its boundary vertices: the centre moved onto any of those sides, the
  // value extrapolated as DualCellContour does; their extremes are
  // separable per axis.
  DualNode leaf{};
  leaf.tree = &tree;
  leaf.node = node;
  leaf.level = level;
  leaf.ijk = ijk;
  leaf.kind = DualNode::Leaf;
  const std::array<double, 3> g = gradient.at(leaf);
  std::array<double, 3> lo;
  std::array<double, 3> hi;
  grid.nodeBounds(tree, level, ijk, lo, hi);
  double low = range.low;
  double high = range.high;
  for (std::size_t a = 0; a < 3; ++a)
  {
    const double centre = 0.5 * (lo[a] + hi[a]);
    double down = 0;
    double up = 0;
    for (int side = 0; side < 2; ++side)
    {
      if (sides[a][static_cast<std::size_t>(side)])
      {
        const double change = g[a] * ((side ? hi[a] : lo[a]) - centre);
        down = std::min(down, change);
        up = std::max(up, change);
      }
    }
    low += down;
    high += up;
  }
  // Outwards by a little more than the rounding of the contour's own sum.
  range.low = low - 1e-12 * std::abs(low);
  range.high = high + 1e-12 * std::abs(high);
}

} // namespace canopy
