// Trees split between ranks (p4est's partition): each rank describes its part
// with the other ranks' parts absent, and its arrays hold exactly what it has.
// Checked against the whole forest: every leaf appears on exactly one rank with
// its value, absent cells are masked and marked as another process's, leaves-only
// coarse values average the present children, and the adaptive surface never
// draws a pixel on two ranks (level of detail on split trees).
#include "HtgWalk.h"
#include "PureMaskCheck.h"
#include "RandomForest.h"
#include "RankPart.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

namespace canopy::testing
{
namespace
{

RandomForestOptions splitOptions(int dimension)
{
  RandomForestOptions o;
  o.dimension = dimension;
  o.rootCells = dimension == 1   ? std::array<std::size_t, 3>{{5, 1, 1}}
                : dimension == 2 ? std::array<std::size_t, 3>{{4, 3, 1}}
                                 : std::array<std::size_t, 3>{{2, 2, 2}};
  o.maxLevels = dimension == 1 ? 9 : dimension == 2 ? 6 : 4;
  o.refineProbability = 0.55;
  o.seed = 11;
  return o;
}

class AbsentParts : public ::testing::TestWithParam<std::tuple<int, int, bool>>
{
};

TEST_P(AbsentParts, EveryLeafOnceWithItsValueAndAbsentCellsMaskedAsAnotherRanks)
{
  const auto [dimension, ranks, depthFirst] = GetParam();
  RandomForest whole(splitOptions(dimension));
  const std::size_t children = whole.childrenPerNode();
  std::map<std::pair<std::size_t, std::size_t>, int> seen; // whole leaf -> times seen
  std::size_t splitTrees = 0;
  for (int rank = 0; rank < ranks; ++rank)
  {
    RankPart part(whole.description(), rank, ranks, depthFirst);
    const auto htg = buildHyperTreeGrid(part.description);
    vtkDataArray* node = htg->GetCellData()->GetArray("node");
    vtkDataArray* leaf = htg->GetCellData()->GetArray("leaf");
    auto* ghosts = vtkUnsignedCharArray::SafeDownCast(
        htg->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()));
    ASSERT_NE(node, nullptr);
    ASSERT_NE(leaf, nullptr);
    for (const auto& tree : part.trees)
    {
      const bool split = std::any_of(tree.absent.begin(), tree.absent.end(),
                                     [](std::uint8_t a) { return a != 0; });
      splitTrees += split;
      if (split)
      {
        ASSERT_NE(ghosts, nullptr);
      }
      forEachNode(htg, tree.rootIndex, tree.refinement, children,
                  [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor, std::size_t n)
                  {
                    const vtkIdType cell = cursor->GetGlobalNodeIndex();
                    if (tree.absent[n])
                    {
                      EXPECT_TRUE(cursor->IsMasked());
                      EXPECT_EQ(ghosts->GetValue(cell), vtkDataSetAttributes::DUPLICATECELL);
                      EXPECT_TRUE(std::isnan(node->GetComponent(cell, 0)));
                      EXPECT_TRUE(std::isnan(leaf->GetComponent(cell, 0)));
                      return;
                    }
                    EXPECT_FALSE(cursor->IsMasked());
                    if (ghosts)
                    {
                      EXPECT_EQ(ghosts->GetValue(cell), 0);
                    }
                    const double expected = wholeValue(tree.wholeTree, tree.wholeNode[n]);
                    EXPECT_EQ(node->GetComponent(cell, 0), expected);
                    if (cursor->IsLeaf())
                    {
                      EXPECT_EQ(leaf->GetComponent(cell, 0), expected);
                      ++seen[{tree.wholeTree, tree.wholeNode[n]}];
                    }
                  });
    }
  }
  if (ranks > 1)
  {
    EXPECT_GT(splitTrees, 0u) << "the partition must split some trees";
  }
  EXPECT_EQ(seen.size(), whole.numberOfLeaves());
  for (const auto& [leafId, times] : seen)
  {
    EXPECT_EQ(times, 1) << "leaf " << leafId.second << " of tree " << leafId.first;
  }
}

INSTANTIATE_TEST_SUITE_P(DimensionRanksOrder, AbsentParts,
                         ::testing::Combine(::testing::Values(1, 2, 3),
                                            ::testing::Values(1, 2, 3, 4), ::testing::Bool()));

/// The volume average over present children, recursively, by brute force.
double presentAverage(const PartitionedTree& tree, const std::vector<std::size_t>& first,
                      std::size_t children, std::size_t n)
{
  if (!tree.refinement[n])
  {
    return wholeValue(tree.wholeTree, tree.wholeNode[n]);
  }
  double sum = 0;
  int used = 0;
  for (std::size_t c = 0; c < children; ++c)
  {
    if (!tree.absent[first[n] + c])
    {
      sum += presentAverage(tree, first, children, first[n] + c);
      ++used;
    }
  }
  return used ? sum / used : std::nan("");
}

TEST(AbsentPartsLeavesOnly, CoarseValuesAverageThePresentChildrenOnly)
{
  RandomForest whole(splitOptions(2));
  const std::size_t children = whole.childrenPerNode();
  RankPart part(whole.description(), 1, 3, false);
  const auto htg = buildHyperTreeGrid(part.description);
  vtkDataArray* leaf = htg->GetCellData()->GetArray("leaf");
  std::size_t checkedCoarse = 0;
  for (const auto& tree : part.trees)
  {
    std::vector<std::size_t> first(tree.refinement.size(), 0);
    for (std::size_t n = 0, next = 1; n < tree.refinement.size(); ++n)
    {
      if (tree.refinement[n])
      {
        first[n] = next;
        next += children;
      }
    }
    forEachNode(htg, tree.rootIndex, tree.refinement, children,
                [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor, std::size_t n)
                {
                  if (tree.absent[n] || cursor->IsLeaf())
                  {
                    return;
                  }
                  ++checkedCoarse;
                  EXPECT_NEAR(leaf->GetComponent(cursor->GetGlobalNodeIndex(), 0),
                              presentAverage(tree, first, children, n), 1e-9);
                });
  }
  EXPECT_GT(checkedCoarse, 10u);
}

TEST(AbsentPartsValidation, ArraysHoldExactlyThePresentNodesAndLeaves)
{
  RandomForest whole(splitOptions(2));
  RankPart part(whole.description(), 1, 3, false);
  const ForestCounts layout = validateForest(part.description);
  EXPECT_TRUE(layout.anyAbsent);
  EXPECT_EQ(layout.totalPresentNodes, part.nodeValues.size());
  EXPECT_EQ(layout.totalPresentLeaves, part.leafValues.size());
  EXPECT_LT(layout.totalPresentNodes, layout.totalNodes);
  // One tuple fewer than the present leaves is refused, naming what is counted.
  part.description.fields[1].numberOfTuples -= 1;
  try
  {
    buildHyperTreeGrid(part.description);
    FAIL() << "too few leaf tuples accepted";
  }
  catch (const InvalidForest& error)
  {
    EXPECT_NE(std::string(error.what()).find("leaves that are not absent"), std::string::npos)
        << error.what();
  }
}

TEST(AbsentPartsValidation, AbsentRootAndRefinedAbsentNodesAreRefused)
{
  const std::vector<double> x{0, 1}, y{0, 1}, z{0};
  const std::vector<std::uint8_t> refinement{1, 0, 1, 0, 0, 0, 0, 0, 0};
  const std::vector<std::uint8_t> absentRoot{1, 0, 0, 0, 0, 0, 0, 0, 0};
  const std::vector<std::uint8_t> absentRefined{0, 0, 1, 0, 0, 0, 0, 0, 0};
  ForestDescription forest;
  forest.dimension = 2;
  forest.maxLevels = 3;
  forest.rootGrid = {x.data(), y.data(), z.data(), 2, 2, 1};
  forest.trees.push_back(
      {0, refinement.data(), refinement.size(), nullptr, nullptr, absentRoot.data()});
  EXPECT_THROW(
      {
        try
        {
          validateForest(forest);
        }
        catch (const InvalidForest& e)
        {
          EXPECT_NE(std::string(e.what()).find("the root is absent"), std::string::npos);
          throw;
        }
      },
      InvalidForest);
  forest.trees[0].absent = absentRefined.data();
  EXPECT_THROW(
      {
        try
        {
          validateForest(forest);
        }
        catch (const InvalidForest& e)
        {
          EXPECT_NE(std::string(e.what()).find("absent node(s) are refined (first: node 2)"),
                    std::string::npos)
              << e.what();
          throw;
        }
      },
      InvalidForest);
}

TEST(AbsentPartsValidation, SlotsNumberOnlyThePresentNodes)
{
  RandomForest whole(splitOptions(2));
  RankPart part(whole.description(), 0, 2, true);
  ASSERT_NO_THROW(validateForest(part.description));
  // A present node given the slot one past the present count is out of range.
  auto& slots = part.slots[0];
  const auto last = std::max_element(slots.begin(), slots.end());
  *last = static_cast<std::int64_t>(part.nodeValues.size());
  EXPECT_THROW(validateForest(part.description), InvalidForest);
}

TEST(AbsentPartsSelection, AbsentCellsAreNeverSelectedEvenWithAllowMasked)
{
  RandomForest whole(splitOptions(3));
  const int ranks = 3;
  const auto& c = whole.coordinates();
  // A lattice of points inside the domain, off every cell boundary.
  auto select = [&](const ForestDescription& forest)
  {
    vtkNew<vtkCanopyExtractSelection> extract;
    extract->SetInputData(buildHyperTreeGrid(forest));
    extract->SetSelectionMode(vtkCanopyExtractSelection::LOCATIONS);
    const int steps = 17;
    for (int i = 0; i < steps; ++i)
      for (int j = 0; j < steps; ++j)
        for (int k = 0; k < steps; ++k)
        {
          const double f[3] = {(i + 0.37) / steps, (j + 0.41) / steps, (k + 0.43) / steps};
          extract->AddLocation(c[0].front() + f[0] * (c[0].back() - c[0].front()),
                               c[1].front() + f[1] * (c[1].back() - c[1].front()),
                               c[2].front() + f[2] * (c[2].back() - c[2].front()));
        }
    extract->SetAllowMasked(true);
    extract->SetPreserveTopology(false);
    extract->Update();
    return static_cast<std::size_t>(
        vtkUnstructuredGrid::SafeDownCast(extract->GetOutputDataObject(0))->GetNumberOfCells());
  };
  // The unsplit forest selects each hit leaf once; the ranks together must too.
  const std::size_t expected = select(whole.description());
  ASSERT_GT(expected, 100u);
  std::size_t selected = 0;
  for (int rank = 0; rank < ranks; ++rank)
  {
    RankPart part(whole.description(), rank, ranks, false);
    selected += select(part.description);
  }
  EXPECT_EQ(selected, expected);
}

TEST(AbsentPartsSelection, BoxAndFrustumSelectEachLeafOnExactlyOneRank)
{
  for (int dimension : {1, 2, 3})
  {
    RandomForest whole(splitOptions(dimension));
    const auto& c = whole.coordinates();
    // A box and a frustum (six planes, tilted) through the middle of the domain.
    double box[6];
    double planes[24] = {};
    for (int a = 0; a < 3; ++a)
    {
      const double lo = c[a].front();
      const double size = c[a].back() - lo;
      box[2 * a] = lo + 0.21 * size - 1e-3;
      box[2 * a + 1] = lo + 0.77 * size + 1e-3;
      planes[8 * a + a] = 1; // x >= xmin, tilted by the next axis
      planes[8 * a + (a + 1) % 3] = 0.1;
      planes[8 * a + 3] = -(box[2 * a] + 0.1 * c[(a + 1) % 3].front());
      planes[8 * a + 4 + a] = -1; // x <= xmax
      planes[8 * a + 7] = box[2 * a + 1];
    }
    auto select = [&](const ForestDescription& forest, bool frustum)
    {
      vtkNew<vtkCanopyExtractSelection> extract;
      extract->SetInputData(buildHyperTreeGrid(forest));
      extract->SetSelectionMode(frustum ? vtkCanopyExtractSelection::FRUSTUM
                                        : vtkCanopyExtractSelection::BOX);
      extract->SetBox(box);
      extract->SetFrustumPlanes(planes);
      extract->SetAllowMasked(true);
      extract->Update();
      // Each selected cell's value: the whole forest's node it is.
      auto* out = vtkUnstructuredGrid::SafeDownCast(extract->GetOutputDataObject(0));
      std::multiset<double> values;
      vtkDataArray* node = out->GetCellData()->GetArray("node");
      for (vtkIdType i = 0; node && i < node->GetNumberOfTuples(); ++i)
      {
        values.insert(node->GetTuple1(i));
      }
      return values;
    };
    for (bool frustum : {false, true})
    {
      // The whole forest's selection, as values of its nodes.
      std::vector<double> values;
      for (std::size_t t = 0; t < whole.nodes().size(); ++t)
      {
        for (std::size_t n = 0; n < whole.nodes()[t].size(); ++n)
        {
          values.push_back(0);
        }
      }
      for (std::size_t t = 0; t < whole.nodes().size(); ++t)
      {
        for (std::size_t n = 0; n < whole.nodes()[t].size(); ++n)
        {
          values[static_cast<std::size_t>(whole.nodes()[t][n].slot)] = wholeValue(t, n);
        }
      }
      ForestDescription described = whole.description();
      described.fields.push_back(FieldDescription::aos("node", values.data(), values.size()));
      const auto expected = select(described, frustum);
      ASSERT_GT(expected.size(), 20u);
      std::multiset<double> together;
      for (int rank = 0; rank < 3; ++rank)
      {
        RankPart part(whole.description(), rank, 3, rank == 1);
        for (double v : select(part.description, frustum))
        {
          EXPECT_FALSE(std::isnan(v)) << "an absent cell was selected";
          together.insert(v);
        }
      }
      EXPECT_EQ(together, expected) << dimension << "D " << (frustum ? "frustum" : "box");
    }
  }
}

// ---- Level of detail on split trees: every pixel has exactly one owner ----

struct Quad
{
  double lo[2];
  double hi[2];
};

std::vector<Quad> surfaceQuads(vtkHyperTreeGrid* htg, double threshold, const double bounds[6],
                               int width, int height)
{
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetInputData(htg);
  const double cx = 0.5 * (bounds[0] + bounds[1]);
  const double cy = 0.5 * (bounds[2] + bounds[3]);
  surface->SetCameraPosition(cx, cy, 10);
  surface->SetCameraFocalPoint(cx, cy, 0);
  surface->SetCameraViewUp(0, 1, 0);
  surface->ParallelProjectionOn();
  // The whole domain in view, with a margin.
  surface->SetParallelScale(
      0.55 * std::max(bounds[3] - bounds[2], (bounds[1] - bounds[0]) * height / width));
  surface->SetViewportSize(width, height);
  surface->SetPixelThreshold(threshold);
  surface->Update();
  vtkPolyData* out = vtkPolyData::SafeDownCast(surface->GetOutput());
  std::vector<Quad> quads;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    double b[6];
    out->GetCellBounds(c, b);
    quads.push_back({{b[0], b[2]}, {b[1], b[3]}});
  }
  return quads;
}

