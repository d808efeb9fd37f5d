// Leaves-only fields: leaf values are read in place, coarse values are volume
// averages of the unmasked children (all children when every child is masked),
// computed bottom-up. Expected values below are worked out by hand.
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>

#include <array>
#include <cmath>

namespace canopy::testing
{
namespace
{

// One 2D binary tree on a 1 x 1 root grid:
//   node 0 (root) refined into nodes 1..4; node 2 refined into nodes 5..8.
// Leaves breadth-first: 1, 3, 4, 5, 6, 7, 8.
struct TwoLevelTree
{
  std::array<double, 2> x{{0.0, 2.0}};
  std::array<double, 2> y{{-1.0, 1.0}};
  std::array<double, 1> z{{0.0}};
  std::array<std::uint8_t, 9> refinement{{1, 0, 1, 0, 0, 0, 0, 0, 0}};
  std::array<std::uint8_t, 9> masked{{0, 0, 0, 0, 0, 0, 0, 0, 0}};
  // Depth-first storage: root, 1, 2, 5, 6, 7, 8, 3, 4.
  std::array<std::int64_t, 9> depthFirstSlots{{0, 1, 2, 7, 8, 3, 4, 5, 6}};

  ForestDescription describe(bool withMask, bool depthFirst)
  {
    ForestDescription d;
    d.dimension = 2;
    d.branchFactor = 2;
    d.maxLevels = 3;
    d.rootGrid = {x.data(), y.data(), z.data(), 2, 2, 1};
    TreeDescription tree;
    tree.rootIndex = 0;
    tree.refinement = refinement.data();
    tree.numberOfNodes = refinement.size();
    tree.masked = withMask ? masked.data() : nullptr;
    tree.storageSlots = depthFirst ? depthFirstSlots.data() : nullptr;
    d.trees.push_back(tree);
    return d;
  }
};

TEST(LeavesOnly, CoarseValuesAreVolumeAveragesBreadthFirst)
{
  TwoLevelTree tree;
  ForestDescription d = tree.describe(false, false);
  // Leaves in slot order (breadth-first): nodes 1, 3, 4, 5, 6, 7, 8.
  const std::vector<double> energy{1, 2, 3, 10, 20, 30, 40};
  d.fields.push_back(
      FieldDescription::aos("energy", energy.data(), energy.size(), 1, Centering::LeavesOnly));
  auto htg = buildHyperTreeGrid(d);
  vtkDataArray* e = htg->GetCellData()->GetArray("energy");
  ASSERT_NE(e, nullptr);
  ASSERT_EQ(e->GetNumberOfTuples(), 9);
  // Global index = breadth-first node number here.
  EXPECT_EQ(e->GetTuple1(2), 25.0);                   // (10 + 20 + 30 + 40) / 4
  EXPECT_EQ(e->GetTuple1(0), (1.0 + 25 + 2 + 3) / 4); // 7.75
  EXPECT_EQ(e->GetTuple1(1), 1.0);
  EXPECT_EQ(e->GetTuple1(3), 2.0);
  EXPECT_EQ(e->GetTuple1(4), 3.0);
  EXPECT_EQ(e->GetTuple1(8), 40.0);
}

TEST(LeavesOnly, CoarseValuesSkipMaskedChildrenInDepthFirstStorage)
{
  TwoLevelTree tree;
  tree.masked[6] = 1; // leaf with value 20
  tree.masked[3] = 1; // leaf with value 2
  ForestDescription d = tree.describe(true, true);
  // Leaves in slot order (depth-first): nodes 1, 5, 6, 7, 8, 3, 4.
  const std::vector<double> energy{1, 10, 20, 30, 40, 2, 3};
  d.fields.push_back(
      FieldDescription::aos("energy", energy.data(), energy.size(), 1, Centering::LeavesOnly));
  auto htg = buildHyperTreeGrid(d);
  vtkDataArray* e = htg->GetCellData()->GetArray("energy");
  const double node2 = (10.0 + 30 + 40) / 3;
  // Cells are breadth-first (cell n = node n); values come from the slots.
  EXPECT_DOUBLE_EQ(e->GetTuple1(2), node2);
  EXPECT_DOUBLE_EQ(e->GetTuple1(0), (1.0 + node2 + 3) / 3); // node 3 (value 2) masked
  EXPECT_EQ(e->GetTuple1(5), 10.0);                         // node 5, in slot 3
  EXPECT_EQ(e->GetTuple1(3), 2.0);                          // node 3, in slot 7: still readable
  // The leaf values are still read in place.
  auto& mutableEnergy = const_cast<std::vector<double>&>(energy);
  mutableEnergy[6] = -5.0; // node 4
  EXPECT_EQ(e->GetTuple1(4), -5.0);
}

TEST(LeavesOnly, AllChildrenMaskedFallsBackToEveryChild)
{
  TwoLevelTree tree;
  for (int n = 5; n <= 8; ++n)
  {
    tree.masked[n] = 1; // every child of node 2
  }
  tree.masked[3] = 1; // a leaf child of the root (value 2)
  ForestDescription d = tree.describe(true, false);
  const std::vector<float> energy{1, 2, 3, 10, 20, 30, 40};
  d.fields.push_back(
      FieldDescription::aos("energy", energy.data(), energy.size(), 1, Centering::LeavesOnly));
  auto htg = buildHyperTreeGrid(d);
  vtkDataArray* e = htg->GetCellData()->GetArray("energy");
  EXPECT_EQ(e->GetDataType(), VTK_FLOAT);
  // Node 2: all children masked, so all of them are used.
  EXPECT_EQ(e->GetTuple1(2), 25.0f);
  // Root: node 3 (masked) is left out: (1 + 25 + 3) / 3; ignoring masks would give 7.75.
  EXPECT_FLOAT_EQ(static_cast<float>(e->GetTuple1(0)), (1.0f + 25.0f + 3.0f) / 3.0f);
}

TEST(LeavesOnly, VectorFieldInRecordsIsAveragedPerComponent)
{
  TwoLevelTree tree;
  ForestDescription d = tree.describe(false, false);
  struct Leaf
  {
    double u;
    double v;
    int id;
  };
  const std::vector<Leaf> leaves{{1, -1, 0},   {2, -2, 0},   {3, -3, 0},  {10, -10, 0},
                                 {20, -20, 0}, {30, -30, 0}, {40, -40, 0}};
  d.fields.push_back(FieldDescription::strided("uv", &leaves[0].u, sizeof(Leaf), leaves.size(), 2,
                                               Centering::LeavesOnly));
  auto htg = buildHyperTreeGrid(d);
  vtkDataArray* uv = htg->GetCellData()->GetArray("uv");
  ASSERT_EQ(uv->GetNumberOfComponents(), 2);
  EXPECT_EQ(uv->GetComponent(2, 0), 25.0);
  EXPECT_EQ(uv->GetComponent(2, 1), -25.0);
  EXPECT_EQ(uv->GetComponent(0, 0), 7.75);
  EXPECT_EQ(uv->GetComponent(0, 1), -7.75);
  EXPECT_EQ(uv->GetComponent(5, 1), -10.0);
}

TEST(LeavesOnly, ThreeDimensionalTernaryAverageMatchesBruteForce)
{
  // Root refined into 27 children, child 13 (centre) refined again: the root's
  // value must equal the volume-weighted mean over all leaves.
  std::array<double, 2> x{{0, 3}}, y{{0, 3}}, z{{0, 3}};
  std::vector<std::uint8_t> refinement(1 + 27 + 27, 0);
  refinement[0] = 1;
  refinement[1 + 13] = 1;
  ForestDescription d;
  d.dimension = 3;
  d.branchFactor = 3;
  d.maxLevels = 3;
  d.rootGrid = {x.data(), y.data(), z.data(), 2, 2, 2};
  TreeDescription t;
  t.refinement = refinement.data();
  t.numberOfNodes = refinement.size();
  d.trees.push_back(t);
  std::vector<double> values;
  double weighted = 0;
  double fineSum = 0;
  for (int k = 0; k < 26 + 27; ++k)
  {
    const double v = std::sin(0.37 * k) * 100;
    values.push_back(v);
    // The first 26 leaves are level-1 cells (volume 1/27), the rest level 2 (1/729).
    weighted += v * (k < 26 ? 1.0 / 27 : 1.0 / 729);
    fineSum += k < 26 ? 0 : v;
  }
  d.fields.push_back(
      FieldDescription::aos("f", values.data(), values.size(), 1, Centering::LeavesOnly));
  auto htg = buildHyperTreeGrid(d);
  vtkDataArray* f = htg->GetCellData()->GetArray("f");
  EXPECT_NEAR(f->GetTuple1(0), weighted, 1e-12 * 100);
  EXPECT_NEAR(f->GetTuple1(14), fineSum / 27, 1e-12 * 100);
}

TEST(LeavesOnly, LineOfTreesAveragesItsSegments)
{
  // A 1D forest along y: tree 0 binary, root -> nodes 1, 2; node 2 -> nodes 3, 4.
  // Tree 1 a single leaf. Leaves in slot order: 1, 3, 4, then tree 1's root.
  const std::array<double, 1> x{{5.0}}, z{{-1.0}};
  const std::array<double, 3> y{{0.0, 1.0, 4.0}};
  const std::array<std::uint8_t, 5> refinement{{1, 0, 1, 0, 0}};
  const std::array<std::uint8_t, 5> masked{{0, 0, 0, 1, 0}};
  const std::array<std::uint8_t, 1> leaf{{0}};
  for (bool withMask : {false, true})
  {
    ForestDescription d;
    d.dimension = 1;
    d.branchFactor = 2;
    d.maxLevels = 3;
    d.rootGrid = {x.data(), y.data(), z.data(), 1, 3, 1};
    d.trees.push_back(
        {0, refinement.data(), refinement.size(), withMask ? masked.data() : nullptr, nullptr});
    d.trees.push_back({1, leaf.data(), leaf.size(), nullptr, nullptr});
    const std::vector<double> energy{1, 10, 20, 7};
    d.fields.push_back(
        FieldDescription::aos("energy", energy.data(), energy.size(), 1, Centering::LeavesOnly));
    auto htg = buildHyperTreeGrid(d);
    ASSERT_EQ(htg->GetDimension(), 1u);
    vtkDataArray* e = htg->GetCellData()->GetArray("energy");
    ASSERT_NE(e, nullptr);
    // Node 2 averages its two children (node 3 masked: node 4 alone); the root
    // averages nodes 1 and 2; tree 1's leaf reads its own value.
    const double node2 = withMask ? 20.0 : 15.0;
    EXPECT_EQ(e->GetTuple1(2), node2);
    EXPECT_EQ(e->GetTuple1(0), (1.0 + node2) / 2);
    EXPECT_EQ(e->GetTuple1(3), 10.0);
    EXPECT_EQ(e->GetTuple1(5), 7.0);
  }
}

TEST(LeavesOnly, SoAVectorOverManyTreesMatchesBruteForceVolumeAverages)
{
  for (StorageOrder order : {StorageOrder::BreadthFirst, StorageOrder::DepthFirst})
  {
    RandomForestOptions o;
    o.dimension = 3;
    o.branchFactor = 2;
    o.rootCells = {{3, 2, 2}};
    o.maxLevels = 4;
    o.maskProbability = 0.2;
    o.order = order;
    o.seed = 77;
    RandomForest forest(o);
    // Leaves in slot order; two components.
    std::vector<std::int64_t> leafOfSlot(forest.numberOfNodes(), -1);
    for (std::size_t t = 0; t < forest.nodes().size(); ++t)
      for (std::size_t n = 0; n < forest.nodes()[t].size(); ++n)
        if (!forest.refinement()[t][n])
          leafOfSlot[static_cast<std::size_t>(forest.nodes()[t][n].slot)] = 0;
    std::int64_t next = 0;
    for (auto& l : leafOfSlot)
      if (l == 0)
        l = next++;
    std::vector<double> a(static_cast<std::size_t>(next)), b(static_cast<std::size_t>(next));
    for (std::size_t i = 0; i < a.size(); ++i)
    {
      a[i] = std::sin(1.7 * i);
      b[i] = std::cos(0.3 * i) * 10;
    }
    auto& d = forest.description();
    d.fields.push_back(
        FieldDescription::soa<double>("ab", {a.data(), b.data()}, a.size(), Centering::LeavesOnly));
    auto htg = buildHyperTreeGrid(d);
    vtkDataArray* ab = htg->GetCellData()->GetArray("ab");
    // Brute force, recursively from each root: the mean of the (unmasked, or all
    // if all masked) children's values.
    for (std::size_t t = 0; t < forest.nodes().size(); ++t)
    {
      const auto& nodes = forest.nodes()[t];
      const auto& masked = forest.masked()[t];
      std::vector<std::vector<std::size_t>> children(nodes.size());
      for (std::size_t n = 1; n < nodes.size(); ++n)
        children[static_cast<std::size_t>(nodes[n].parent)].push_back(n);
      auto value = [&](auto& self, std::size_t n, int c) -> double
      {
        if (children[n].empty())
        {
          const auto leaf = leafOfSlot[static_cast<std::size_t>(nodes[n].slot)];
          return c == 0 ? a[static_cast<std::size_t>(leaf)] : b[static_cast<std::size_t>(leaf)];
        }
        double sum = 0;
        int used = 0;
        for (std::size_t k : children[n])
          if (!masked[k])
          {
            sum += self(self, k, c);
            ++used;
          }
        if (used == 0)
          for (std::size_t k : children[n])
          {
            sum += self(self, k, c);
            ++used;
          }
        return sum / used;
      };
      for (std::size_t n = 0; n < nodes.size(); ++n)
        for (int c = 0; c < 2; ++c)
          ASSERT_NEAR(ab->GetComponent(forest.cellOf(t, n), c), value(value, n, c), 1e-12)
              << "tree " << t << " node " << n;
    }
  }
}

} // namespace
} // namespace canopy::testing
