// The adaptive surface on 1D grids (a line of roots along x, y or z) against
// brute-force references: the emitted segments are exactly the visible leaves
// whose segment, clipped by VTK's own camera frustum planes, has positive length;
// each is a VTK_LINE on its cell; level of detail stops where the closed form
// says and never above a node larger than the threshold; the segments tile the
// visible part of the line.
#include "ConvexClip.h"
#include "HtgWalk.h"
#include "RandomForest.h"

#include "canopy/HtgBuilder.h"
#include "vtkCanopyAdaptiveSurface.h"

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkMatrix4x4.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

namespace canopy::testing
{
namespace
{

struct View
{
  ClipPoint position;
  ClipPoint focal;
  ClipPoint up;
  bool parallel;
  double scale; // parallel scale or view angle
  int width;
  int height;
};

vtkSmartPointer<vtkCamera> cameraFor(const View& v)
{
  auto camera = vtkSmartPointer<vtkCamera>::New();
  camera->SetPosition(v.position.data());
  camera->SetFocalPoint(v.focal.data());
  camera->SetViewUp(v.up.data());
  camera->SetParallelProjection(v.parallel);
  camera->SetParallelScale(v.scale);
  camera->SetViewAngle(v.parallel ? 30 : v.scale);
  const double distance = camera->GetDistance();
  camera->SetClippingRange(distance / 1e6, distance * 1e6);
  return camera;
}

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

vtkSmartPointer<vtkPolyData> runFilter(vtkHyperTreeGrid* htg, const View& v, bool lod,
                                       double threshold = 1.0)
{
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->SetCamera(cameraFor(v));
  filter->SetViewportSize(v.width, v.height);
  filter->SetLevelOfDetail(lod);
  filter->SetPixelThreshold(threshold);
  filter->Update();
  vtkSmartPointer<vtkPolyData> out = filter->GetPolyDataOutput();
  return out;
}

std::set<vtkIdType> emittedIds(vtkPolyData* surface)
{
  auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
  std::set<vtkIdType> result;
  for (vtkIdType i = 0; ids && i < ids->GetNumberOfTuples(); ++i)
  {
    result.insert(ids->GetValue(i));
  }
  EXPECT_EQ(result.size(), static_cast<std::size_t>(surface->GetNumberOfCells()))
      << "a cell emitted twice";
  return result;
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
    vtkNew<vtkCanopyAdaptiveSurface> filter;
    filter->SetInputData(htg);
    filter->ViewDependentOff();
    filter->Update();
    vtkPolyData* surface = filter->GetPolyDataOutput();
    const auto leaves = visibleLeafBoxes(htg);
    ASSERT_EQ(surface->GetNumberOfCells(), static_cast<vtkIdType>(leaves.size()));
    EXPECT_EQ(surface->GetNumberOfLines(), surface->GetNumberOfCells());
    std::map<vtkIdType, const LeafBox*> byId;
    for (const LeafBox& leaf : leaves)
    {
      byId[leaf.global] = &leaf;
    }
    auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
    auto* levels = vtkUnsignedCharArray::SafeDownCast(surface->GetCellData()->GetArray("Level"));
    for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
    {
      ASSERT_EQ(surface->GetCellType(c), VTK_LINE) << "seed " << seed;
      const LeafBox* leaf = byId.at(ids->GetValue(c));
      EXPECT_EQ(levels->GetValue(c), leaf->level);
      double b[6];
      surface->GetCell(c)->GetBounds(b);
      for (int i = 0; i < 6; ++i)
      {
        ASSERT_NEAR(b[i], leaf->bounds[i], 1e-12) << "seed " << seed << " bound " << i;
      }
    }
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
    EXPECT_EQ(emittedIds(runFilter(htg, v, false)), expected)
        << "seed " << seed << (v.parallel ? " parallel" : " perspective");
    nonTrivial += !expected.empty() && expected.size() < visibleLeafBoxes(htg).size();
  }
  EXPECT_GE(nonTrivial, 20);
}

/// Pixel footprint of a segment by VTK's own projection matrix.
double vtkFootprint(const View& v, const double b[6])
{
  // The camera owns the matrix: it must outlive its use (a temporary camera here was
  // a heap-use-after-free, found by the sanitizer build).
  const vtkSmartPointer<vtkCamera> camera = cameraFor(v);
  vtkMatrix4x4* m =
      camera->GetCompositeProjectionTransformMatrix(double(v.width) / v.height, -1, 1);
  double lo[2] = {1e300, 1e300};
  double hi[2] = {-1e300, -1e300};
  for (int k = 0; k < 2; ++k)
  {
    const double p[4] = {b[k], b[2 + k], b[4 + k], 1};
    double q[4];
    m->MultiplyPoint(p, q);
    const double xy[2] = {(q[0] / q[3] + 1) * 0.5 * v.width, (q[1] / q[3] + 1) * 0.5 * v.height};
    for (int a = 0; a < 2; ++a)
    {
      lo[a] = std::min(lo[a], xy[a]);
      hi[a] = std::max(hi[a], xy[a]);
    }
  }
  return std::max(hi[0] - lo[0], hi[1] - lo[1]);
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
    auto surface = runFilter(htg, v, true, threshold);
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
  // Uniformly refined roots of length 10 along x, seen across: every segment is
  // at level ceil(log(S / (t p)) / log f), capped by the depth.
  for (int f : {2, 3})
  {
    RandomForestOptions o;
    o.dimension = 1;
    o.activeAxis = 0;
    o.branchFactor = f;
    o.rootCells = {{3, 1, 1}};
    o.maxLevels = f == 2 ? 12 : 8;
    o.refineProbability = 1.0;
    RandomForest forest(o);
    auto& g = const_cast<std::array<std::vector<double>, 3>&>(forest.coordinates());
    for (std::size_t i = 0; i < g[0].size(); ++i)
    {
      g[0][i] = 10.0 * static_cast<double>(i);
    }
    auto htg = buildHyperTreeGrid(forest.description());
    for (double scale : {3.0, 15.0, 40.0, 200.0})
    {
      for (double threshold : {1.0, 3.0})
      {
        const View v{{{15, g[1][0], 50}}, {{15, g[1][0], 0}}, {{0, 1, 0}}, true, scale, 512, 512};
        auto surface = runFilter(htg, v, true, threshold);
        const double pixel = 2 * scale / 512;
        const double exact = std::log(10.0 / (threshold * pixel)) / std::log(double(f));
        const int expected =
            std::min(o.maxLevels - 1, std::max(0, static_cast<int>(std::ceil(exact - 1e-12))));
        auto* levels =
            vtkUnsignedCharArray::SafeDownCast(surface->GetCellData()->GetArray("Level"));
        ASSERT_GT(surface->GetNumberOfCells(), 0);
        for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
        {
          ASSERT_EQ(levels->GetValue(c), expected)
              << "f " << f << " scale " << scale << " threshold " << threshold;
        }
      }
    }
  }
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
      auto surface = runFilter(htg, v, lod);
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
