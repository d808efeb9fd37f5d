// Whether a grid's pure mask (vtkHyperTreeGrid::GetPureMask, which Canopy gives
// rather than lets VTK compute: adaptor/common/PureMask.h) is what VTK's own
// cursor walk computes, on every node that walk reaches (never below a masked one).
#pragma once

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
  vtkHyperTreeGrid::vtkHyperTreeGridIterator trees;
  computed->InitializeTreeIterator(trees);
  while (trees.GetNextTree(index))
  {
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> cursor;
    computed->InitializeNonOrientedGeometryCursor(cursor, index);
    auto walk = [&](auto& self) -> void
    {
      const vtkIdType global = cursor->GetGlobalNodeIndex();
      ++result.compared;
      result.differing += ours->GetValue(global) != vtks->GetValue(global);
      if (cursor->IsMasked() || cursor->IsLeaf())
      {
        return;
      }
      for (unsigned char c = 0; c < cursor->GetNumberOfChildren(); ++c)
      {
        cursor->ToChild(c);
        self(self);
        cursor->ToParent();
      }
    };
    walk(walk);
  }
  return result;
}

} // namespace canopy::testing
