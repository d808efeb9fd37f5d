// Paper cases A and B described through Canopy's API must equal, node by node,
// what vtkHyperTreeGridSource builds from the same descriptor strings.
#include "HtgWalk.h"
#include "PaperCaseDefinitions.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkHyperTreeGridSource.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <array>

#include <string>

namespace canopy::testing
{
namespace
{

vtkSmartPointer<vtkHyperTreeGrid> buildWithVtkSource(const SourceParameters& p)
{
  vtkNew<vtkHyperTreeGridSource> source;
  source->SetDimensions(p.dimensions[0], p.dimensions[1], p.dimensions[2]);
  source->SetGridScale(p.gridScale[0], p.gridScale[1], p.gridScale[2]);
  source->SetBranchFactor(p.branchFactor);
  source->SetMaxDepth(p.maxDepth);
  source->SetDescriptor(p.descriptor.c_str());
  if (!p.mask.empty())
  {
    source->SetUseMask(true);
    source->SetMask(p.mask.c_str());
  }
  source->Update();
  vtkSmartPointer<vtkHyperTreeGrid> htg = source->GetHyperTreeGridOutput();
  return htg;
}

struct WalkTotals
{
  std::size_t nodes = 0;
  std::size_t leaves = 0;
  std::size_t unmaskedLeaves = 0;
};

/// Walks both trees together and compares every node.
/// Where Canopy must have put each node: slot = tree offset + breadth-first number.
struct ExpectedSlots
{
  std::size_t offset;
  std::vector<std::size_t> firstChild;
};

void compareSubtrees(vtkHyperTreeGridNonOrientedGeometryCursor* canopy,
                     vtkHyperTreeGridNonOrientedGeometryCursor* reference,
                     vtkDataArray* canopyDepth, vtkDataArray* referenceDepth, bool masked,
                     WalkTotals& totals, const std::string& where, const ExpectedSlots& slots,
                     std::size_t node)
{
  ++totals.nodes;
  ASSERT_EQ(canopy->GetGlobalNodeIndex(), static_cast<vtkIdType>(slots.offset + node)) << where;
  ASSERT_EQ(canopy->IsLeaf(), reference->IsLeaf()) << where;
  ASSERT_EQ(canopy->GetLevel(), reference->GetLevel()) << where;
  if (masked)
  {
    ASSERT_EQ(canopy->IsMasked(), reference->IsMasked()) << where;
  }
  double canopyBounds[6];
  double referenceBounds[6];
  canopy->GetBounds(canopyBounds);
  reference->GetBounds(referenceBounds);
  for (int i = 0; i < 6; ++i)
  {
    ASSERT_DOUBLE_EQ(canopyBounds[i], referenceBounds[i]) << where << " bound " << i;
  }
  ASSERT_EQ(canopyDepth->GetTuple1(canopy->GetGlobalNodeIndex()),
            referenceDepth->GetTuple1(reference->GetGlobalNodeIndex()))
      << where;
  if (canopy->IsLeaf())
  {
    ++totals.leaves;
    totals.unmaskedLeaves += masked && canopy->IsMasked() ? 0 : 1;
    return;
  }
  if (canopy->IsMasked())
  {
    return; // VTK's cursors do not descend below a masked node
  }
  for (unsigned char c = 0; c < canopy->GetNumberOfChildren(); ++c)
  {
    canopy->ToChild(c);
    reference->ToChild(c);
    compareSubtrees(canopy, reference, canopyDepth, referenceDepth, masked, totals,
                    where + "/" + std::to_string(c), slots, slots.firstChild[node] + c);
    canopy->ToParent();
    reference->ToParent();
  }
}

WalkTotals compareGrids(vtkHyperTreeGrid* canopy, vtkHyperTreeGrid* reference, bool masked,
                        const DescriptorForest& forest)
{
  WalkTotals totals;
  EXPECT_EQ(canopy->GetDimension(), reference->GetDimension());
  EXPECT_EQ(canopy->GetBranchFactor(), reference->GetBranchFactor());
  EXPECT_EQ(canopy->GetMaxNumberOfTrees(), reference->GetMaxNumberOfTrees());
  EXPECT_EQ(canopy->GetNumberOfLevels(), reference->GetNumberOfLevels());
  EXPECT_EQ(canopy->GetNumberOfCells(), reference->GetNumberOfCells());
  EXPECT_EQ(canopy->HasMask(), reference->HasMask());
  for (int axis = 0; axis < 3; ++axis)
  {
    EXPECT_EQ(canopy->GetDimensions()[axis], reference->GetDimensions()[axis]);
  }
  vtkDataArray* canopyDepth = canopy->GetCellData()->GetArray("Depth");
  vtkDataArray* referenceDepth = reference->GetCellData()->GetArray("Depth");
  EXPECT_NE(canopyDepth, nullptr);
  EXPECT_NE(referenceDepth, nullptr);
  if (!canopyDepth || !referenceDepth)
  {
    return totals;
  }
  vtkHyperTreeGrid::vtkHyperTreeGridIterator trees;
  reference->InitializeTreeIterator(trees);
  vtkIdType index = 0;
  std::size_t referenceTrees = 0;
  while (trees.GetNextTree(index))
  {
    ++referenceTrees;
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> canopyCursor;
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> referenceCursor;
    EXPECT_NE(canopy->GetTree(index), nullptr) << "tree " << index << " missing in Canopy's grid";
    if (!canopy->GetTree(index))
    {
      continue;
    }
    canopy->InitializeNonOrientedGeometryCursor(canopyCursor, index);
    reference->InitializeNonOrientedGeometryCursor(referenceCursor, index);
    ExpectedSlots slots{0, {}};
    const auto& refinement = forest.refinement();
    for (vtkIdType t = 0; t < index; ++t)
    {
      slots.offset += refinement[static_cast<std::size_t>(t)].size();
    }
    const auto& tree = refinement[static_cast<std::size_t>(index)];
    const std::size_t children = canopy->GetNumberOfChildren();
    std::size_t next = 1;
    slots.firstChild.assign(tree.size(), 0);
    for (std::size_t n = 0; n < tree.size(); ++n)
    {
      if (tree[n])
      {
        slots.firstChild[n] = next;
        next += children;
      }
    }
    compareSubtrees(canopyCursor, referenceCursor, canopyDepth, referenceDepth, masked, totals,
                    "tree " + std::to_string(index), slots, 0);
  }
  return totals;
}

/// A leaf under a masked ancestor is hidden even when its own mask bit is 0.
std::size_t visibleLeavesOf(vtkHyperTreeGrid* htg)
{
  std::size_t visible = 0;
  forEachVisibleLeaf(htg, [&](vtkHyperTreeGridNonOrientedGeometryCursor*) { ++visible; });
  return visible;
}

TEST(PaperCases, CaseAEqualsVtkSource)
{
  DescriptorForest forest(paperCaseA(false));
  EXPECT_EQ(forest.numberOfNodes(), 98u);
  EXPECT_EQ(forest.numberOfLeaves(), 75u);
  auto canopy = buildHyperTreeGrid(forest.description());
  auto reference = buildWithVtkSource(paperCaseA(false));
  const WalkTotals totals = compareGrids(canopy, reference, false, forest);
  EXPECT_EQ(totals.nodes, 98u);
  EXPECT_EQ(totals.leaves, 75u);
}

TEST(PaperCases, CaseAWithMaskEqualsVtkSource)
{
  DescriptorForest forest(paperCaseA(true));
  auto canopy = buildHyperTreeGrid(forest.description());
  auto reference = buildWithVtkSource(paperCaseA(true));
  const WalkTotals totals = compareGrids(canopy, reference, true, forest);
  EXPECT_EQ(totals.nodes, 98u);
  EXPECT_EQ(visibleLeavesOf(canopy), 62u);
  EXPECT_EQ(visibleLeavesOf(reference), 62u);
  EXPECT_EQ(forest.numberOfUnmaskedLeaves(), 62u);
}

TEST(PaperCases, CaseBEqualsVtkSource)
{
  DescriptorForest forest(paperCaseB(false));
  EXPECT_EQ(forest.numberOfLeaves(), 954u);
  auto canopy = buildHyperTreeGrid(forest.description());
  auto reference = buildWithVtkSource(paperCaseB(false));
  const WalkTotals totals = compareGrids(canopy, reference, false, forest);
  EXPECT_EQ(totals.nodes, forest.numberOfNodes());
  EXPECT_EQ(totals.leaves, 954u);
}

TEST(PaperCases, CaseBWithMaskEqualsVtkSource)
{
  DescriptorForest forest(paperCaseB(true));
  auto canopy = buildHyperTreeGrid(forest.description());
  auto reference = buildWithVtkSource(paperCaseB(true));
  const WalkTotals totals = compareGrids(canopy, reference, true, forest);
  EXPECT_EQ(totals.leaves, 954u);
  EXPECT_EQ(visibleLeavesOf(canopy), 844u);
  EXPECT_EQ(visibleLeavesOf(reference), 844u);
  EXPECT_EQ(forest.numberOfUnmaskedLeaves(), 844u);
}

TEST(PaperCases, FiltersAcceptGridsFromVtkSource)
{
  // vtkHyperTreeGridSource leaves a 0 in a single-leaf tree's child table and
  // uses explicit global indices: both must be read correctly.
  for (bool caseB : {false, true})
  {
    auto reference = buildWithVtkSource(caseB ? paperCaseB(false) : paperCaseA(false));
    vtkNew<vtkCanopyAdaptiveSurface> surface;
    surface->SetInputData(reference);
    surface->ViewDependentOff();
    surface->Update();
    EXPECT_EQ(surface->GetPolyDataOutput()->GetNumberOfCells(), caseB ? 466 : 75);
  }
}

/// 1D forests along each axis (lines of roots), binary and ternary, with and
/// without a mask, as vtkHyperTreeGridSource builds them from the same strings.
std::vector<SourceParameters> lineCases()
{
  std::vector<SourceParameters> cases;
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int f : {2, 3})
    {
      SourceParameters p;
      p.dimensions = {{1, 1, 1}};
      p.dimensions[axis] = 5;
      p.gridScale = {{1.5, 0.5, 0.7}};
      p.branchFactor = f;
      if (f == 2)
      {
        p.maxDepth = 5;
        p.descriptor = "R.RR|R. .. .R|R. .R|.. R.|..";
        p.mask = "1111|10 11 11|11 01|11 11|11";
      }
      else
      {
        p.maxDepth = 4;
        p.descriptor = "R..R|R.. ..R|... .R.|...";
        p.mask = "1101|110 111|111 110|111";
      }
      cases.push_back(p);
      p.mask.clear();
      cases.push_back(p);
    }
  }
  return cases;
}

