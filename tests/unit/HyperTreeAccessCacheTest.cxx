// HyperTreeAccessCache (adaptor/filters/HyperTreeAccessCache.h), through its own
// header: the access a filter keeps across executions. Its contract, checked
// here change by change: while the grid's topology is unchanged, get() returns
// the kept access itself (the same object), and that access is exactly what a
// new HyperTreeAccess of the grid as it is now would be; after any change to
// what the access reads it returns a new one, again equal to a new access. The
// oracle is a HyperTreeAccess made afresh from the grid, compared field by field
// and node by node. Each change is one that a kept access would show stale
// (checked before the cache is asked), so keeping it would be wrong, not merely
// wasteful. Grids stamped by Canopy's builder and grids Canopy did not build
// (deep copies: content keys) both.
#include "HyperTreeAccessCache.h"
#include "ChangingForest.h"

#include <canopy/GridBuilder.h>

#include <gtest/gtest.h>
#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedCursor.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <memory>
#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

using AccessPointer = std::shared_ptr<const HyperTreeAccess>;

/// What a new access of `grid` made now says, and what `kept` says, the same:
/// every grid-wide answer, every tree's fields and every node's leaf test and
/// global index. Stops at the first tree whose shape differs (its table may be
/// gone).
void expectSameAsFresh(const HyperTreeAccess& kept, vtkHyperTreeGrid* grid)
{
  const HyperTreeAccess fresh(grid, kept.hasIndexTables(), kept.hasMaskedDescendantFlags());
  EXPECT_EQ(kept.dimension(), fresh.dimension());
  EXPECT_EQ(kept.branchFactor(), fresh.branchFactor());
  EXPECT_EQ(kept.activeAxes(), fresh.activeAxes());
  EXPECT_EQ(kept.rootCells(), fresh.rootCells());
  EXPECT_EQ(kept.bounds(), fresh.bounds());
  for (int a = 0; a < 3; ++a)
  {
    EXPECT_EQ(kept.coordinates(a), fresh.coordinates(a)) << "axis " << a;
  }
  EXPECT_EQ(kept.numberOfCells(), fresh.numberOfCells());
  EXPECT_EQ(kept.hasMask(), fresh.hasMask());
  EXPECT_EQ(kept.hasAbsent(), fresh.hasAbsent());
  EXPECT_EQ(kept.hasTreesElsewhere(), fresh.hasTreesElsewhere());
  EXPECT_EQ(kept.maskBits(), fresh.maskBits());
  EXPECT_EQ(kept.maskSize(), fresh.maskSize());
  EXPECT_EQ(kept.ghostMarks(), fresh.ghostMarks());
  EXPECT_EQ(kept.ghostMarkCount(), fresh.ghostMarkCount());
  ASSERT_EQ(kept.trees().size(), fresh.trees().size());
  for (std::size_t t = 0; t < fresh.trees().size(); ++t)
  {
    const TreeAccess& a = kept.trees()[t];
    const TreeAccess& b = fresh.trees()[t];
    SCOPED_TRACE("tree " + std::to_string(b.treeIndex));
    ASSERT_EQ(a.treeIndex, b.treeIndex);
    ASSERT_EQ(a.tree, b.tree);
    ASSERT_EQ(a.numberOfVertices, b.numberOfVertices);
    ASSERT_EQ(a.elderChild, b.elderChild);
    ASSERT_EQ(a.elderChildSize, b.elderChildSize);
    EXPECT_EQ(a.implicitGlobalIndex, b.implicitGlobalIndex);
    EXPECT_EQ(a.globalIndexStart, b.globalIndexStart);
    EXPECT_EQ(a.origin, b.origin);
    EXPECT_EQ(a.size, b.size);
    EXPECT_EQ(a.rootIJK, b.rootIJK);
    EXPECT_EQ(a.maskedBelow, b.maskedBelow);
    EXPECT_EQ(a.absentBelow, b.absentBelow);
    EXPECT_EQ(a.visibleLeaves, b.visibleLeaves);
    EXPECT_EQ(a.globalTable, b.globalTable);
    EXPECT_EQ(a.stampBuilder, b.stampBuilder);
    EXPECT_EQ(a.stampTopology, b.stampTopology);
    EXPECT_EQ(a.stampMarks, b.stampMarks);
    for (vtkIdType n = 0; n < b.numberOfVertices; ++n)
    {
      ASSERT_EQ(a.isLeaf(n), b.isLeaf(n)) << "node " << n;
      ASSERT_EQ(a.globalIndex(n), b.globalIndex(n)) << "node " << n;
    }
  }
  for (vtkIdType c = 0; c < fresh.numberOfCells(); ++c)
  {
    ASSERT_EQ(kept.isMasked(c), fresh.isMasked(c)) << "cell " << c;
    ASSERT_EQ(kept.isAbsent(c), fresh.isAbsent(c)) << "cell " << c;
  }
}

