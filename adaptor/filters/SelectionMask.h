// The mask that shows a selection on the same grid (vtkCanopyExtractSelection
// with PreserveTopology): no cell or field is copied, only a new mask is made.
//
// Visible are the selected nodes with their subtrees, and their ancestors (to
// reach them); inverted, the selectable leaves outside every selected subtree,
// and their ancestors. What stays hidden in a selected subtree: absent cells
// always, masked ones unless they may be selected. Nodes with another rank's
// parts below them (split trees) stay visible, their own unselected children
// masked one by one: a masked node then never hides another rank's cells, which
// that rank may have selected (the 3D surface takes a masked node for a hole as
// large as the node).
//
// Cost: per tree the memo does not keep (SelectionMaskMemo.h: only the trees
// whose topology, marks or selection changed), one byte per node, a mark per
// selected node (and subtree) or one walk of the visible nodes (inverted), one
// reverse pass over the nodes (children follow their parents in local order);
// then the mask: the last one patched (N / 4 bytes copied), or packed anew from
// every tree's bytes. Trees run in parallel.
#pragma once

#include "CellSelection.h"
#include "HyperTreeAccess.h"
#include "SelectionMaskMemo.h"
#include "TreeProgress.h"

#include <vtkSmartPointer.h>

#include <array>
#include <functional>
#include <vector>

class vtkBitArray;

namespace canopy
{

struct SelectionMaskResult
{
  vtkSmartPointer<vtkBitArray> mask;
  /// VTK's pure mask of the masked grid (PureMask.h): masked, or a refined
  /// visible node with a marked child.
  vtkSmartPointer<vtkBitArray> pure;
  /// Bounds of the visible leaves that are selected (min > max when none).
  std::array<double, 6> bounds;
};

/// `selected`: what the selection picked (any order; nodes of trees the memo
/// keeps are not read). `allowMasked`: masked cells count as selectable (as
/// CellSelection's). `memo`: begun for this grid and selection
/// (SelectionMaskMemo::begin); the trees it keeps are not marked again, and it
/// keeps this mask for the next execution. `progress`: where the loop over
/// trees reports and learns that the execution was aborted; stopped, the
/// result has no mask and the memo is cleared.
SelectionMaskResult selectionMask(const HyperTreeAccess& grid,
                                  const std::vector<SelectedNode>& selected, bool invert,
                                  bool allowMasked, SelectionMaskMemo& memo,
                                  const ProgressShare& progress = {});

/// The same for a selection of leaves by a test of their global index (a value
/// range): the leaves are tested in the mask's own pass, no node list is made.
SelectionMaskResult selectionMaskOfLeaves(const HyperTreeAccess& grid,
                                          const std::function<bool(vtkIdType)>& picked, bool invert,
                                          bool allowMasked, SelectionMaskMemo& memo,
                                          const ProgressShare& progress = {});

/// The same for a box or frustum (CellSelection::boxRegion, frustumRegion):
/// the visible leaves overlapping it, tested in the mask's own pass. A tree the
/// region misses or contains, with no hidden cell, is marked whole without a
/// walk; other trees descend only into nodes that overlap the region (inverted:
/// into every node). `visited`: increased by the nodes examined, roots included.
SelectionMaskResult selectionMaskOfRegion(const HyperTreeAccess& grid,
                                          const SelectionRegion& region, bool invert,
                                          bool allowMasked, SelectionMaskMemo& memo,
                                          std::size_t& visited, const ProgressShare& progress = {});

} // namespace canopy
