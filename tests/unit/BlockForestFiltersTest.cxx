// Canopy's filters on block forests give what they give on the same forest
// described cell by cell (its blocks expanded into ordinary subtrees, values as a
// leaves-only field: the path the filter tests check against brute force): the
// same grid cell for cell, the same adaptive surface and slices with level of
// detail, the same selections; split between ranks at block boundaries, the
// ranks' slices add up to the whole's.
#include "BlockForest.h"
#include "ErrorMessages.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include <cmath>

namespace canopy::testing
{
namespace
{

/// `forest` described node by node: every block a full subtree of its levels.
struct ExpandedTwin
{
  std::vector<std::vector<std::uint8_t>> refinement, absent, masked;
  std::vector<double> leaves; ///< present leaves, breadth-first tree by tree, AoS
  ForestDescription description;

  explicit ExpandedTwin(const BlockForest& forest)
  {
    const ForestDescription& d = forest.description();
    const int bf = d.branchFactor;
    std::size_t children = 1;
    for (int a = 0; a < d.dimension; ++a)
    {
      children *= static_cast<std::size_t>(bf);
    }
    const int n = forest.options().cellsPerSide;
    const int nc = forest.options().components;
    std::map<std::pair<std::size_t, std::size_t>, std::size_t> blockOf;
    for (std::size_t b = 0; b < forest.blocks().size(); ++b)
    {
      blockOf[{forest.blocks()[b].tree, forest.blocks()[b].node}] = b;
    }
    struct Node
    {
      long long described; ///< node of the description, or -1 inside a block
      long long block;
      std::array<int, 3> position; ///< inside the block
      int width;                   ///< cells of the block across this node
    };
    for (std::size_t t = 0; t < d.trees.size(); ++t)
    {
      const TreeDescription& tree = d.trees[t];
      std::vector<std::size_t> firstChild(tree.numberOfNodes, 0);
      for (std::size_t i = 0, next = 1; i < tree.numberOfNodes; ++i)
      {
        if (tree.refinement[i])
        {
          firstChild[i] = next;
          next += children;
        }
      }
      std::vector<std::uint8_t> r, ab, m;
      std::vector<Node> level{{0, -1, {{0, 0, 0}}, 0}};
      while (!level.empty())
      {
        std::vector<Node> below;
        for (const Node& node : level)
        {
          if (node.described >= 0)
          {
            const auto i = static_cast<std::size_t>(node.described);
            const bool isAbsent = tree.absent && tree.absent[i];
            const bool isBlock = !tree.refinement[i] && !isAbsent;
            r.push_back(!isAbsent);
            ab.push_back(isAbsent);
            m.push_back(tree.masked ? tree.masked[i] : 0);
            for (std::size_t c = 0; tree.refinement[i] && c < children; ++c)
            {
              below.push_back({static_cast<long long>(firstChild[i] + c), -1, {{0, 0, 0}}, 0});
            }
            if (isBlock)
            {
              for (std::size_t c = 0; c < children; ++c)
              {
                Node child{-1, static_cast<long long>(blockOf.at({t, i})), {{0, 0, 0}}, n / bf};
                std::size_t digit = c;
                for (int a = 0; a < d.dimension; ++a)
                {
                  child.position[static_cast<std::size_t>(a)] = static_cast<int>(digit % bf);
                  digit /= static_cast<std::size_t>(bf);
                }
                below.push_back(child);
              }
            }
            continue;
          }
          const bool refined = node.width > 1;
          r.push_back(refined);
          ab.push_back(0);
          m.push_back(0);
          if (!refined)
          {
            for (int c = 0; c < nc; ++c)
            {
              leaves.push_back(
                  forest.stored(static_cast<std::size_t>(node.block), node.position, c));
            }
            continue;
          }
          for (std::size_t c = 0; c < children; ++c)
          {
            Node child{-1, node.block, {{0, 0, 0}}, node.width / bf};
            std::size_t digit = c;
            for (int a = 0; a < d.dimension; ++a)
            {
              const auto axis = static_cast<std::size_t>(a);
              child.position[axis] = node.position[axis] * bf + static_cast<int>(digit % bf);
              digit /= static_cast<std::size_t>(bf);
            }
            below.push_back(child);
          }
        }
        level = std::move(below);
      }
      refinement.push_back(std::move(r));
      absent.push_back(std::move(ab));
      masked.push_back(std::move(m));
    }
    description.dimension = d.dimension;
    description.branchFactor = d.branchFactor;
    description.maxLevels = d.maxLevels;
    description.rootGrid = d.rootGrid;
    description.missingTreesAreElsewhere = d.missingTreesAreElsewhere;
    for (std::size_t t = 0; t < d.trees.size(); ++t)
    {
      TreeDescription tree;
      tree.rootIndex = d.trees[t].rootIndex;
      tree.refinement = refinement[t].data();
      tree.numberOfNodes = refinement[t].size();
      tree.absent = d.trees[t].absent ? absent[t].data() : nullptr;
      tree.masked = d.trees[t].masked ? masked[t].data() : nullptr;
      description.trees.push_back(tree);
    }
    description.fields.push_back(FieldDescription::aos("f", leaves.data(),
                                                       leaves.size() / static_cast<std::size_t>(nc),
                                                       nc, Centering::LeavesOnly));
  }
};

BlockForestOptions threeDimensional(int rank, int ranks, double maskProbability)
{
  BlockForestOptions o;
  o.shape.dimension = 3;
  o.shape.rootCells = {{2, 2, 1}};
  o.shape.maxLevels = 3;
  o.shape.refineProbability = 0.5;
  o.shape.maskProbability = maskProbability;
  o.shape.seed = 9;
  o.cellsPerSide = 8;
  o.ghostCells = 2;
  o.components = 2;
  o.shuffledBlocks = true;
  o.rank = rank;
  o.ranks = ranks;
  return o;
}

void expectSamePolyData(vtkPolyData* blocks, vtkPolyData* twin, const char* what)
{
  ASSERT_GT(twin->GetNumberOfCells(), 0) << what;
  EXPECT_EQ(blocks->GetNumberOfCells(), twin->GetNumberOfCells()) << what;
  EXPECT_EQ(blocks->GetNumberOfPoints(), twin->GetNumberOfPoints()) << what;
  double a[6];
  double b[6];
  blocks->GetBounds(a);
  twin->GetBounds(b);
  for (int i = 0; i < 6; ++i)
  {
    EXPECT_DOUBLE_EQ(a[i], b[i]) << what;
  }
  vtkDataArray* fa = blocks->GetCellData()->GetArray("f");
  vtkDataArray* fb = twin->GetCellData()->GetArray("f");
  ASSERT_TRUE(fa && fb) << what;
  ASSERT_EQ(fa->GetNumberOfTuples(), fb->GetNumberOfTuples()) << what;
  for (vtkIdType i = 0; i < fa->GetNumberOfTuples(); ++i)
  {
    const double x = fa->GetComponent(i, 0);
    const double y = fb->GetComponent(i, 0);
    ASSERT_NEAR(x, y, 1e-9 * std::max(1.0, std::abs(y))) << what << " cell " << i;
  }
}

vtkSmartPointer<vtkPolyData> slices(vtkHyperTreeGrid* htg, bool lod)
{
  double b[6];
  htg->GetBounds(b);
  vtkNew<vtkCanopyAdaptiveSlice> slice;
  slice->SetInputData(htg);
  slice->AddPlane(0, 0.37 * b[0] + 0.63 * b[1]);
  slice->AddPlane(1, 0.5 * (b[2] + b[3]));
  slice->AddPlane(2, 0.21 * b[4] + 0.79 * b[5]);
  if (lod)
  {
    slice->SetCameraFocalPoint(0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]));
    slice->SetCameraPosition(b[1] + 6, b[3] + 4, b[5] + 5);
    slice->SetViewAngle(30);
    slice->SetViewportSize(96, 64);
    slice->SetPixelThreshold(2.0);
  }
  else
  {
    slice->ViewDependentOff();
  }
  EXPECT_TRUE(errorsOfUpdate(slice).empty());
  return slice->GetPolyDataOutput();
}

