// 2D and 3D, branch factor 2 and 3, AoS / SoA / strided vector fields, breadth-
// first or the simulation's own (depth-first) storage order, grids in every
// axis-aligned plane at offset origins: every node of the built grid must have
// the simulation's topology, geometry and values.
#include "HtgWalk.h"
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>

#include <gtest/gtest.h>
#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTree.h>

#include <array>
#include <ostream>
#include <tuple>

namespace canopy::testing
{
namespace
{

struct LayoutCase
{
  int dimension;
  int branchFactor;
  int flatAxis;
  StorageOrder order;
  Layout layout;
};

std::ostream& operator<<(std::ostream& out, const LayoutCase& c)
{
  static const char* layouts[] = {"AoS", "SoA", "Strided", "Indirect"};
  return out << c.dimension << "D_bf" << c.branchFactor << "_flat" << c.flatAxis << "_"
             << (c.order == StorageOrder::BreadthFirst ? "breadthFirst" : "depthFirst") << "_"
             << layouts[static_cast<int>(c.layout)];
}

/// The value the simulation stores for component c of the node in `slot`.
double valueAt(std::int64_t slot, int c)
{
  return 1000.0 * static_cast<double>(slot) + c + 0.25;
}

/// The simulation's storage of a 3-component vector in the requested layout.
struct VectorStorage
{
  std::vector<double> aos;
  std::array<std::vector<double>, 3> soa;
  struct Record
  {
    int tag;
    double vector[3];
    float extra;
  };
  std::vector<Record> records;
  std::vector<const void*> addresses;