TEST(LineForests, EqualVtkSourceAlongEveryAxis)
{
  for (const SourceParameters& p : lineCases())
  {
    DescriptorForest forest(p);
    ASSERT_EQ(forest.description().dimension, 1);
    auto canopy = buildHyperTreeGrid(forest.description());
    auto reference = buildWithVtkSource(p);
    const std::string label = "axis " +
                              std::to_string(p.dimensions[0] > 1   ? 0
                                             : p.dimensions[1] > 1 ? 1
                                                                   : 2) +
                              ", branch factor " + std::to_string(p.branchFactor) +
                              (p.mask.empty() ? "" : ", masked");
    EXPECT_EQ(canopy->GetDimension(), 1u) << label;
    EXPECT_EQ(canopy->GetOrientation(), reference->GetOrientation()) << label;
    EXPECT_EQ(canopy->GetNumberOfChildren(), static_cast<unsigned int>(p.branchFactor)) << label;
    const WalkTotals totals = compareGrids(canopy, reference, !p.mask.empty(), forest);
    EXPECT_EQ(totals.nodes, forest.numberOfNodes()) << label;
    EXPECT_EQ(totals.leaves, forest.numberOfLeaves()) << label;
    EXPECT_EQ(visibleLeavesOf(canopy), forest.numberOfUnmaskedLeaves()) << label;
    EXPECT_EQ(visibleLeavesOf(reference), forest.numberOfUnmaskedLeaves()) << label;
    if (!p.mask.empty())
    {
      EXPECT_LT(forest.numberOfUnmaskedLeaves(), forest.numberOfLeaves()) << label;
    }
  }
}