/// A fresh access of `grid` differs from `before` in something it reads: the
/// premise that keeping `before` would serve stale answers.
bool freshDiffers(const HyperTreeAccess& before, vtkHyperTreeGrid* grid)
{
  const HyperTreeAccess fresh(grid, before.hasIndexTables(), before.hasMaskedDescendantFlags());
  if (fresh.trees().size() != before.trees().size() || fresh.bounds() != before.bounds() ||
      fresh.hasTreesElsewhere() != before.hasTreesElsewhere() ||
      fresh.hasAbsent() != before.hasAbsent() || fresh.maskBits() != before.maskBits() ||
      fresh.ghostMarks() != before.ghostMarks())
  {
    return true;
  }
  for (std::size_t t = 0; t < fresh.trees().size(); ++t)
  {
    const TreeAccess& a = before.trees()[t];
    const TreeAccess& b = fresh.trees()[t];
    if (a.tree != b.tree || a.numberOfVertices != b.numberOfVertices ||
        a.elderChild != b.elderChild || a.origin != b.origin || a.size != b.size ||
        a.maskedBelow != b.maskedBelow || a.absentBelow != b.absentBelow ||
        a.stampMarks != b.stampMarks || a.stampTopology != b.stampTopology)
    {
      return true;
    }
  }
  return false;
}

/// The cache, a changing forest and its builder, and get() checked.
class CacheFixture
{
protected:
  /// A forest of 8 trees with masked nodes, built by Canopy's builder.
  vtkSmartPointer<vtkHyperTreeGrid> buildGrid(int dimension)
  {
    Forest = std::make_unique<ChangingForest>(dimension, 8, false, 29);
    return Builder.build(Forest->describe(0));
  }

  /// get(), checked: the same object as `previous` exactly when `kept`, and in
  /// either case what a fresh access would be.
  AccessPointer expectGet(vtkHyperTreeGrid* grid, const AccessPointer& previous, bool kept,
                          bool indexTables = false, bool maskedDescendants = true)
  {
    AccessPointer access = Cache.get(grid, indexTables, maskedDescendants);
    EXPECT_EQ(Cache.lastWasKept(), kept);
    EXPECT_EQ(access == previous, kept) << (kept ? "a new access although nothing changed"
                                                 : "the kept access although the grid changed");
    expectSameAsFresh(*access, grid);
    return access;
  }

  std::unique_ptr<ChangingForest> Forest;
  GridBuilder Builder;
  HyperTreeAccessCache Cache;
};

/// How the grids of a test are made: stamped by Canopy's builder, or not
/// Canopy's (a deep copy: new trees and arrays, no stamp, content keys).
enum class Origin
{
  CanopyBuilder,
  DeepCopy
};

std::string originName(const ::testing::TestParamInfo<Origin>& info)
{
  return info.param == Origin::CanopyBuilder ? "CanopyBuilder" : "DeepCopy";
}

