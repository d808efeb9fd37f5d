// Whether two hypertree grids are the same grid, node by node: topology, mask,
// levels, global indices and every component of the named cell fields (masked
// subtrees as a whole: cursors cannot enter them). GoogleTest assertions; one
// home for what the .htg round trip and the packed grid's round trip check.
#pragma once

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkNew.h>

#include <cstddef>
#include <vector>

namespace canopy::testing
{

struct SameGridTotals
{
  std::size_t trees = 0;
  std::size_t nodes = 0;
  std::size_t masked = 0;
};

inline void expectSameNode(vtkHyperTreeGridNonOrientedGeometryCursor* a,
                           vtkHyperTreeGridNonOrientedGeometryCursor* b, vtkHyperTreeGrid* ga,
                           vtkHyperTreeGrid* gb, const std::vector<const char*>& fields,
                           SameGridTotals& totals)
{
  ++totals.nodes;
  ASSERT_EQ(a->IsMasked(), b->IsMasked());
  ASSERT_EQ(a->IsLeaf(), b->IsLeaf());
  ASSERT_EQ(a->GetLevel(), b->GetLevel());
  // Cells come back breadth-first, tree by tree: Canopy's own numbering.
  ASSERT_EQ(a->GetGlobalNodeIndex(), b->GetGlobalNodeIndex());
  for (const char* name : fields)
  {
    vtkDataArray* va = ga->GetCellData()->GetArray(name);
    vtkDataArray* vb = gb->GetCellData()->GetArray(name);
    ASSERT_NE(vb, nullptr) << name;
    ASSERT_EQ(vb->GetDataType(), va->GetDataType()) << name;
    const int components = va->GetNumberOfComponents();
    ASSERT_EQ(vb->GetNumberOfComponents(), components) << name;
    for (int c = 0; c < components; ++c)
    {
      ASSERT_EQ(va->GetComponent(a->GetGlobalNodeIndex(), c),
                vb->GetComponent(b->GetGlobalNodeIndex(), c))
          << name << " component " << c;
    }
  }
  if (a->IsMasked())
  {
    ++totals.masked;
    return;
  }
  if (a->IsLeaf())
  {
    return;
  }
  for (unsigned char c = 0; c < a->GetNumberOfChildren(); ++c)
  {
    a->ToChild(c);
    b->ToChild(c);
    expectSameNode(a, b, ga, gb, fields, totals);
    a->ToParent();
    b->ToParent();
  }
}

/// Every tree of `expected` compared with the same tree of `actual`.
inline SameGridTotals expectSameGrid(vtkHyperTreeGrid* expected, vtkHyperTreeGrid* actual,
                                     const std::vector<const char*>& fields)
{
  SameGridTotals totals;
  EXPECT_EQ(actual->GetDimension(), expected->GetDimension());
  EXPECT_EQ(actual->GetBranchFactor(), expected->GetBranchFactor());
  EXPECT_EQ(actual->HasMask(), expected->HasMask());
  vtkHyperTreeGrid::vtkHyperTreeGridIterator trees;
  expected->InitializeTreeIterator(trees);
  vtkIdType index = 0;
  while (trees.GetNextTree(index))
  {
    ++totals.trees;
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> a;
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> b;
    expected->InitializeNonOrientedGeometryCursor(a, index);
    actual->InitializeNonOrientedGeometryCursor(b, index);
    expectSameNode(a, b, expected, actual, fields, totals);
  }
  return totals;
}

} // namespace canopy::testing
