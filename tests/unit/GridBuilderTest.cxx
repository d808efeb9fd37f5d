// GridBuilder against a fresh build at every step of random sequences of
// changes (some trees re-refined, masks toggled, fields moved, values changed,
// slot maps, absent parts): node by node, the reused grid must equal the grid
// buildHyperTreeGrid builds from scratch, only the changed trees are rebuilt,
// and filters downstream see every change.
#include "ChangingForest.h"

#include <canopy/GridBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyContour.h>

#include <gtest/gtest.h>
#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <cstdint>
#include <random>
#include <vector>

namespace canopy::testing
{
namespace
{

/// Node by node: trees, leaves, cells, mask, every field's values.
void expectSameGrid(vtkHyperTreeGrid* a, vtkHyperTreeGrid* b)
{
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  b->InitializeTreeIterator(it);
  vtkIdType index = 0;
  std::size_t trees = 0;
  while (vtkHyperTree* expected = it.GetNextTree(index))
  {
    ++trees;
    vtkHyperTree* got = a->GetTree(index);
    ASSERT_NE(got, nullptr) << "tree " << index;
    ASSERT_EQ(got->GetNumberOfVertices(), expected->GetNumberOfVertices()) << "tree " << index;
    for (vtkIdType n = 0; n < expected->GetNumberOfVertices(); ++n)
    {
      ASSERT_EQ(got->IsLeaf(n), expected->IsLeaf(n)) << "tree " << index << " node " << n;
      ASSERT_EQ(got->GetGlobalIndexFromLocal(n), expected->GetGlobalIndexFromLocal(n));
    }
  }
  EXPECT_GT(trees, 0u);
  ASSERT_EQ(a->HasMask(), b->HasMask());
  for (vtkIdType c = 0; b->HasMask() && c < b->GetNumberOfCells(); ++c)
    ASSERT_EQ(a->GetMask()->GetValue(c), b->GetMask()->GetValue(c)) << "mask of cell " << c;
  ASSERT_EQ(a->GetCellData()->GetNumberOfArrays(), b->GetCellData()->GetNumberOfArrays());
  for (int i = 0; i < b->GetCellData()->GetNumberOfArrays(); ++i)
  {
    vtkDataArray* expected = b->GetCellData()->GetArray(i);
    vtkDataArray* got = a->GetCellData()->GetArray(expected->GetName());
    ASSERT_NE(got, nullptr) << expected->GetName();
    ASSERT_EQ(got->GetNumberOfTuples(), expected->GetNumberOfTuples());
    for (vtkIdType c = 0; c < expected->GetNumberOfTuples(); ++c)
      ASSERT_EQ(got->GetComponent(c, 0), expected->GetComponent(c, 0))
          << expected->GetName() << " at cell " << c;
  }
}

class GridBuilderSequence : public ::testing::TestWithParam<std::tuple<int, bool>>
{
};

TEST_P(GridBuilderSequence, EveryStepEqualsAFreshBuildAndOnlyChangedTreesAreRebuilt)
{
  const auto [dimension, slots] = GetParam();
  ChangingForest forest(dimension, dimension == 3 ? 8 : 9, slots, 4242 + dimension);
  std::mt19937_64 random(99);
  GridBuilder builder;
  vtkHyperTreeGrid* previous = nullptr;
  vtkMTimeType previousTime = 0;
  for (int step = 0; step < 40; ++step)
  {
    // Change a random number of trees (none at some steps), sometimes only masks.
    std::size_t refined = 0;
    std::vector<bool> touched(forest.size(), false);
    const int changes = step == 0 ? 0 : static_cast<int>(random() % 4);
    for (int c = 0; c < changes; ++c)
    {
      const std::size_t t = random() % forest.size();
      if (random() % 3 == 0)
      {
        forest.toggleMask(t); // the mask changes, the tree stays
      }
      else
      {
        forest.refine(t);
        refined += !touched[t];
        touched[t] = true;
      }
    }
    const ForestDescription d = forest.describe(100.0 * step);
    vtkSmartPointer<vtkHyperTreeGrid> built = builder.build(d);
    vtkSmartPointer<vtkHyperTreeGrid> fresh = buildHyperTreeGrid(d);
    expectSameGrid(built, fresh);
    if (HasFatalFailure())
      return;
    const GridBuilder::Reuse& reuse = builder.lastBuild();
    if (step == 0)
    {
      EXPECT_TRUE(reuse.newGrid);
    }
    else
    {
      // The same grid object, modified; rebuilt trees are those re-refined (a
      // re-refinement may happen to draw the same tree again: at most `refined`).
      EXPECT_FALSE(reuse.newGrid) << "step " << step;
      EXPECT_EQ(built.GetPointer(), previous) << "step " << step;
      EXPECT_LE(reuse.treesRebuilt, refined) << "step " << step;
      if (refined == 0)
      {
        EXPECT_EQ(reuse.treesRebuilt, 0u) << "step " << step;
      }
      EXPECT_EQ(reuse.treesRebuilt + reuse.treesKept, forest.size());
      EXPECT_GT(built->GetMTime(), previousTime) << "step " << step;
    }
    previous = built;
    previousTime = built->GetMTime();
  }
}

INSTANTIATE_TEST_SUITE_P(DimensionAndSlots, GridBuilderSequence,
                         ::testing::Combine(::testing::Values(2, 3), ::testing::Bool()));

TEST(GridBuilder, UnchangedTopologyRebuildsNoTreeAndFiltersSeeNewValues)
{
  ChangingForest forest(2, 9, false, 7);
  GridBuilder builder;
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetViewDependent(false);
  auto grid = builder.build(forest.describe(0.0));
  surface->SetInputData(grid);
  surface->Update();
  const double before = vtkPolyData::SafeDownCast(surface->GetOutput())
                            ->GetCellData()
                            ->GetArray("value")
                            ->GetRange()[1];
  // Same topology, values moved and changed.
  grid = builder.build(forest.describe(1000.0));
  EXPECT_EQ(builder.lastBuild().treesRebuilt, 0u);
  EXPECT_EQ(builder.lastBuild().treesKept, forest.size());
  surface->Update();
  const double after = vtkPolyData::SafeDownCast(surface->GetOutput())
                           ->GetCellData()
                           ->GetArray("value")
                           ->GetRange()[1];
  EXPECT_DOUBLE_EQ(after, before + 1000.0);
}

TEST(GridBuilder, ADifferentSetOfTreesGivesANewGrid)
{
  ChangingForest forest(2, 9, false, 8);
  GridBuilder builder;
  ForestDescription d = forest.describe(0.0);
  auto first = builder.build(d);
  d.trees.pop_back();
  d.fields.clear();
  auto second = builder.build(d);
  EXPECT_TRUE(builder.lastBuild().newGrid);
  EXPECT_NE(first.GetPointer(), second.GetPointer());
  expectSameGrid(second, buildHyperTreeGrid(d));
}

TEST(GridBuilder, AnInvalidDescriptionChangesNothing)
{
  ChangingForest forest(2, 9, false, 9);
  GridBuilder builder;
  const ForestDescription good = forest.describe(0.0);
  auto grid = builder.build(good);
  const vtkMTimeType time = grid->GetMTime();
  ForestDescription bad = good;
  bad.fields[0].numberOfTuples -= 1;
  EXPECT_THROW(builder.build(bad), InvalidForest);
  EXPECT_EQ(grid->GetMTime(), time);
  builder.build(good);
  EXPECT_EQ(builder.lastBuild().treesRebuilt, 0u);
}

TEST(GridBuilder, VouchedValuesKeepTheirArrays)
{
  // FieldDescription::valuesRevision: the same nonzero revision, the same
  // borrow and the same topology keep the array object, unmodified; anything
  // else wraps the field anew.
  ChangingForest forest(2, 9, false, 10);
  GridBuilder builder;
  ForestDescription d = forest.describe(0.0);
  d.fields[0].valuesRevision = 5;
  d.fields[1].valuesRevision = 5;
  auto grid = builder.build(d);
  EXPECT_EQ(builder.lastBuild().fieldsKept, 0u);
  auto arrayOf = [&](const char* name) { return grid->GetCellData()->GetArray(name); };
  vtkDataArray* value = arrayOf("value");
  vtkDataArray* leafValue = arrayOf("leafValue");
  const vtkMTimeType valueTime = value->GetMTime();
  const vtkMTimeType leafTime = leafValue->GetMTime();

  grid = builder.build(d);
  EXPECT_EQ(builder.lastBuild().fieldsKept, 2u);
  EXPECT_EQ(arrayOf("value"), value);
  EXPECT_EQ(arrayOf("leafValue"), leafValue);
  EXPECT_EQ(value->GetMTime(), valueTime);
  EXPECT_EQ(leafValue->GetMTime(), leafTime);
  expectSameGrid(grid, buildHyperTreeGrid(d));

  d.fields[1].valuesRevision = 0; // no word: wrapped anew
  grid = builder.build(d);
  EXPECT_EQ(builder.lastBuild().fieldsKept, 1u);
  EXPECT_EQ(arrayOf("value"), value);
  EXPECT_NE(arrayOf("leafValue"), leafValue);

  d.fields[0].valuesRevision = 6; // new values
  grid = builder.build(d);
  EXPECT_EQ(builder.lastBuild().fieldsKept, 0u);
  EXPECT_NE(arrayOf("value"), value);
  value = arrayOf("value");
  grid = builder.build(d);
  EXPECT_EQ(arrayOf("value"), value);

  // The same revision, the field described otherwise (strided over the same memory).
  const auto* data = static_cast<const double*>(d.fields[0].data);
  d.fields[0] =
      FieldDescription::strided("value", data, sizeof(double), d.fields[0].numberOfTuples);
  d.fields[0].valuesRevision = 6;
  grid = builder.build(d);
  EXPECT_EQ(builder.lastBuild().fieldsKept, 0u);
  EXPECT_NE(arrayOf("value"), value);
  value = arrayOf("value");

  // The same revision and memory, a mask changed: wrapped anew.
  forest.toggleMask(0);
  grid = builder.build(d);
  EXPECT_EQ(builder.lastBuild().fieldsKept, 0u);
  EXPECT_NE(arrayOf("value"), value);
  expectSameGrid(grid, buildHyperTreeGrid(d));
}

TEST(GridBuilder, VouchedValuesKeepTheContoursRanges)
{
  // Across builds whose values the simulation vouches for, the contour prunes
  // with the value ranges of the build before (no pass over the nodes).
  ChangingForest forest(2, 9, false, 11);
  GridBuilder builder;
  ForestDescription d = forest.describe(0.0);
  d.fields[0].valuesRevision = 1;
  vtkNew<vtkCanopyContour> contour;
  contour->SetInputData(builder.build(d));
  contour->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "value");
  contour->SetValue(0, 20.25);
  contour->Update();
  const vtkIdType cells = contour->GetOutput()->GetNumberOfCells();
  EXPECT_GT(cells, 0);
  EXPECT_FALSE(contour->GetLastRangesKept());
  contour->SetInputData(builder.build(d));
  contour->Update();
  EXPECT_TRUE(contour->GetLastRangesKept());
  EXPECT_EQ(contour->GetOutput()->GetNumberOfCells(), cells);
  d.fields[0].valuesRevision = 0;
  contour->SetInputData(builder.build(d));
  contour->Update();
  EXPECT_FALSE(contour->GetLastRangesKept());
  EXPECT_EQ(contour->GetOutput()->GetNumberOfCells(), cells);
}

} // namespace
} // namespace canopy::testing