class SplitTreeLevelOfDetail : public ::testing::TestWithParam<std::tuple<int, double>>
{
};

TEST_P(SplitTreeLevelOfDetail, NoTwoRanksQuadsOverlapAndTheirUnionCoversTheDomain)
{
  const auto [ranks, threshold] = GetParam();
  RandomForestOptions o = splitOptions(2);
  o.maxLevels = 8;
  o.refineProbability = 0.6;
  RandomForest whole(o);
  const auto& c = whole.coordinates();
  const double bounds[6] = {c[0].front(), c[0].back(), c[1].front(), c[1].back(), 0, 0};
  const double domainArea = (bounds[1] - bounds[0]) * (bounds[3] - bounds[2]);
  std::vector<std::vector<Quad>> perRank;
  std::size_t quads = 0;
  for (int rank = 0; rank < ranks; ++rank)
  {
    RankPart part(whole.description(), rank, ranks, false);
    perRank.push_back(
        surfaceQuads(buildHyperTreeGrid(part.description), threshold, bounds, 96, 72));
    quads += perRank.back().size();
  }
  // Level of detail must have been at work (fewer quads than leaves).
  EXPECT_LT(quads, whole.numberOfLeaves());
  double area = 0;
  for (const auto& rankQuads : perRank)
  {
    for (const Quad& q : rankQuads)
    {
      area += (q.hi[0] - q.lo[0]) * (q.hi[1] - q.lo[1]);
    }
  }
  // Union covers the domain and nothing is drawn twice: areas add up exactly...
  EXPECT_NEAR(area, domainArea, 1e-9 * domainArea);
  // ...and no two quads of different ranks overlap with positive area.
  std::size_t overlaps = 0;
  for (int a = 0; a < ranks; ++a)
  {
    for (int b = a + 1; b < ranks; ++b)
    {
      for (const Quad& p : perRank[static_cast<std::size_t>(a)])
      {
        for (const Quad& q : perRank[static_cast<std::size_t>(b)])
        {
          const double w = std::min(p.hi[0], q.hi[0]) - std::max(p.lo[0], q.lo[0]);
          const double h = std::min(p.hi[1], q.hi[1]) - std::max(p.lo[1], q.lo[1]);
          overlaps += w > 1e-12 && h > 1e-12;
        }
      }
    }
  }
  EXPECT_EQ(overlaps, 0u);
}