/// Changes made to a grid in place, through VTK's API.
class HyperTreeAccessCacheTest : public CacheFixture, public ::testing::TestWithParam<Origin>
{
protected:
  vtkSmartPointer<vtkHyperTreeGrid> makeGrid(int dimension = 3)
  {
    vtkSmartPointer<vtkHyperTreeGrid> built = buildGrid(dimension);
    if (GetParam() == Origin::CanopyBuilder)
    {
      return built;
    }
    auto copy = vtkSmartPointer<vtkHyperTreeGrid>::New();
    copy->DeepCopy(built);
    return copy;
  }
};

/// A simulation's steps through Canopy's builder, which returns the same grid
/// object while the root grid's shape and set of trees stay.
class HyperTreeAccessCacheBuilderSteps : public CacheFixture, public ::testing::Test
{
};

TEST_P(HyperTreeAccessCacheTest, KeptWhileNothingButTheGridsTimeChanges)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = makeGrid();
  AccessPointer first = expectGet(grid, nullptr, false);
  expectGet(grid, first, true);
  // A simulation's step: its field values changed, the grid is marked modified.
  grid->Modified();
  expectGet(grid, first, true);
  // The same coordinates in new array objects (a builder may hand new ones).
  vtkNew<vtkDoubleArray> x;
  x->DeepCopy(grid->GetXCoordinates());
  grid->SetXCoordinates(x);
  expectGet(grid, first, true);
}

TEST_P(HyperTreeAccessCacheTest, DroppedWhenATreeIsRefinedInPlace)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = makeGrid();
  grid->SetMask(nullptr); // VTK 9.2 refines only unmasked leaves
  const AccessPointer first = expectGet(grid, nullptr, false);
  // Through VTK's own cursor, without Modified(): the tree object stays.
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cursor;
  grid->InitializeNonOrientedCursor(cursor, 5, false);
  while (!cursor->IsLeaf())
  {
    cursor->ToChild(0);
  }
  cursor->SubdivideLeaf();
  ASSERT_TRUE(freshDiffers(*first, grid));
  expectGet(grid, first, false);
}

TEST_P(HyperTreeAccessCacheTest, DroppedWhenTheMaskIsModifiedOrReplaced)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = makeGrid();
  ASSERT_TRUE(grid->HasMask());
  AccessPointer access = expectGet(grid, nullptr, false);
  // A node with no masked child yet gets one: its masked-descendant flag (kept
  // with the access, 3D) changes.
  auto maskAChild = [&](vtkBitArray* mask)
  {
    for (const TreeAccess& tree : access->trees())
    {
      for (vtkIdType n = 0; n < tree.numberOfVertices; ++n)
      {
        if (!tree.isLeaf(n) && !tree.hasMaskedDescendant(n) &&
            !access->isMasked(tree.globalIndex(n)))
        {
          mask->SetValue(tree.globalIndex(tree.firstChild(n)), 1);
          return;
        }
      }
    }
    FAIL() << "no node without a masked descendant";
  };

  // Marked modified, bits unchanged: Modified() is the mask's word that it changed.
  grid->GetMask()->Modified();
  access = expectGet(grid, access, false);

  // A bit set in place, then Modified().
  maskAChild(grid->GetMask());
  grid->GetMask()->Modified();
  ASSERT_TRUE(freshDiffers(*access, grid));
  access = expectGet(grid, access, false);

  // Replaced by a new array with one more masked child.
  vtkNew<vtkBitArray> replacement;
  replacement->DeepCopy(grid->GetMask());
  maskAChild(replacement);
  grid->SetMask(replacement);
  ASSERT_TRUE(freshDiffers(*access, grid));
  access = expectGet(grid, access, false);

  // Removed.
  grid->SetMask(nullptr);
  access = expectGet(grid, access, false);
  EXPECT_FALSE(access->hasMask());
  expectGet(grid, access, true);
}

