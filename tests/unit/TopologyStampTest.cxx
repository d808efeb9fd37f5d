// The one rule for what changed (common/TopologyStamp.h, filters/TopologyKeys.h):
// GridBuilder stamps each grid with the build that last changed each tree's
// refinement and marks; the stamp vouches only for what is still as stamped
// (every change made through VTK's API ends it); a simulation's own revision
// spares the builder reading the trees' bytes, and a revision that does not
// fit the trees is not trusted.
#include "TopologyStamp.h"
#include "ChangingForest.h"
#include "HyperTreeAccess.h"
#include "TopologyKeys.h"

#include <canopy/GridBuilder.h>
#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <gtest/gtest.h>

#include <vtkBitArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedCursor.h>
#include <vtkNew.h>

namespace
{

using canopy::readTopologyStamp;
using canopy::testing::ChangingForest;

using Revisions = std::pair<std::uint64_t, std::uint64_t>;

/// The stamp's (topology, marks) revisions of tree `index`; {0, 0} if it does not vouch.
Revisions revisionsOf(vtkHyperTreeGrid* grid, vtkIdType index)
{
  const auto stamp = readTopologyStamp(grid);
  const canopy::TreeStamp* tree = stamp ? stamp->vouchedTree(index, grid->GetTree(index)) : nullptr;
  return tree ? Revisions{tree->topology, tree->marks} : Revisions{0, 0};
}

TEST(TopologyStamp, TheBuilderStampsTheBuildThatChangedEachTree)
{
  ChangingForest forest(3, 8, true, 17);
  canopy::GridBuilder builder;
  vtkSmartPointer<vtkHyperTreeGrid> grid = builder.build(forest.describe(0));
  for (vtkIdType t = 0; t < 8; ++t)
  {
    EXPECT_EQ(revisionsOf(grid, t), Revisions(1, 1)) << "tree " << t;
  }
  // Build 2: values only. Build 3: tree 3 re-refined, tree 5's mask toggled.
  grid = builder.build(forest.describe(1));
  const std::size_t before = forest.numberOfNodes(3);
  do
  {
    forest.refine(3);
  } while (forest.numberOfNodes(3) == before);
  forest.toggleMask(5);
  grid = builder.build(forest.describe(2));
  ASSERT_EQ(builder.lastBuild().treesRebuilt, 1u);
  for (vtkIdType t = 0; t < 8; ++t)
  {
    const Revisions want = t == 3 ? Revisions(3, 3) : t == 5 ? Revisions(1, 3) : Revisions(1, 1);
    EXPECT_EQ(revisionsOf(grid, t), want) << "tree " << t;
  }
  const auto stamp = readTopologyStamp(grid);
  ASSERT_TRUE(stamp);
  EXPECT_TRUE(stamp->arraysVouched);
  EXPECT_EQ(stamp->arrays, 3u); // a mask changed at build 3
  EXPECT_EQ(stamp->builder, builder.identity());
}

TEST(TopologyStamp, ItVouchesOnlyForWhatIsAsStamped)
{
  ChangingForest forest(3, 8, false, 5);
  vtkSmartPointer<vtkHyperTreeGrid> grid = canopy::buildHyperTreeGrid(forest.describe(0));
  auto stamp = readTopologyStamp(grid);
  ASSERT_TRUE(stamp);
  EXPECT_TRUE(stamp->arraysVouched);
  EXPECT_NE(stamp->vouchedTree(2, grid->GetTree(2)), nullptr);

  // Another grid object (a filter's shallow copy carries the field data along).
  vtkNew<vtkHyperTreeGrid> copy;
  copy->ShallowCopy(grid);
  EXPECT_FALSE(readTopologyStamp(copy));

  // The mask marked modified, then replaced: the arrays are no longer vouched
  // for, the trees' topology still is.
  grid->GetMask()->Modified();
  stamp = readTopologyStamp(grid);
  ASSERT_TRUE(stamp);
  EXPECT_FALSE(stamp->arraysVouched);
  EXPECT_NE(stamp->vouchedTree(2, grid->GetTree(2)), nullptr);
  vtkNew<vtkBitArray> mask;
  mask->DeepCopy(grid->GetMask());
  grid->SetMask(mask);
  EXPECT_FALSE(readTopologyStamp(grid)->arraysVouched);
  canopy::HyperTreeAccess access(grid);
  for (const canopy::TreeAccess& tree : access.trees())
  {
    EXPECT_NE(tree.stampTopology, 0u);
    EXPECT_EQ(tree.stampMarks, 0u) << "marks must come from the cells, not the stamp";
    const canopy::TreeTopologyKey key = canopy::treeTopologyKey(access, tree);
    EXPECT_NE(key.marks, tree.stampMarks);
  }

  // A tree refined in place (VTK 9.2 never coarsens one): not vouched for. (VTK
  // refines only unmasked leaves: the mask goes first.)
  grid->SetMask(nullptr);
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cursor;
  grid->InitializeNonOrientedCursor(cursor, 2, false);
  while (!cursor->IsLeaf())
  {
    cursor->ToChild(0);
  }
  cursor->SubdivideLeaf();
  stamp = readTopologyStamp(grid);
  EXPECT_EQ(stamp->vouchedTree(2, grid->GetTree(2)), nullptr);
  EXPECT_NE(stamp->vouchedTree(1, grid->GetTree(1)), nullptr);
}

TEST(TopologyStamp, AnUnchangedStampedGridKeysOnRevisionsNotContent)
{
  ChangingForest forest(2, 6, true, 3);
  canopy::GridBuilder builder;
  vtkSmartPointer<vtkHyperTreeGrid> grid = builder.build(forest.describe(0));
  canopy::HyperTreeAccess first(grid);
  std::vector<canopy::TreeTopologyKey> keys;
  for (const auto& tree : first.trees())
  {
    keys.push_back(canopy::treeTopologyKey(first, tree));
    EXPECT_EQ(keys.back().builder, builder.identity());
    EXPECT_EQ(keys.back().marks, 1u) << "the stamp's revision, no fingerprint";
  }
  grid = builder.build(forest.describe(1)); // values only
  canopy::HyperTreeAccess second(grid);
  for (std::size_t t = 0; t < keys.size(); ++t)
  {
    EXPECT_TRUE(canopy::treeTopologyKey(second, second.trees()[t]) == keys[t]) << "tree " << t;
  }
  forest.toggleMask(4);
  grid = builder.build(forest.describe(2));
  canopy::HyperTreeAccess third(grid);
  for (std::size_t t = 0; t < keys.size(); ++t)
  {
    const bool same = canopy::treeTopologyKey(third, third.trees()[t]) == keys[t];
    EXPECT_EQ(same, t != 4) << "tree " << t;
  }
}

TEST(TopologyStamp, TheSimulationsRevisionSparesReadingTheTreesWhenItFits)
{
  ChangingForest forest(3, 8, true, 23);
  canopy::GridBuilder builder;
  canopy::ForestDescription d = forest.describe(0);
  d.revision = 41;
  builder.build(d);
  EXPECT_FALSE(builder.lastBuild().revisionTrusted);

  d = forest.describe(1);
  d.revision = 41; // nothing changed, the simulation says so
  vtkSmartPointer<vtkHyperTreeGrid> grid = builder.build(d);
  EXPECT_TRUE(builder.lastBuild().revisionTrusted);
  EXPECT_EQ(builder.lastBuild().treesKept, 8u);
  EXPECT_EQ(grid->GetNumberOfCells(), canopy::buildHyperTreeGrid(d)->GetNumberOfCells());

  // A revision that does not fit the trees (one has other nodes) is not trusted.
  const std::size_t before = forest.numberOfNodes(6);
  do
  {
    forest.refine(6);
  } while (forest.numberOfNodes(6) == before);
  d = forest.describe(2);
  d.revision = 41;
  grid = builder.build(d);
  EXPECT_FALSE(builder.lastBuild().revisionTrusted);
  EXPECT_EQ(builder.lastBuild().treesRebuilt, 1u);
  EXPECT_EQ(grid->GetNumberOfCells(), canopy::buildHyperTreeGrid(d)->GetNumberOfCells());

  // A new revision: the bytes are read.
  d.revision = 42;
  builder.build(d);
  EXPECT_FALSE(builder.lastBuild().revisionTrusted);
  EXPECT_EQ(builder.lastBuild().treesRebuilt, 0u);
}

TEST(TopologyStamp, ASelectionRedoesTheTreeWhoseMaskTheStampSaysChanged)
{
  // The selection's memo reads the stamp's marks revision, not the mask bits:
  // a tree whose mask changed is redone, the others kept, the output that of a
  // new filter.
  ChangingForest forest(3, 8, false, 5);
  canopy::GridBuilder builder;
  vtkSmartPointer<vtkHyperTreeGrid> grid = builder.build(forest.describe(0));
  vtkNew<vtkCanopyExtractSelection> kept;
  kept->SetInputData(grid);
  kept->SetSelectionMode(vtkCanopyExtractSelection::BOX);
  kept->SetBox(-10, 10, -10, 10, -10, 10);
  kept->PreserveTopologyOn();
  kept->Update();
  forest.toggleMask(3);
  grid = builder.build(forest.describe(1));
  kept->SetInputData(grid);
  kept->Update();
  EXPECT_EQ(kept->GetLastKeptTrees(), 7);
  EXPECT_EQ(kept->GetLastRecomputedNodes(), grid->GetTree(3)->GetNumberOfVertices());
  vtkNew<vtkCanopyExtractSelection> fresh;
  fresh->SetInputData(grid);
  fresh->SetSelectionMode(vtkCanopyExtractSelection::BOX);
  fresh->SetBox(-10, 10, -10, 10, -10, 10);
  fresh->PreserveTopologyOn();
  fresh->Update();
  auto* a = vtkHyperTreeGrid::SafeDownCast(kept->GetOutputDataObject(0));
  auto* b = vtkHyperTreeGrid::SafeDownCast(fresh->GetOutputDataObject(0));
  ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
  for (vtkIdType c = 0; c < a->GetNumberOfCells(); ++c)
  {
    ASSERT_EQ(a->GetMask()->GetValue(c), b->GetMask()->GetValue(c)) << "cell " << c;
  }
}

} // namespace