INSTANTIATE_TEST_SUITE_P(RanksAndThresholds, SplitTreeLevelOfDetail,
                         ::testing::Combine(::testing::Values(2, 3), ::testing::Values(1.0, 8.0)));

class SplitLineLevelOfDetail : public ::testing::TestWithParam<std::tuple<int, double>>
{
};

TEST_P(SplitLineLevelOfDetail, NoTwoRanksSegmentsOverlapAndTheyCoverTheLine)
{
  const auto [ranks, threshold] = GetParam();
  RandomForestOptions o = splitOptions(1);
  o.maxLevels = 12;
  o.refineProbability = 0.65;
  RandomForest whole(o);
  const auto& c = whole.coordinates();
  const double length = c[0].back() - c[0].front();
  std::vector<std::pair<double, double>> segments; // (lo, hi) along x, with the rank in order
  std::vector<int> owner;
  for (int rank = 0; rank < ranks; ++rank)
  {
    RankPart part(whole.description(), rank, ranks, false);
    vtkNew<vtkCanopyAdaptiveSurface> surface;
    surface->SetInputData(buildHyperTreeGrid(part.description));
    // The whole line across 60 pixels, seen from +z.
    const double cx = 0.5 * (c[0].front() + c[0].back());
    surface->SetCameraPosition(cx, c[1][0], 10);
    surface->SetCameraFocalPoint(cx, c[1][0], 0);
    surface->ParallelProjectionOn();
    surface->SetParallelScale(0.55 * length);
    surface->SetViewportSize(60, 60);
    surface->SetPixelThreshold(threshold);
    surface->Update();
    vtkPolyData* out = surface->GetPolyDataOutput();
    for (vtkIdType i = 0; i < out->GetNumberOfCells(); ++i)
    {
      double b[6];
      out->GetCellBounds(i, b);
      segments.emplace_back(b[0], b[1]);
      owner.push_back(rank);
    }
  }
  EXPECT_LT(segments.size(), whole.numberOfLeaves()) << "level of detail must be at work";
  double total = 0;
  std::size_t overlaps = 0;
  for (std::size_t i = 0; i < segments.size(); ++i)
  {
    total += segments[i].second - segments[i].first;
    for (std::size_t j = i + 1; j < segments.size(); ++j)
    {
      const double shared = std::min(segments[i].second, segments[j].second) -
                            std::max(segments[i].first, segments[j].first);
      overlaps += owner[i] != owner[j] && shared > 1e-12 * length;
    }
  }
  EXPECT_NEAR(total, length, 1e-9 * length);
  EXPECT_EQ(overlaps, 0u);
}

