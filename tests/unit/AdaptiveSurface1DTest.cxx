// The adaptive surface on 1D grids (a line of roots along x, y or z) against
// brute-force references: the emitted segments are exactly the visible leaves
// whose segment, clipped by VTK's own camera frustum planes, has positive length;
// each is a VTK_LINE on its cell; level of detail stops where the closed form
// says and never above a node larger than the threshold; the segments tile the
// visible part of the line.
#include "ConvexClip.h"
#include "HtgWalk.h"
#include "RandomForest.h"
#include "SurfaceRuns.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>

namespace canopy::testing
{
namespace
{

/// VTK's frustum side planes (near and far are far away and left out).
std::vector<ClipPlane> sidePlanes(const View& v)
{
  double planes[24];
  cameraFor(v)->GetFrustumPlanes(static_cast<double>(v.width) / v.height, planes);
  std::vector<ClipPlane> sides;
  for (int p = 0; p < 4; ++p)
  {
    sides.push_back({{planes[4 * p], planes[4 * p + 1], planes[4 * p + 2], planes[4 * p + 3]}});
  }
  return sides;
}

/// Ends of a 1D cell from its bounds.
std::pair<ClipPoint, ClipPoint> segmentOf(const double b[6])
{
  return {{{b[0], b[2], b[4]}}, {{b[1], b[3], b[5]}}};
}

double lengthOf(const double b[6])
{
  return std::max({b[1] - b[0], b[3] - b[2], b[5] - b[4]});
}

std::set<vtkIdType> bruteForceVisible(vtkHyperTreeGrid* htg, const View& view)
{
  const auto planes = sidePlanes(view);
  std::set<vtkIdType> ids;
  for (const LeafBox& leaf : visibleLeafBoxes(htg))
  {
    const auto [p, q] = segmentOf(leaf.bounds);
    if (clippedLength(p, q, planes) > 1e-12 * lengthOf(leaf.bounds))
    {
      ids.insert(leaf.global);
    }
  }
  return ids;
}

RandomForestOptions lineOptions(std::uint64_t seed)
{
  RandomForestOptions o;
  o.dimension = 1;
  o.activeAxis = static_cast<int>(seed % 3);
  o.branchFactor = seed % 2 ? 3 : 2;
  o.rootCells = {{6, 5, 7}};
  o.maxLevels = o.branchFactor == 2 ? 9 : 6;
  o.refineProbability = 0.6;
  o.maskProbability = seed % 4 < 2 ? 0.1 : 0.0;
  o.order = seed % 5 == 1 ? StorageOrder::DepthFirst : StorageOrder::BreadthFirst;
  o.skipEveryOtherRoot = seed % 7 == 3;
  o.origin = {{-7.5 * static_cast<double>(seed % 3), 1e3, -42.0}};
  o.seed = seed;
  return o;
}

/// A view of the line: looking across it, tilted up to about 60 degrees
/// toward it, from a random distance.
View randomView(const double b[6], int axis, std::mt19937_64& random, std::uint64_t seed)
{
  std::uniform_real_distribution<double> unit(0, 1);
  const double extent = b[2 * axis + 1] - b[2 * axis];
  View v;
  for (int a = 0; a < 3; ++a)
  {
    v.focal[a] = b[2 * a] + unit(random) * (b[2 * a + 1] - b[2 * a]);
  }
  ClipPoint direction{{unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5}};
  direction[axis] *= 1.5;
  const double length = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] +
                                  direction[2] * direction[2]);
  const double distance = extent * (0.2 + unit(random));
  for (int a = 0; a < 3; ++a)
  {
    v.position[a] = v.focal[a] + distance * direction[a] / length;
  }
  v.up = {{unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5}};
  v.parallel = seed % 4 < 2;
  v.scale = v.parallel ? extent * (0.02 + 0.4 * unit(random)) : 10 + 50 * unit(random);
  const int sizes[][2] = {{400, 400}, {640, 480}, {300, 900}, {1024, 256}};
  v.width = sizes[seed % 4][0];
  v.height = sizes[seed % 4][1];
  return v;
}

