// GridBuilder against a fresh build at every step of random sequences of
// changes (some trees re-refined, masks toggled, fields moved, values changed,
// slot maps, absent parts): node by node, the reused grid must equal the grid
// buildHyperTreeGrid builds from scratch, only the changed trees are rebuilt,
// and filters downstream see every change.
#include "canopy/GridBuilder.h"
#include "vtkCanopyAdaptiveSurface.h"

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

/// A forest whose trees the test changes one by one, as an AMR code does.
class ChangingForest
{
public:
  ChangingForest(int dimension, int trees, bool slots, std::uint64_t seed)
      : Dimension(dimension), Random(seed), UseSlots(slots)
  {
    Children = dimension == 3 ? 8 : 4;
    const int side = dimension == 3 ? 2 : 3;
    for (int a = 0; a < 3; ++a)
    {
      const int points = a < dimension ? side + 1 : 1;
      for (int i = 0; i < points; ++i)
        Coordinates[a].push_back(0.5 * i + 0.1 * a);
    }
    Trees.resize(static_cast<std::size_t>(trees));
    for (std::size_t t = 0; t < Trees.size(); ++t)
    {
      Trees[t].root = static_cast<std::int64_t>(t);
      refine(t);
    }
  }

  /// New random refinement (and mask) for tree t.
  void refine(std::size_t t)
  {
    std::uniform_real_distribution<double> unit(0, 1);
    Tree& tree = Trees[t];
    tree.refinement.assign(1, 0);
    std::vector<int> level{0};
    for (std::size_t n = 0; n < tree.refinement.size(); ++n)
    {
      if (level[n] < 3 && unit(Random) < 0.5)
      {
        tree.refinement[n] = 1;
        for (int c = 0; c < Children; ++c)
        {
          tree.refinement.push_back(0);
          level.push_back(level[n] + 1);
        }
      }
    }
    tree.masked.assign(tree.refinement.size(), 0);
    for (std::size_t n = 1; n < tree.masked.size(); ++n)
      tree.masked[n] = unit(Random) < 0.1;
  }

  void toggleMask(std::size_t t)
  {
    auto& masked = Trees[t].masked;
    masked[masked.size() / 2] ^= 1;
  }

  /// The description, slots depth-first per tree when asked, values fresh in new memory.
  ForestDescription describe(double valueOffset)
  {
    ForestDescription d;
    d.dimension = Dimension;
    d.maxLevels = 4;
    d.rootGrid = {Coordinates[0].data(), Coordinates[1].data(), Coordinates[2].data(),
                  Coordinates[0].size(), Coordinates[1].size(), Coordinates[2].size()};
    std::size_t total = 0;
    std::size_t leaves = 0;
    for (auto& tree : Trees)
    {
      tree.slots.resize(tree.refinement.size());
      for (std::size_t n = 0; n < tree.slots.size(); ++n)
      {
        // Reversed within the tree: a slot map that is not breadth-first.
        tree.slots[n] = static_cast<std::int64_t>(total + tree.slots.size() - 1 - n);
      }
      total += tree.refinement.size();
      for (auto r : tree.refinement)
        leaves += r == 0;
      d.trees.push_back({tree.root, tree.refinement.data(), tree.refinement.size(),
                         tree.masked.data(), UseSlots ? tree.slots.data() : nullptr, nullptr});
    }
    // New memory each time: the builder must wrap the fields anew.
    Values = std::make_unique<std::vector<double>>(total);
    LeafValues = std::make_unique<std::vector<double>>(leaves);
    for (std::size_t i = 0; i < total; ++i)
      (*Values)[i] = valueOffset + 0.5 * static_cast<double>(i);
    for (std::size_t i = 0; i < leaves; ++i)
      (*LeafValues)[i] = valueOffset - static_cast<double>(i);
    d.fields.push_back(FieldDescription::aos("value", Values->data(), total));
    d.fields.push_back(
        FieldDescription::aos("leafValue", LeafValues->data(), leaves, 1, Centering::LeavesOnly));
    return d;
  }

  std::size_t size() const { return Trees.size(); }

private:
  struct Tree
  {
    std::int64_t root;
    std::vector<std::uint8_t> refinement;
    std::vector<std::uint8_t> masked;
    std::vector<std::int64_t> slots;
  };
  int Dimension;
  int Children;
  std::mt19937_64 Random;
  bool UseSlots;
  std::array<std::vector<double>, 3> Coordinates;
  std::vector<Tree> Trees;
  std::unique_ptr<std::vector<double>> Values;
  std::unique_ptr<std::vector<double>> LeafValues;
};

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

} // namespace
} // namespace canopy::testing
