// Whether a grid's pure mask (vtkHyperTreeGrid::GetPureMask, which Canopy gives
// rather than lets VTK compute: adaptor/common/PureMask.h) is what VTK's own
// cursor walk computes, on every node that walk reaches (never below a masked one).
#pragma once

#include "HtgWalk.h"

#include <vtkBitArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkNew.h>

#include <cstddef>

namespace canopy::testing
{

struct PureMaskComparison
{
  std::size_t compared = 0;
  std::size_t differing = 0;
  bool sameArray = false; ///< the grid computed its own after all
};

inline PureMaskComparison comparePureMask(vtkHyperTreeGrid* given)
{
  // The same structure and mask without the given pure mask: VTK computes its own.
  vtkNew<vtkHyperTreeGrid> computed;
  computed->CopyEmptyStructure(given);
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  given->InitializeTreeIterator(it);
  vtkIdType index = 0;
  while (vtkHyperTree* tree = it.GetNextTree(index))
  {
    computed->SetTree(index, tree);
  }
  computed->SetMask(given->GetMask());
  vtkBitArray* ours = given->GetPureMask();
  vtkBitArray* vtks = computed->GetPureMask();
  PureMaskComparison result;
  result.sameArray = ours == vtks;
  forEachReachableNode(
      computed,
      [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor, const std::vector<vtkIdType>&)
      {
        const vtkIdType global = cursor->GetGlobalNodeIndex();
        ++result.compared;
        result.differing += ours->GetValue(global) != vtks->GetValue(global);
      });
  return result;
}

} // namespace canopy::testing
