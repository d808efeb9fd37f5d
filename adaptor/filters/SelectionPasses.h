// The walks that carry out a selection (SelectionSpec.h) on a grid, chosen by
// what it asks for and by the output it feeds: a list of the selected nodes
// (CellSelection.h: what the cells output is made of, and what the mask of a
// location or id selection marks), or the mask pass itself (SelectionMask.h),
// which tests a value range, a box or a frustum in its own walk and keeps its
// trees in the memo (SelectionMaskMemo.h) for the next execution.
#pragma once

#include "CellSelection.h"
#include "SelectionMask.h"
#include "SelectionMaskMemo.h"
#include "SelectionSpec.h"
#include "TreeProgress.h"

#include <vector>

namespace canopy
{

/// A box or frustum selection's region (empty for the other modes).
SelectionRegion regionOf(const CellSelection& selection, const SelectionSpec& spec);

/// The nodes the selection picks, before any inversion. `forMask`: the list
/// feeds the mask pass, which tests a value range, a box or a frustum itself
/// (nothing is listed for those). `report`: what was left out, and why.
std::vector<SelectedNode> selectNodes(const CellSelection& selection, const SelectionSpec& spec,
                                      const SelectionRegion& region, bool forMask,
                                      SelectionReport& report);

/// The mask that shows the selection on the same grid, inverted as the spec
/// says: the leaves tested by value or region in the mask's own pass, else the
/// nodes `listed` (selectNodes) marked. `memo`: begun for this grid and the
/// spec's fingerprint (SelectionMaskMemo::begin). `visited`: increased by the
/// nodes a region pass examined.
SelectionMaskResult selectionMaskOf(const HyperTreeAccess& grid, const SelectionSpec& spec,
                                    const SelectionRegion& region,
                                    const std::vector<SelectedNode>& listed, bool allowMasked,
                                    SelectionMaskMemo& memo, const ProgressShare& progress,
                                    std::size_t& visited);

} // namespace canopy
