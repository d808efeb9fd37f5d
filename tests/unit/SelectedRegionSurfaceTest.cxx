// Selected regions drawn as surfaces: a value range and a cut-away box
// (vtkCanopyExtractSelection with PreserveTopology, the second one inverted),
// then vtkCanopyAdaptiveSurface. The surface must be exactly the faces between
// selected and unselected cells, voxel by voxel, where the selection is worked
// out by brute force from the forest (values from the forest's own numbering,
// boxes from VTK's cursors). The same on 2 and 4 MPI ranks with split trees:
// tests/mpi/SplitTreeSurfacesTest.cxx. Also: Invert and the INVERSE key select
// the complement, and a selected coarse cell never reveals masked or absent cells.
#include "PureMaskCheck.h"
#include "SelectedRegionCase.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <gtest/gtest.h>
#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSelection.h>
#include <vtkSelectionNode.h>
#include <vtkUnstructuredGrid.h>

#include <map>
#include <set>

namespace canopy::testing
{
namespace
{

TEST(SelectedRegionSurface, IsExactlyTheFacesBetweenSelectedAndUnselectedCells)
{
  for (const char* field : {"node", "hash"})
    for (std::uint64_t seed : {3u, 8u})
    {
      SelectedRegionCase region(seed, field);
      ASSERT_GT(region.selected, region.leaves / 5) << "a region worth drawing";
      ASSERT_LT(region.selected, region.leaves * 4 / 5);
      expectExactBoundary(Voxels(region.oracle),
                          selectedSurface(buildHyperTreeGrid(region.described), region.field,
                                          region.range, region.cutAway),
                          std::string(field) + " seed " + std::to_string(seed));
    }
}

std::set<vtkIdType> idsOf(vtkCanopyExtractSelection* filter)
{
  EXPECT_TRUE(errorsOfUpdate(filter).empty());
  std::set<vtkIdType> ids;
  auto* out = vtkUnstructuredGrid::SafeDownCast(filter->GetOutputDataObject(0));
  vtkDataArray* original = out->GetCellData()->GetArray("OriginalCellId");
  for (vtkIdType i = 0; original && i < original->GetNumberOfTuples(); ++i)
  {
    ids.insert(static_cast<vtkIdType>(original->GetTuple1(i)));
  }
  return ids;
}

TEST(SelectionInvert, AnInvertedBoxSelectsEveryOtherVisibleLeaf)
{
  RandomForestOptions o = SelectedRegionCase::options(5);
  o.maskProbability = 0.1;
  RandomForest forest(o);
  auto htg = buildHyperTreeGrid(forest.description());
  double b[6];
  htg->GetBounds(b);
  const std::array<double, 6> box{{b[0] + 0.2 * (b[1] - b[0]), b[0] + 0.7 * (b[1] - b[0]), b[2],
                                   b[2] + 0.6 * (b[3] - b[2]), b[4] + 0.1 * (b[5] - b[4]), b[5]}};
  std::set<vtkIdType> inside;
  std::set<vtkIdType> outside;
  for (const LeafBox& leaf : visibleLeafBoxes(htg))
  {
    (overlapsBox(leaf.bounds, box) ? inside : outside).insert(leaf.global);
  }
  ASSERT_FALSE(inside.empty());
  ASSERT_FALSE(outside.empty());
  vtkNew<vtkCanopyExtractSelection> filter;
  filter->SetInputData(htg);
  filter->SetSelectionMode(vtkCanopyExtractSelection::BOX);
  filter->SetBox(box.data());
  EXPECT_EQ(idsOf(filter), inside);
  filter->InvertOn();
  EXPECT_EQ(idsOf(filter), outside);

  // The same through a selection input: INVERSE inverts, and inverts Invert back.
  vtkNew<vtkSelection> selection;
  vtkNew<vtkSelectionNode> node;
  node->SetContentType(vtkSelectionNode::GLOBALIDS);
  node->SetFieldType(vtkSelectionNode::CELL);
  vtkNew<vtkDoubleArray> list;
  for (vtkIdType id : inside)
  {
    list->InsertNextValue(static_cast<double>(id));
  }
  node->SetSelectionList(list);
  node->GetProperties()->Set(vtkSelectionNode::INVERSE(), 1);
  selection->AddNode(node);
  vtkNew<vtkCanopyExtractSelection> byIds;
  byIds->SetInputData(0, htg);
  byIds->SetInputData(1, selection);
  EXPECT_EQ(idsOf(byIds), outside);
  byIds->InvertOn();
  EXPECT_EQ(idsOf(byIds), inside);
}

TEST(SelectionMask, ASelectedCoarseCellNeverRevealsMaskedOrAbsentCells)
{
  RandomForestOptions o = SelectedRegionCase::options(9);
  o.maskProbability = 0.2;
  RandomForest forest(o);
  auto htg = buildHyperTreeGrid(forest.description());
  std::set<vtkIdType> visibleBefore;
  std::vector<vtkIdType> coarse;
  forEachVisibleNode(htg,
                     [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
                     {
                       visibleBefore.insert(cursor->GetGlobalNodeIndex());
                       if (!cursor->IsLeaf() && cursor->GetLevel() == 1)
                       {
                         coarse.push_back(cursor->GetGlobalNodeIndex());
                       }
                     });
  ASSERT_GT(coarse.size(), 3u);
  vtkNew<vtkCanopyExtractSelection> filter;
  filter->SetInputData(htg);
  filter->SetSelectionMode(vtkCanopyExtractSelection::IDS);
  for (vtkIdType id : coarse)
  {
    filter->AddId(id);
  }
  filter->PreserveTopologyOn();
  ASSERT_TRUE(errorsOfUpdate(filter).empty());
  auto* out = vtkHyperTreeGrid::SafeDownCast(filter->GetOutputDataObject(0));
  std::size_t visibleAfter = 0;
  std::size_t revealed = 0;
  forEachVisibleNode(out,
                     [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
                     {
                       ++visibleAfter;
                       revealed += visibleBefore.count(cursor->GetGlobalNodeIndex()) == 0;
                     });
  EXPECT_EQ(revealed, 0u) << "cells masked in the input became visible";
  EXPECT_GT(visibleAfter, coarse.size()) << "the selected subtrees are shown";
}

TEST(SelectionMask, TheOutputCarriesThePureMaskVTKWouldCompute)
{
  // The filter gives its output VTK's "pure mask" (PureMask.h) so that nobody
  // pays VTK's cursor walk for it: it must be what that walk computes, on every
  // node the walk reaches (it never goes below a masked node).
  for (bool invert : {false, true})
  {
    SelectedRegionCase region(4, "hash");
    RankPart part(region.whole.description(), 1, 3, false); // absent cells too
    vtkNew<vtkCanopyExtractSelection> filter;
    filter->SetInputData(buildHyperTreeGrid(part.description));
    filter->SetSelectionMode(vtkCanopyExtractSelection::VALUE_RANGE);
    filter->SetValueArrayName("hash");
    filter->SetValueRange(0.0, 0.5);
    filter->SetInvert(invert);
    filter->PreserveTopologyOn();
    ASSERT_TRUE(errorsOfUpdate(filter).empty());
    const PureMaskComparison pure =
        comparePureMask(vtkHyperTreeGrid::SafeDownCast(filter->GetOutputDataObject(0)));
    EXPECT_FALSE(pure.sameArray);
    const std::size_t compared = pure.compared;
    const std::size_t differing = pure.differing;
    EXPECT_GT(compared, 100u);
    EXPECT_EQ(differing, 0u) << (invert ? "inverted" : "selected");
  }
}

} // namespace
} // namespace canopy::testing