TEST_P(HyperTreeAccessCacheTest, DroppedWhenTheGhostMarksAreModifiedOrReplaced)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = makeGrid();
  // Absent cells are masked and marked DUPLICATECELL (another rank's part).
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  ghosts->SetNumberOfValues(grid->GetNumberOfCells());
  ghosts->FillValue(0);
  grid->GetCellData()->AddArray(ghosts);
  AccessPointer access = expectGet(grid, nullptr, false);
  EXPECT_FALSE(access->hasAbsent());

  // A leaf's cell below a refined root marked absent (and masked) in place,
  // then Modified().
  const TreeAccess* refined = nullptr;
  for (const TreeAccess& tree : access->trees())
  {
    refined = refined != nullptr || tree.isLeaf(0) ? refined : &tree;
  }
  ASSERT_NE(refined, nullptr) << "premise: a tree is refined";
  const TreeAccess& tree = *refined;
  vtkIdType leaf = 0;
  while (!tree.isLeaf(leaf))
  {
    leaf = tree.firstChild(leaf) + 1;
  }
  ghosts->SetValue(tree.globalIndex(leaf), vtkDataSetAttributes::DUPLICATECELL);
  grid->GetMask()->SetValue(tree.globalIndex(leaf), 1);
  ghosts->Modified();
  ASSERT_TRUE(freshDiffers(*access, grid));
  access = expectGet(grid, access, false);
  EXPECT_TRUE(access->hasAbsent());

  // Replaced by an array with no absent cell.
  vtkNew<vtkUnsignedCharArray> none;
  none->SetName(vtkDataSetAttributes::GhostArrayName());
  none->SetNumberOfValues(grid->GetNumberOfCells());
  none->FillValue(0);
  grid->GetCellData()->AddArray(none); // replaces the array of that name
  ASSERT_TRUE(freshDiffers(*access, grid));
  access = expectGet(grid, access, false);
  EXPECT_FALSE(access->hasAbsent());
}

TEST_P(HyperTreeAccessCacheTest, DroppedWhenTheCoordinatesMove)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = makeGrid();
  AccessPointer access = expectGet(grid, nullptr, false);
  // Moved in place, without Modified(): the values are the key.
  vtkDataArray* y = grid->GetYCoordinates();
  for (vtkIdType i = 0; i < y->GetNumberOfTuples(); ++i)
  {
    y->SetComponent(i, 0, y->GetComponent(i, 0) + 0.25);
  }
  ASSERT_TRUE(freshDiffers(*access, grid));
  access = expectGet(grid, access, false);
  // New arrays with other values.
  vtkNew<vtkDoubleArray> z;
  z->DeepCopy(grid->GetZCoordinates());
  z->SetComponent(z->GetNumberOfTuples() - 1, 0,
                  z->GetComponent(z->GetNumberOfTuples() - 1, 0) + 1);
  grid->SetZCoordinates(z);
  ASSERT_TRUE(freshDiffers(*access, grid));
  access = expectGet(grid, access, false);
  expectGet(grid, access, true);
}

TEST_P(HyperTreeAccessCacheTest, DroppedForAShallowCopyAndForAGridShallowCopiedInto)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = makeGrid();
  AccessPointer access = expectGet(grid, nullptr, false);
  // Another grid object sharing the trees' tables and the arrays: its access
  // points into it.
  vtkNew<vtkHyperTreeGrid> copy;
  copy->ShallowCopy(grid);
  std::size_t size = 0;
  ASSERT_EQ(copy->GetTree(3)->GetElderChildIndexArray(size),
            grid->GetTree(3)->GetElderChildIndexArray(size))
      << "premise: a shallow copy shares the trees' tables";
  access = expectGet(copy, access, false);
  access = expectGet(copy, access, true);
  // The same object given another grid's content: other trees.
  ChangingForest other(3, 8, false, 31);
  canopy::GridBuilder otherBuilder;
  vtkSmartPointer<vtkHyperTreeGrid> otherGrid = otherBuilder.build(other.describe(0));
  copy->ShallowCopy(otherGrid);
  ASSERT_TRUE(freshDiffers(*access, copy));
  access = expectGet(copy, access, false);
  // And back to the first grid: the cache holds one access, for one grid.
  expectGet(grid, access, false);
}