TEST(AdaptiveSurface1D, EverySegmentIsAVtkLineOnItsCellInAnyStorageOrder)
{
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
  {
    RandomForest forest(lineOptions(seed));
    auto htg = buildHyperTreeGrid(forest.description());
    expectOneCellPerVisibleLeaf(htg, VTK_LINE, "seed " + std::to_string(seed));
  }
}

TEST(AdaptiveSurface1D, RandomViewsEmitExactlyTheOverlappingLeaves)
{
  int nonTrivial = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed)
  {
    const RandomForestOptions o = lineOptions(seed);
    RandomForest forest(o);
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    std::mt19937_64 random(seed);
    const View v = randomView(b, o.activeAxis, random, seed);
    const auto expected = bruteForceVisible(htg, v);
    EXPECT_EQ(emittedIds(runSurface(htg, v, false)), expected)
        << "seed " << seed << (v.parallel ? " parallel" : " perspective");
    nonTrivial += !expected.empty() && expected.size() < visibleLeafBoxes(htg).size();
  }
  EXPECT_GE(nonTrivial, 20);
}

TEST(AdaptiveSurface1D, LevelOfDetailStopsOnlyAtNodesBelowTheThreshold)
{
  int coarseEmitted = 0;
  for (std::uint64_t seed = 101; seed <= 130; ++seed)
  {
    const RandomForestOptions o = lineOptions(seed);
    RandomForest forest(o);
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    std::mt19937_64 random(seed);
    View v = randomView(b, o.activeAxis, random, seed);
    v.width /= 8; // coarse viewports so that level of detail engages
    v.height /= 8;
    const double threshold = 2.5;
    auto surface = runSurface(htg, v, true, threshold);
    std::map<vtkIdType, bool> leafById;
    for (std::size_t t = 0; t < forest.nodes().size(); ++t)
    {
      for (std::size_t n = 0; n < forest.nodes()[t].size(); ++n)
      {
        leafById[forest.cellOf(t, n)] = forest.refinement()[t][n] == 0;
      }
    }
    auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
    for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
    {
      if (leafById.at(ids->GetValue(c)))
      {
        continue;
      }
      ++coarseEmitted;
      double cb[6];
      surface->GetCell(c)->GetBounds(cb);
      EXPECT_LE(vtkFootprint(v, cb), threshold * (1 + 1e-9)) << "seed " << seed;
    }
  }
  EXPECT_GT(coarseEmitted, 20) << "level of detail must actually stop above the leaves";
}

TEST(AdaptiveSurface1D, LevelOfDetailMatchesTheClosedForm)
{
  // Uniformly refined roots of length 10 along x, seen across.
  expectLevelsMatchClosedForm(1);
}

TEST(AdaptiveSurface1D, SegmentsTileTheVisiblePartOfTheLine)
{
  for (std::uint64_t seed = 201; seed <= 230; ++seed)
  {
    RandomForestOptions o = lineOptions(seed);
    o.maskProbability = 0; // holes are not tiled
    o.skipEveryOtherRoot = false;
    RandomForest forest(o);
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    std::mt19937_64 random(seed);
    for (bool lod : {false, true})
    {
      View v = randomView(b, o.activeAxis, random, seed);
      v.width /= lod ? 16 : 1;
      v.height /= lod ? 16 : 1;
      const auto planes = sidePlanes(v);
      const auto [p, q] = segmentOf(b);
      const double visible = clippedLength(p, q, planes);
      auto surface = runSurface(htg, v, lod);
      double covered = 0;
      for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
      {
        double cb[6];
        surface->GetCell(c)->GetBounds(cb);
        const auto [cp, cq] = segmentOf(cb);
        covered += clippedLength(cp, cq, planes);
      }
      EXPECT_NEAR(covered, visible, 1e-9 * lengthOf(b))
          << "seed " << seed << (lod ? " with" : " without") << " level of detail";
    }
  }
}

} // namespace
} // namespace canopy::testing