vtkSmartPointer<vtkPolyData> surface(vtkHyperTreeGrid* htg)
{
  double b[6];
  htg->GetBounds(b);
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->SetCameraFocalPoint(0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]));
  filter->SetCameraPosition(b[1] + 5, b[3] + 7, b[5] + 4);
  filter->SetViewAngle(30);
  filter->SetViewportSize(120, 90);
  filter->SetPixelThreshold(2.0);
  EXPECT_TRUE(errorsOfUpdate(filter).empty());
  return filter->GetPolyDataOutput();
}

vtkIdType selectedCells(vtkHyperTreeGrid* htg, int mode, double low, double high)
{
  double b[6];
  htg->GetBounds(b);
  vtkNew<vtkCanopyExtractSelection> filter;
  filter->SetInputData(htg);
  filter->SetSelectionMode(mode);
  filter->SetValueArrayName("f");
  filter->SetValueRange(low, high);
  filter->SetBox(b[0], 0.5 * (b[0] + b[1]), b[2], 0.6 * b[2] + 0.4 * b[3], b[4], b[5]);
  EXPECT_TRUE(errorsOfUpdate(filter).empty());
  auto* cells = vtkUnstructuredGrid::SafeDownCast(filter->GetOutput());
  return cells ? cells->GetNumberOfCells() : -1;
}