TEST_P(HyperTreeAccessCacheTest, DroppedWhenTheTreesElsewhereFlagChanges)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = makeGrid();
  AccessPointer access = expectGet(grid, nullptr, false);
  vtkNew<vtkIntArray> flag;
  flag->SetName(missingTreesElsewhereName());
  flag->InsertNextValue(1);
  grid->GetFieldData()->AddArray(flag);
  access = expectGet(grid, access, false);
  EXPECT_TRUE(access->hasTreesElsewhere());
  // Set to 0 in place (a grid whose missing trees are holes again).
  flag->SetValue(0, 0);
  access = expectGet(grid, access, false);
  EXPECT_FALSE(access->hasTreesElsewhere());
}

TEST_P(HyperTreeAccessCacheTest, AnAccessWithLessThanAskedForIsReplaced)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = makeGrid();
  // Masked-descendant flags (a pass over every node) only when asked for.
  AccessPointer access = expectGet(grid, nullptr, false, false, false);
  EXPECT_FALSE(access->hasMaskedDescendantFlags());
  access = expectGet(grid, access, false, false, true);
  EXPECT_TRUE(access->hasMaskedDescendantFlags());
  access = expectGet(grid, access, true, false, false); // more than asked for: kept
  // Index tables likewise.
  access = expectGet(grid, access, false, true, true);
  EXPECT_TRUE(access->hasIndexTables());
  expectGet(grid, access, true, false, true);
}

TEST_P(HyperTreeAccessCacheTest, ClearForgetsTheAccess)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = makeGrid();
  const AccessPointer first = expectGet(grid, nullptr, false);
  Cache.clear();
  expectGet(grid, first, false);
}

INSTANTIATE_TEST_SUITE_P(Grids, HyperTreeAccessCacheTest,
                         ::testing::Values(Origin::CanopyBuilder, Origin::DeepCopy), originName);

TEST_F(HyperTreeAccessCacheBuilderSteps, KeptAcrossBuildsThatChangeOnlyValues)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = buildGrid(3);
  const AccessPointer first = expectGet(grid, nullptr, false);
  vtkSmartPointer<vtkHyperTreeGrid> next = Builder.build(Forest->describe(1));
  ASSERT_EQ(next.Get(), grid.Get()) << "premise: the builder returns the same grid object";
  expectGet(next, first, true);
}

TEST_F(HyperTreeAccessCacheBuilderSteps, DroppedWhenATreeIsReRefinedByTheBuilder)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = buildGrid(3);
  const AccessPointer first = expectGet(grid, nullptr, false);
  const std::size_t before = Forest->numberOfNodes(3);
  do
  {
    Forest->refine(3);
  } while (Forest->numberOfNodes(3) == before);
  vtkSmartPointer<vtkHyperTreeGrid> next = Builder.build(Forest->describe(1));
  ASSERT_EQ(next.Get(), grid.Get());
  ASSERT_TRUE(freshDiffers(*first, next));
  const AccessPointer second = expectGet(next, first, false);
  expectGet(next, second, true);
}

TEST_F(HyperTreeAccessCacheBuilderSteps, DroppedWhenTheBuilderChangesAMask)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = buildGrid(3);
  const AccessPointer first = expectGet(grid, nullptr, false);
  for (std::size_t t = 0; t < Forest->size(); ++t)
  {
    Forest->toggleMask(t); // every tree: some node's masked-descendant flag changes
  }
  vtkSmartPointer<vtkHyperTreeGrid> next = Builder.build(Forest->describe(1));
  ASSERT_EQ(next.Get(), grid.Get());
  ASSERT_TRUE(freshDiffers(*first, next));
  expectGet(next, first, false);
}