/// The segments a box selects, as sorted (lo, hi) bounds.
std::vector<std::array<double, 6>> boxSelection(vtkHyperTreeGrid* htg, const double box[6])
{
  vtkNew<vtkCanopyExtractSelection> filter;
  filter->SetInputData(htg);
  filter->SetSelectionMode(vtkCanopyExtractSelection::BOX);
  filter->SetBox(box);
  filter->Update();
  auto* out = vtkUnstructuredGrid::SafeDownCast(filter->GetOutput());
  std::vector<std::array<double, 6>> cells;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    std::array<double, 6> b;
    out->GetCell(c)->GetBounds(b.data());
    cells.push_back(b);
  }
  std::sort(cells.begin(), cells.end());
  return cells;
}

TEST(LineForests, FiltersAcceptVtkSourceLines)
{
  // VTK's 1D grids (explicit global indices, a 0 in single-leaf trees' child
  // tables) give the filters what Canopy's own give them.
  for (const SourceParameters& p : lineCases())
  {
    DescriptorForest forest(p);
    auto canopy = buildHyperTreeGrid(forest.description());
    auto reference = buildWithVtkSource(p);
    vtkNew<vtkCanopyAdaptiveSurface> surface;
    surface->SetInputData(reference);
    surface->ViewDependentOff();
    surface->Update();
    EXPECT_EQ(surface->GetPolyDataOutput()->GetNumberOfLines(),
              static_cast<vtkIdType>(forest.numberOfUnmaskedLeaves()));
    double b[6];
    canopy->GetBounds(b);
    const int axis = p.dimensions[0] > 1 ? 0 : p.dimensions[1] > 1 ? 1 : 2;
    const double box[6] = {-1, 1, -1, 1, -1, 1};
    double middle[6];
    std::copy(box, box + 6, middle);
    middle[2 * axis] = b[2 * axis] + 0.3 * (b[2 * axis + 1] - b[2 * axis]);
    middle[2 * axis + 1] = b[2 * axis] + 0.8 * (b[2 * axis + 1] - b[2 * axis]);
    const auto expected = boxSelection(canopy, middle);
    EXPECT_FALSE(expected.empty());
    const auto got = boxSelection(reference, middle);
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i)
    {
      for (int k = 0; k < 6; ++k)
      {
        EXPECT_DOUBLE_EQ(got[i][k], expected[i][k]);
      }
    }
  }
}

} // namespace
} // namespace canopy::testing
