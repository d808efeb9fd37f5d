// Per node, the range of a field over the visible leaves below it: what lets
// the contour skip every part of the dual whose nodes' values all lie on one
// side of every contour value (DualCellContour::enter).
//
// One pass over the nodes when the field's values or the topology changed
// (vtkCanopyContour keeps them otherwise), trees in parallel, each tree
// bottom-up (over the forest as it is: from its last node to its first, VTK
// numbering children after their parent, then along the domain's boundary for
// the leaves there; with a maximum level or ghosts: a walk from the root),
// over the forest without a view: a refined node's range holds its
// own value too, so it covers whatever a view's level of detail draws below it
// as a coarse leaf, and the ranges are kept across camera moves. Only boundary
// vertices depend on the view (a coarse leaf's gradient): under level of
// detail, DualCellContour::enter descends nodes touching the domain's boundary
// whatever their ranges. With other ranks' leaves (ContourGhosts.h, sent as the
// view made them), the ranges are over the traversal's own forest, ghosts
// included, and are not kept (ContourBuilder::ranges). A hidden node (masked
// or absent) has an empty range: its cells are never contoured. A leaf on the
// domain's boundary also covers its boundary vertices' extrapolated values
// (its gradient computed as the contour computes it), so a group of nodes
// along the boundary is pruned like any other.
//
// Tested by ContourPruning.SameOutputLessWorkOnASphere (tests/unit/ContourTest.cxx):
// the same output bit for bit with and without, far fewer groups descended;
// ContourPruning.RangesInReverseEqualTheWalkFromTheRoot: both passes alike.
#pragma once

#include "ContourField.h"
#include "DualTraversal.h"
#include "HyperTreeAccess.h"
#include "TreeProgress.h"

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace canopy
{

class LeafGradient;

struct ValueRange
{
  double low = std::numeric_limits<double>::infinity();
  double high = -std::numeric_limits<double>::infinity();
  bool empty() const { return low > high; }
  void add(const ValueRange& o)
  {
    low = o.low < low ? o.low : low;
    high = o.high > high ? o.high : high;
  }
};

class NodeRanges
{
public:
  /// `grid`, `dual` and `field` are borrowed (only during the construction).
  /// Stopped by `progress`, it leaves ranges that prune nothing. `reverseWhenPossible`
  /// false: always the walk from the root (the test's reference).
  NodeRanges(const HyperTreeAccess& grid, const DualTraversal& dual, const ContourField& field,
             const ProgressShare& progress, bool reverseWhenPossible = true);

  /// The range below `node` of the tree at position `tree` in grid.trees().
  const ValueRange& at(std::size_t tree, vtkIdType node) const
  {
    return Ranges[tree][static_cast<std::size_t>(node)];
  }

private:
  /// Each node's range from the last node to the first (children after their
  /// parent in VTK's numbering); false, and partial, when a node's children
  /// come before it.
  static bool rangesInReverse(const HyperTreeAccess& grid, const ContourField& field,
                              const TreeAccess& tree, std::vector<ValueRange>& ranges);
  /// Each visible node's range from the root down, post-order (VTK's numbering
  /// not relied on). `boundaryOnly`: only the nodes touching the domain's
  /// boundary, after rangesInReverse: its leaves widened, their ancestors again.
  static void walkFromRoot(const HyperTreeAccess& grid, const DualTraversal& dual,
                           const ContourField& field, const LeafGradient& gradient,
                           const TreeAccess& tree, bool boundaryOnly,
                           std::vector<ValueRange>& ranges);
  static void widenAtBoundary(const HyperTreeAccess& grid, const DualTraversal& dual,
                              const LeafGradient& gradient, const TreeAccess& tree, vtkIdType node,
                              int level, const std::array<std::int64_t, 3>& ijk, ValueRange& range);

  std::vector<std::vector<ValueRange>> Ranges;
};

} // namespace canopy