INSTANTIATE_TEST_SUITE_P(RanksAndThresholds, SplitLineLevelOfDetail,
                         ::testing::Combine(::testing::Values(2, 3), ::testing::Values(1.0, 8.0)));

/// The quads of a full (view-independent) surface, as sorted corner lists.
std::multiset<std::vector<double>> fullSurfaceQuads(vtkHyperTreeGrid* htg)
{
  vtkNew<vtkCanopyAdaptiveSurface> surface;
  surface->SetInputData(htg);
  surface->SetViewDependent(false);
  surface->Update();
  vtkPolyData* out = vtkPolyData::SafeDownCast(surface->GetOutput());
  std::multiset<std::vector<double>> quads;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    double b[6];
    out->GetCellBounds(c, b);
    quads.insert(std::vector<double>(b, b + 6));
  }
  return quads;
}

class SplitTree3DFaces : public ::testing::TestWithParam<int>
{
};

TEST_P(SplitTree3DFaces, RanksTogetherDrawExactlyTheBoundaryOfTheWholeForest)
{
  const int ranks = GetParam();
  RandomForest whole(splitOptions(3));
  const auto reference = fullSurfaceQuads(buildHyperTreeGrid(whole.description()));
  std::multiset<std::vector<double>> together;
  for (int rank = 0; rank < ranks; ++rank)
  {
    RankPart part(whole.description(), rank, ranks, false);
    for (const auto& quad : fullSurfaceQuads(buildHyperTreeGrid(part.description)))
    {
      together.insert(quad);
    }
  }
  // No face between ranks (inside the domain) and none missing.
  EXPECT_EQ(together.size(), reference.size());
  EXPECT_TRUE(together == reference);
}

INSTANTIATE_TEST_SUITE_P(Ranks, SplitTree3DFaces, ::testing::Values(2, 3, 4));

TEST(BuiltGrid, CarriesThePureMaskVTKWouldCompute)
{
  // The builder gives VTK's pure mask (adaptor/common/PureMask.h) for masked
  // grids and for split trees (absent cells are masked).
  RandomForestOptions masked = splitOptions(3);
  masked.maskProbability = 0.15;
  RandomForest holes(masked);
  RandomForest whole(splitOptions(3));
  RankPart part(whole.description(), 1, 3, true);
  for (const ForestDescription* forest : {&holes.description(), &part.description})
  {
    auto htg = buildHyperTreeGrid(*forest);
    ASSERT_TRUE(htg->HasMask());
    const PureMaskComparison pure = comparePureMask(htg);
    EXPECT_FALSE(pure.sameArray);
    EXPECT_GT(pure.compared, 20u);
    EXPECT_EQ(pure.differing, 0u);
  }
}

} // namespace
} // namespace canopy::testing