  FieldDescription describe(Layout layout, std::size_t n)
  {
    switch (layout)
    {
    case Layout::AoS:
      aos.resize(3 * n);
      for (std::size_t s = 0; s < n; ++s)
        for (int c = 0; c < 3; ++c)
          aos[3 * s + c] = valueAt(static_cast<std::int64_t>(s), c);
      return FieldDescription::aos("vector", aos.data(), n, 3);
    case Layout::SoA:
      for (int c = 0; c < 3; ++c)
      {
        soa[c].resize(n);
        for (std::size_t s = 0; s < n; ++s)
          soa[c][s] = valueAt(static_cast<std::int64_t>(s), c);
      }
      return FieldDescription::soa<double>("vector", {soa[0].data(), soa[1].data(), soa[2].data()},
                                           n);
    case Layout::Strided:
      records.resize(n);
      for (std::size_t s = 0; s < n; ++s)
        for (int c = 0; c < 3; ++c)
          records[s].vector[c] = valueAt(static_cast<std::int64_t>(s), c);
      return FieldDescription::strided("vector", &records[0].vector[0], sizeof(Record), n, 3);
    case Layout::Indirect:
      // Records scattered in memory (reversed here), found through an address table.
      records.resize(n);
      addresses.resize(n);
      for (std::size_t s = 0; s < n; ++s)
      {
        Record& record = records[n - 1 - s];
        for (int c = 0; c < 3; ++c)
          record.vector[c] = valueAt(static_cast<std::int64_t>(s), c);
        addresses[s] = &record.vector[0];
      }
      return FieldDescription::indirect<double>("vector", addresses.data(), n, 3);
    case Layout::Blocks: // BlockForestTest's
      break;
    }
    return {};
  }
};

/// Bounds of a node from its root cell and its path of child positions.
std::array<double, 6> expectedBounds(const RandomForest& forest, const LayoutCase& lc,
                                     std::int64_t rootIndex, std::size_t tree, std::size_t node)
{
  const auto& coords = forest.coordinates();
  std::array<std::size_t, 3> cells;
  for (int a = 0; a < 3; ++a)
  {
    cells[a] = coords[a].size() > 1 ? coords[a].size() - 1 : 1;
  }
  std::array<std::size_t, 3> ijk{
      {rootIndex % cells[0], (rootIndex / cells[0]) % cells[1], rootIndex / (cells[0] * cells[1])}};
  std::array<double, 6> b;
  for (int a = 0; a < 3; ++a)
  {
    b[2 * a] = coords[a][ijk[a]];
    b[2 * a + 1] = coords[a].size() > 1 ? coords[a][ijk[a] + 1] : coords[a][0];
  }
  // Path from root to node.
  std::vector<int> path;
  const auto& nodes = forest.nodes()[tree];
  for (std::int64_t n = static_cast<std::int64_t>(node); nodes[n].parent >= 0; n = nodes[n].parent)
  {
    path.insert(path.begin(), nodes[n].childIndex);
  }
  for (int child : path)
  {
    for (int a = 0; a < 3; ++a)
    {
      if (lc.dimension == 2 && a == lc.flatAxis)
      {
        continue;
      }
      const int position = child % lc.branchFactor;
      child /= lc.branchFactor;
      const double size = (b[2 * a + 1] - b[2 * a]) / lc.branchFactor;
      const double low = b[2 * a] + position * size;
      b[2 * a + 1] = position == lc.branchFactor - 1 ? b[2 * a + 1] : low + size;
      b[2 * a] = low;
    }
  }
  return b;
}

class Layouts : public ::testing::TestWithParam<LayoutCase>
{
};

TEST_P(Layouts, EveryNodeMatchesTheSimulation)
{
  const LayoutCase lc = GetParam();
  RandomForestOptions o;
  o.dimension = lc.dimension;
  o.branchFactor = lc.branchFactor;
  o.flatAxis = lc.flatAxis;
  o.rootCells = {{3, 3, 3}};
  o.maxLevels = lc.branchFactor == 2 ? 5 : 4;
  o.refineProbability = 0.45;
  o.maskProbability = 0.15;
  o.order = lc.order;
  o.origin = {{-1e3, 250.5, 17.0}};
  o.skipEveryOtherRoot = true; // not every root cell carries a tree
  o.seed = 1234 + lc.dimension * 10 + lc.branchFactor;
  RandomForest forest(o);
  ASSERT_GT(forest.numberOfNodes(), 20u) << "the random forest should refine";

  VectorStorage storage;
  auto& d = forest.description();
  d.fields.push_back(storage.describe(lc.layout, forest.numberOfNodes()));
  auto htg = buildHyperTreeGrid(d);

  ASSERT_EQ(htg->GetDimension(), static_cast<unsigned int>(lc.dimension));
  ASSERT_EQ(htg->GetBranchFactor(), static_cast<unsigned int>(lc.branchFactor));
  ASSERT_EQ(htg->GetNumberOfCells(), static_cast<vtkIdType>(forest.numberOfNodes()));
  vtkDataArray* vector = htg->GetCellData()->GetArray("vector");
  ASSERT_NE(vector, nullptr);
  ASSERT_EQ(vector->GetNumberOfComponents(), 3);

  std::size_t visited = 0;
  std::size_t leaves = 0;
  for (std::size_t t = 0; t < d.trees.size(); ++t)
  {
    const std::int64_t root = d.trees[t].rootIndex;
    ASSERT_NE(htg->GetTree(root), nullptr);
    const auto& nodes = forest.nodes()[t];
    const auto& refinement = forest.refinement()[t];
    // Below masked nodes cursors cannot go: check the tree's own storage there.
    // Breadth-first construction gives local index = breadth-first node number.
    vtkHyperTree* tree = htg->GetTree(root);
    ASSERT_EQ(tree->GetNumberOfVertices(), static_cast<vtkIdType>(nodes.size()));
    std::size_t nextChild = 1;
    for (std::size_t n = 0; n < nodes.size(); ++n)
    {
      const auto local = static_cast<vtkIdType>(n);
      ASSERT_EQ(tree->IsLeaf(local), refinement[n] == 0) << "tree " << t << " node " << n;
      // Cells are breadth-first whatever the storage order: no per-node VTK table.
      ASSERT_EQ(tree->GetGlobalIndexFromLocal(local), forest.cellOf(t, n));
      if (refinement[n])
      {
        ASSERT_EQ(tree->GetElderChildIndex(static_cast<unsigned int>(n)), nextChild);
        nextChild += forest.childrenPerNode();
      }
      ASSERT_EQ(htg->GetMask()->GetValue(forest.cellOf(t, n)), forest.masked()[t][n]);
    }
    forEachNode(htg, root, refinement, forest.childrenPerNode(),
                [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor, std::size_t n)
                {
                  ++visited;
                  ASSERT_LT(n, nodes.size());
                  EXPECT_EQ(cursor->IsLeaf(), refinement[n] == 0);
                  leaves += cursor->IsLeaf();
                  EXPECT_EQ(cursor->GetLevel(), static_cast<unsigned int>(nodes[n].level));
                  EXPECT_EQ(cursor->IsMasked(), forest.masked()[t][n] != 0);
                  const vtkIdType global = cursor->GetGlobalNodeIndex();
                  ASSERT_EQ(global, forest.cellOf(t, n)) << "tree " << t << " node " << n;
                  // The value at the cell is the simulation's, from the node's slot.
                  for (int c = 0; c < 3; ++c)
                  {
                    ASSERT_EQ(vector->GetComponent(global, c), valueAt(nodes[n].slot, c));
                  }
                  double bounds[6];
                  cursor->GetBounds(bounds);
                  const auto expected = expectedBounds(forest, lc, root, t, n);
                  for (int i = 0; i < 6; ++i)
                  {
                    ASSERT_NEAR(bounds[i], expected[i], 1e-9 * (1 + std::abs(expected[i])))
                        << "bound " << i << " of tree " << t << " node " << n;
                  }
                });
  }
  // The cursor walk reaches exactly the nodes with no masked ancestor.
  std::size_t reachable = 0;
  std::size_t reachableLeaves = 0;
  for (std::size_t t = 0; t < d.trees.size(); ++t)
  {
    const auto& nodes = forest.nodes()[t];
    for (std::size_t n = 0; n < nodes.size(); ++n)
    {
      bool hidden = false;
      for (std::int64_t a = nodes[n].parent; a >= 0; a = nodes[a].parent)
      {
        hidden = hidden || forest.masked()[t][a] != 0;
      }
      reachable += !hidden;
      reachableLeaves += !hidden && forest.refinement()[t][n] == 0;
    }
  }
  EXPECT_EQ(visited, reachable);
  EXPECT_EQ(leaves, reachableLeaves);
}

std::vector<LayoutCase> allCases()
{
  std::vector<LayoutCase> cases;
  for (int dimension : {2, 3})
    for (int bf : {2, 3})
      for (StorageOrder order : {StorageOrder::BreadthFirst, StorageOrder::DepthFirst})
        for (Layout layout : {Layout::AoS, Layout::SoA, Layout::Strided, Layout::Indirect})
          cases.push_back({dimension, bf, 2, order, layout});
  // 2D grids lying in the XZ and YZ planes.
  for (int flat : {0, 1})
    for (int bf : {2, 3})
      cases.push_back({2, bf, flat, StorageOrder::DepthFirst, Layout::Strided});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(AllLayouts, Layouts, ::testing::ValuesIn(allCases()),
                         [](const ::testing::TestParamInfo<LayoutCase>& info)
                         {
                           std::ostringstream name;
                           name << info.param;
                           return name.str();
                         });

} // namespace
} // namespace canopy::testing