TEST_F(HyperTreeAccessCacheBuilderSteps, DroppedWhenTheBuilderMovesTheMesh)
{
  vtkSmartPointer<vtkHyperTreeGrid> grid = buildGrid(2);
  const AccessPointer first = expectGet(grid, nullptr, false);
  Forest->shiftCoordinates(0.125);
  vtkSmartPointer<vtkHyperTreeGrid> next = Builder.build(Forest->describe(1));
  ASSERT_EQ(next.Get(), grid.Get());
  ASSERT_TRUE(freshDiffers(*first, next));
  expectGet(next, first, false);
}

/// A 2D grid whose trees carry explicit global indices (each tree's cells
/// numbered by a table, not from a start), as some readers make them.
vtkSmartPointer<vtkHyperTreeGrid> explicitIndexGrid()
{
  auto grid = vtkSmartPointer<vtkHyperTreeGrid>::New();
  grid->SetBranchFactor(2);
  grid->SetDimensions(3, 2, 1);
  for (int a = 0; a < 3; ++a)
  {
    vtkNew<vtkDoubleArray> axis;
    const int points = a == 0 ? 3 : a == 1 ? 2 : 1;
    for (int i = 0; i < points; ++i)
    {
      axis->InsertNextValue(i);
    }
    a == 0   ? grid->SetXCoordinates(axis)
    : a == 1 ? grid->SetYCoordinates(axis)
             : grid->SetZCoordinates(axis);
  }
  // Numbered backwards from 9: tree 0 holds cells 9 .. 5, tree 1 cells 4 .. 0.
  vtkIdType next = 9;
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cursor;
  for (vtkIdType t = 0; t < 2; ++t)
  {
    grid->InitializeNonOrientedCursor(cursor, t, true);
    cursor->SetGlobalIndexFromLocal(next--);
    cursor->SubdivideLeaf();
    for (unsigned char c = 0; c < 4; ++c)
    {
      cursor->ToChild(c);
      cursor->SetGlobalIndexFromLocal(next--);
      cursor->ToParent();
    }
  }
  return grid;
}

TEST(HyperTreeAccessCacheExplicitIndices, KeyedOnTheGridsTimeAsWell)
{
  // Their index tables are not compared: any Modified() of the grid drops the
  // access, and the tables of the new one are the grid's.
  vtkSmartPointer<vtkHyperTreeGrid> grid = explicitIndexGrid();
  HyperTreeAccessCache cache;
  const AccessPointer first = cache.get(grid, true);
  ASSERT_FALSE(first->trees()[0].implicitGlobalIndex) << "premise: explicit indices";
  EXPECT_EQ(first->trees()[0].globalIndex(0), 9);
  EXPECT_EQ(first->trees()[1].globalIndex(4), 0);
  expectSameAsFresh(*first, grid);
  EXPECT_EQ(cache.get(grid, true), first);
  EXPECT_TRUE(cache.lastWasKept());
  // Tree 1's first and last children swap their numbers in place: only the
  // grid's time tells.
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cursor;
  grid->InitializeNonOrientedCursor(cursor, 1, false);
  cursor->ToChild(0);
  cursor->SetGlobalIndexFromLocal(0);
  cursor->ToParent();
  cursor->ToChild(3);
  cursor->SetGlobalIndexFromLocal(3);
  grid->Modified();
  const AccessPointer second = cache.get(grid, true);
  EXPECT_FALSE(cache.lastWasKept());
  EXPECT_NE(second, first);
  EXPECT_EQ(second->trees()[1].globalIndex(1), 0);
  EXPECT_EQ(second->trees()[1].globalIndex(4), 3);
  expectSameAsFresh(*second, grid);
}

} // namespace
} // namespace canopy::testing
