// Which nodes of a hypertree grid a selection picks, independent of VTK's
// pipeline: by location, by global id, by value range, by box or by frustum.
//
// Location rule (documented in docs/filters.md): cells are half-open
// [lo, hi) along each axis, except that the last cell of the grid along an axis
// also owns the grid's upper boundary. So a point on a face, edge or corner
// shared by several cells belongs to the cell on its upper side; a point on the
// domain's upper boundary belongs to the last cell; a point outside the domain
// (or in a root cell without a tree) selects nothing. In 2D the coordinate
// along the flat axis is ignored. Location and id lookups cost O(depth) per
// point and one traversal for all ids.
//
// Box and frustum rule (docs/filters.md): the visible leaves whose closed box
// shares a part of positive measure in the grid's own dimension with the closed
// region: volume in 3D, area in 2D, length in 1D. Touching along a face, edge or
// corner is not overlapping. A box ignores the flat axes of 2D and 1D grids (like
// locations); a frustum is cut by a 2D grid's plane or a 1D grid's line. Only
// subtrees that overlap are descended.
#pragma once

#include "Frustum.h"
#include "HalfSpace.h"
#include "HyperTreeAccess.h"
#include "TreeProgress.h"

#include <vtkType.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

class vtkDataArray;

namespace canopy
{

/// A box or frustum as the selections test cells against it (the rule above).
struct SelectionRegion
{
  /// Whether the closed box [lo, hi] shares a part of positive measure with the
  /// region (what selects a leaf).
  std::function<bool(const Vec3&, const Vec3&)> overlaps;
  /// Whether the closed box [lo, hi], of positive measure, lies in the closed
  /// region: every leaf below it overlaps. May answer false when unsure (a
  /// frustum never says yes).
  std::function<bool(const Vec3&, const Vec3&)> contains;
  /// The region meets no cell of the grid (a frustum that misses it): nothing
  /// to walk.
  bool empty = false;
};

/// Whether a node can never be selected: absent (another rank's part) always,
/// masked unless masked cells may be selected. The one rule every selection
/// (node lists and masks) applies.
inline bool unselectable(const HyperTreeAccess& grid, const TreeAccess& tree, vtkIdType node,
                         bool allowMasked)
{
  if (!grid.hasMask())
  {
    return false;
  }
  const vtkIdType global = tree.globalIndex(node);
  return grid.isAbsent(global) || (!allowMasked && grid.isMasked(global));
}

/// A selected node.
struct SelectedNode
{
  const TreeAccess* tree;
  vtkIdType node;   ///< local index in the tree
  vtkIdType global; ///< global cell index
  int level;
  std::array<std::int64_t, 3> ijk; ///< integer position at its level
};

struct SelectionReport
{
  std::size_t outside = 0;    ///< points outside the domain or in absent trees
  std::size_t masked = 0;     ///< points or ids that hit masked cells (not selected)
  std::size_t outOfRange = 0; ///< ids that are not global indices of the grid
  std::size_t duplicates = 0; ///< points or ids selecting an already selected cell
  std::size_t visited = 0;    ///< nodes a box or frustum selection examined (its cost)
};

class CellSelection
{
public:
  CellSelection(const HyperTreeAccess& grid, bool allowMasked);

  /// Where the next selections' loops over trees report and learn that the
  /// execution was aborted; stopped, they leave out the trees not begun, and
  /// their results are to be discarded. (Locations are looked up point by
  /// point, without a loop over trees.)
  void setProgress(const ProgressShare& progress) { Progress = progress; }

  /// The unmasked leaf containing each point (see the rule above).
  std::vector<SelectedNode> byLocation(const std::vector<Vec3>& points,
                                       SelectionReport& report) const;
  /// The nodes with these global indices (coarse ids select coarse cells).
  std::vector<SelectedNode> byId(const std::vector<vtkIdType>& ids, SelectionReport& report) const;
  /// Visible leaves whose value (component, or magnitude when component < 0) is
  /// within [low, high]; NaN is never selected.
  std::vector<SelectedNode> byValue(vtkDataArray* values, int component, double low,
                                    double high) const;
  /// The test byValue applies to a cell (its global index): the value (component,
  /// or magnitude when component < 0) within [low, high], never NaN. Reads
  /// contiguous double and float arrays directly. `values` must outlive it.
  static std::function<bool(vtkIdType)> valueInRange(vtkDataArray* values, int component,
                                                     double low, double high);

  /// The box [xmin, xmax, ymin, ymax, zmin, zmax] as a region, along the grid's
  /// active axes (flat axes ignored). Precondition: min <= max on every axis, no NaN.
  SelectionRegion boxRegion(const std::array<double, 6>& box) const;
  /// The frustum as a region: in 3D, its volume; in 2D or 1D, its section by the
  /// grid's plane or line. Precondition: frustum.problem() is empty.
  SelectionRegion frustumRegion(const Frustum& frustum) const;
  /// Visible leaves overlapping the region, descending only into nodes that do.
  std::vector<SelectedNode> byRegion(const SelectionRegion& region, SelectionReport& report) const;

  /// The visible leaves (selectable: unmasked, or masked with allowMasked; never
  /// absent) that are neither one of `selected` nor below one: what an inverted
  /// selection selects. In tree order.
  std::vector<SelectedNode> complement(const std::vector<SelectedNode>& selected) const;

  /// Lower and upper corners of a selected node.
  void bounds(const SelectedNode& n, Vec3& lo, Vec3& hi) const;

private:
  bool hidden(const TreeAccess& tree, vtkIdType node) const;
  /// The visible leaves, per tree in parallel, in tree order: subtrees whose root
  /// skip(global) names are left out, and leaves for which keep(global) fails.
  template <typename Skip, typename Keep>
  std::vector<SelectedNode> visibleLeaves(const Skip& skip, const Keep& keep) const;
  const HyperTreeAccess& Grid;
  bool AllowMasked;
  ProgressShare Progress;
};

} // namespace canopy