TEST(BlockForestFilters, SameGridSurfaceSlicesAndSelectionsAsTheForestCellByCell)
{
  for (const double maskProbability : {0.0, 0.25})
  {
    BlockForest forest(threeDimensional(0, 1, maskProbability));
    ExpandedTwin twin(forest);
    vtkSmartPointer<vtkHyperTreeGrid> a = buildHyperTreeGrid(forest.description());
    vtkSmartPointer<vtkHyperTreeGrid> b = buildHyperTreeGrid(twin.description);
    ASSERT_EQ(a->GetNumberOfCells(), b->GetNumberOfCells());
    // The same breadth-first tree: VTK numbers both grids' cells alike.
    vtkDataArray* fa = a->GetCellData()->GetArray("f");
    vtkDataArray* fb = b->GetCellData()->GetArray("f");
    for (vtkIdType cell = 0; cell < a->GetNumberOfCells(); ++cell)
    {
      for (int c = 0; c < 2; ++c)
      {
        const double x = fa->GetComponent(cell, c);
        const double y = fb->GetComponent(cell, c);
        ASSERT_TRUE(std::isnan(y) ? std::isnan(x) : std::abs(x - y) <= 1e-9 * std::abs(y))
            << "cell " << cell << ": " << x << " vs " << y;
      }
    }
    expectSamePolyData(surface(a), surface(b), "adaptive surface");
    expectSamePolyData(slices(a, false), slices(b, false), "slices at full resolution");
    expectSamePolyData(slices(a, true), slices(b, true), "slices with level of detail");
    double range[2];
    fb->GetRange(range, 0);
    const double low = range[0] + 0.3 * (range[1] - range[0]);
    const double high = range[0] + 0.6 * (range[1] - range[0]);
    for (int mode : {vtkCanopyExtractSelection::VALUE_RANGE, vtkCanopyExtractSelection::BOX})
    {
      const vtkIdType selected = selectedCells(a, mode, low, high);
      EXPECT_GT(selected, 0) << "mode " << mode;
      EXPECT_EQ(selected, selectedCells(b, mode, low, high)) << "mode " << mode;
    }
  }
}

TEST(BlockForestFilters, RanksSplitAtBlockBoundariesSliceTheWholeOnce)
{
  BlockForest whole(threeDimensional(0, 1, 0.0));
  vtkSmartPointer<vtkPolyData> all = slices(buildHyperTreeGrid(whole.description()), false);
  for (int ranks : {2, 3})
  {
    vtkIdType quads = 0;
    for (int rank = 0; rank < ranks; ++rank)
    {
      BlockForest part(threeDimensional(rank, ranks, 0.0));
      quads += slices(buildHyperTreeGrid(part.description()), false)->GetNumberOfCells();
    }
    EXPECT_EQ(quads, all->GetNumberOfCells()) << ranks << " ranks";
  }
}

} // namespace
} // namespace canopy::testing
