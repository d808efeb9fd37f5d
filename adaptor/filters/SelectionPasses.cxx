#include "SelectionPasses.h"

#include <canopy/filters/vtkCanopyExtractSelection.h>

namespace canopy
{

using Modes = vtkCanopyExtractSelection::SelectionModes;

SelectionRegion regionOf(const CellSelection& selection, const SelectionSpec& spec)
{
  if (spec.mode == Modes::BOX)
  {
    return selection.boxRegion(spec.box);
  }
  if (spec.mode == Modes::FRUSTUM)
  {
    return selection.frustumRegion(spec.frustum);
  }
  return SelectionRegion();
}

std::vector<SelectedNode> selectNodes(const CellSelection& selection, const SelectionSpec& spec,
                                      const SelectionRegion& region, bool forMask,
                                      SelectionReport& report)
{
  if (spec.mode == Modes::LOCATIONS)
  {
    return selection.byLocation(spec.points, report);
  }
  if (spec.mode == Modes::IDS)
  {
    return selection.byId(spec.ids, report);
  }
  if (forMask)
  {
    return {}; // the mask pass tests values and regions itself
  }
  if (spec.mode == Modes::VALUE_RANGE)
  {
    return selection.byValue(spec.values, spec.component, spec.range[0], spec.range[1]);
  }
  if (spec.byRegion())
  {
    return selection.byRegion(region, report);
  }
  return {};
}

SelectionMaskResult selectionMaskOf(const HyperTreeAccess& grid, const SelectionSpec& spec,
                                    const SelectionRegion& region,
                                    const std::vector<SelectedNode>& listed, bool allowMasked,
                                    SelectionMaskMemo& memo, const ProgressShare& progress,
                                    std::size_t& visited)
{
  if (spec.mode == Modes::VALUE_RANGE)
  {
    return selectionMaskOfLeaves(
        grid,
        CellSelection::valueInRange(spec.values, spec.component, spec.range[0], spec.range[1]),
        spec.invert, allowMasked, memo, progress);
  }
  if (spec.byRegion())
  {
    return selectionMaskOfRegion(grid, region, spec.invert, allowMasked, memo, visited, progress);
  }
  return selectionMask(grid, listed, spec.invert, allowMasked, memo, progress);
}

} // namespace canopy
