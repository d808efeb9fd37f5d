// The adaptive surface on 3D grids against a voxelization at the finest level:
// the output must cover exactly the boundary of the union of unmasked leaves
// (per-axis area equal to the exposed voxel faces, every quad with an occupied
// voxel behind it and an empty one in front, closed-surface volume identity),
// and culling must only ever remove pieces of that surface.
#include "CameraPlanes.h"
#include "HtgWalk.h"
#include "PaperCaseDefinitions.h"
#include "RandomForest.h"

#include "canopy/HtgBuilder.h"
#include "vtkCanopyAdaptiveSurface.h"

#include <gtest/gtest.h>
#include <vtkBitArray.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <set>

namespace canopy::testing
{
namespace
{

using Point = std::array<double, 3>;

/// Occupancy of the finest-level voxels by unmasked leaves (VTK's cursors).
class Voxels
{
public:
  explicit Voxels(vtkHyperTreeGrid* htg)
  {
    const unsigned int levels = htg->GetNumberOfLevels();
    PerRoot = 1;
    for (unsigned int l = 1; l < levels; ++l)
    {
      PerRoot *= static_cast<long>(htg->GetBranchFactor());
    }
    vtkDataArray* coords[3] = {htg->GetXCoordinates(), htg->GetYCoordinates(),
                               htg->GetZCoordinates()};
    for (int a = 0; a < 3; ++a)
    {
      for (vtkIdType i = 0; i < coords[a]->GetNumberOfTuples(); ++i)
      {
        Coords[a].push_back(coords[a]->GetComponent(i, 0));
      }
      Count[a] = (static_cast<long>(Coords[a].size()) - 1) * PerRoot;
    }
    Occupied.assign(static_cast<std::size_t>(Count[0] * Count[1] * Count[2]), 0);
    forEachVisibleLeaf(
        htg,
        [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
        {
          double b[6];
          cursor->GetBounds(b);
          std::array<long, 3> lo;
          std::array<long, 3> hi;
          for (int a = 0; a < 3; ++a)
          {
            lo[a] = voxelAt(a, b[2 * a], +1);
            hi[a] = voxelAt(a, b[2 * a + 1], -1) + 1;
          }
          for (long k = lo[2]; k < hi[2]; ++k)
            for (long j = lo[1]; j < hi[1]; ++j)
              for (long i = lo[0]; i < hi[0]; ++i)
                Occupied[static_cast<std::size_t>(i + Count[0] * (j + Count[1] * k))] = 1;
        });
  }

  /// Voxel index along `axis` containing x (nudged inward by `bias` voxels * 1e-6).
  long voxelAt(int axis, double x, int bias) const
  {
    const auto& c = Coords[axis];
    long root = static_cast<long>(std::upper_bound(c.begin(), c.end(), x) - c.begin()) - 1;
    root = std::clamp(root, 0L, static_cast<long>(c.size()) - 2);
    const double t = (x - c[root]) / (c[root + 1] - c[root]) * PerRoot + bias * 1e-6;
    return std::clamp(root * PerRoot + static_cast<long>(std::floor(t)), 0L, Count[axis] - 1);
  }

  bool occupiedAt(const Point& p) const
  {
    for (int a = 0; a < 3; ++a)
    {
      if (p[a] < Coords[a].front() || p[a] > Coords[a].back())
      {
        return false;
      }
    }
    const long i = voxelAt(0, p[0], 0);
    const long j = voxelAt(1, p[1], 0);
    const long k = voxelAt(2, p[2], 0);
    return Occupied[static_cast<std::size_t>(i + Count[0] * (j + Count[1] * k))] != 0;
  }

  double size(int axis, long i) const
  {
    const long root = i / PerRoot;
    return (Coords[axis][root + 1] - Coords[axis][root]) / PerRoot;
  }
  double lower(int axis, long i) const
  {
    const long root = i / PerRoot;
    return Coords[axis][root] + size(axis, i) * static_cast<double>(i % PerRoot);
  }

  /// Exposed area per axis and the occupied volume.
  void boundary(std::array<double, 3>& area, double& volume) const
  {
    area = {{0, 0, 0}};
    volume = 0;
    auto occupied = [&](long i, long j, long k)
    {
      if (i < 0 || j < 0 || k < 0 || i >= Count[0] || j >= Count[1] || k >= Count[2])
      {
        return false;
      }
      return Occupied[static_cast<std::size_t>(i + Count[0] * (j + Count[1] * k))] != 0;
    };
    for (long k = 0; k < Count[2]; ++k)
      for (long j = 0; j < Count[1]; ++j)
        for (long i = 0; i < Count[0]; ++i)
        {
          if (!occupied(i, j, k))
          {
            continue;
          }
          const double dx = size(0, i), dy = size(1, j), dz = size(2, k);
          volume += dx * dy * dz;
          area[0] += (!occupied(i - 1, j, k) + !occupied(i + 1, j, k)) * dy * dz;
          area[1] += (!occupied(i, j - 1, k) + !occupied(i, j + 1, k)) * dx * dz;
          area[2] += (!occupied(i, j, k - 1) + !occupied(i, j, k + 1)) * dx * dy;
        }
  }

  double smallestVoxel() const
  {
    double s = 1e300;
    for (int a = 0; a < 3; ++a)
      for (long i = 0; i < Count[a]; i += PerRoot)
        s = std::min(s, size(a, i));
    return s;
  }

private:
  std::array<std::vector<double>, 3> Coords;
  std::array<long, 3> Count{{0, 0, 0}};
  long PerRoot = 1;
  std::vector<unsigned char> Occupied;
};

struct Quad
{
  std::array<Point, 4> p;
  int axis;    ///< axis of the normal
  double sign; ///< +1 or -1: outward direction along the axis
  double area;
};

std::vector<Quad> quadsOf(vtkPolyData* surface)
{
  std::vector<Quad> quads;
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    surface->GetCellPoints(c, n, ids);
    EXPECT_EQ(n, 4);
    Quad q;
    for (int k = 0; k < 4; ++k)
    {
      surface->GetPoint(ids[k], q.p[k].data());
    }
    Point e1, e2;
    for (int a = 0; a < 3; ++a)
    {
      e1[a] = q.p[1][a] - q.p[0][a];
      e2[a] = q.p[3][a] - q.p[0][a];
    }
    const Point normal{{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]}};
    q.axis = 0;
    for (int a = 1; a < 3; ++a)
    {
      if (std::abs(normal[a]) > std::abs(normal[q.axis]))
      {
        q.axis = a;
      }
    }
    q.sign = normal[q.axis] > 0 ? 1.0 : -1.0;
    q.area = std::abs(normal[q.axis]);
    quads.push_back(q);
  }
  return quads;
}

/// Checks the surface against the voxelization; returns the number of quads.
std::size_t expectExactBoundary(vtkHyperTreeGrid* htg, vtkPolyData* surface,
                                const std::string& label)
{
  Voxels voxels(htg);
  std::array<double, 3> expectedArea;
  double expectedVolume = 0;
  voxels.boundary(expectedArea, expectedVolume);
  const double eps = 1e-3 * voxels.smallestVoxel();
  std::array<double, 3> area{{0, 0, 0}};
  std::array<double, 3> volume{{0, 0, 0}};
  int misplaced = 0;
  for (const Quad& q : quadsOf(surface))
  {
    area[q.axis] += q.area;
    volume[q.axis] += q.sign * q.p[0][q.axis] * q.area;
    Point centre{{0, 0, 0}};
    for (const Point& p : q.p)
      for (int a = 0; a < 3; ++a)
        centre[a] += p[a] / 4;
    Point inside = centre;
    Point outside = centre;
    inside[q.axis] -= q.sign * eps;
    outside[q.axis] += q.sign * eps;
    misplaced += !(voxels.occupiedAt(inside) && !voxels.occupiedAt(outside));
  }
  EXPECT_EQ(misplaced, 0) << label << ": quads not on the boundary or facing inward";
  for (int a = 0; a < 3; ++a)
  {
    EXPECT_NEAR(area[a], expectedArea[a], 1e-9 * expectedArea[a] + 1e-12)
        << label << ": area normal to axis " << a;
    EXPECT_NEAR(volume[a], expectedVolume, 1e-9 * expectedVolume + 1e-12)
        << label << ": volume identity along axis " << a;
  }
  return quadsOf(surface).size();
}

vtkSmartPointer<vtkPolyData> fullSurface(vtkHyperTreeGrid* htg)
{
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->ViewDependentOff();
  filter->Update();
  return filter->GetPolyDataOutput();
}

TEST(AdaptiveSurface3D, CaseBFullSurfaceIsExactlyTheBoundary)
{
  DescriptorForest plain(paperCaseB(false));
  auto htg = buildHyperTreeGrid(plain.description());
  const std::size_t outer = expectExactBoundary(htg, fullSurface(htg), "case B");
  EXPECT_EQ(outer, 466u); // faces with no neighbour (paper_cases.md)

  DescriptorForest masked(paperCaseB(true));
  auto maskedHtg = buildHyperTreeGrid(masked.description());
  const std::size_t withMask =
      expectExactBoundary(maskedHtg, fullSurface(maskedHtg), "case B with mask");
  std::cout << "case B: " << outer << " faces; with mask: " << withMask << " faces\n";
}

TEST(AdaptiveSurface3D, RandomForestsFullSurfaceIsExactlyTheBoundary)
{
  for (std::uint64_t seed = 1; seed <= 12; ++seed)
  {
    RandomForestOptions o;
    o.dimension = 3;
    o.branchFactor = seed % 3 == 0 ? 3 : 2;
    o.rootCells = {{3, 2, 2}};
    o.maxLevels = o.branchFactor == 2 ? 5 : 3;
    o.refineProbability = 0.4;
    o.maskProbability = 0.15;
    o.skipEveryOtherRoot = seed % 4 == 1; // absent trees expose their neighbours
    o.order = seed % 2 ? StorageOrder::DepthFirst : StorageOrder::BreadthFirst;
    o.origin = {{-7.5, 1e3, 3.25}};
    o.seed = seed;
    RandomForest forest(o);
    auto htg = buildHyperTreeGrid(forest.description());
    expectExactBoundary(htg, fullSurface(htg), "seed " + std::to_string(seed));
  }
}

using QuadKey = std::array<long long, 12>;

QuadKey quadKey(const Quad& q)
{
  std::array<std::array<long long, 3>, 4> corners;
  for (int k = 0; k < 4; ++k)
    for (int a = 0; a < 3; ++a)
      corners[k][a] = std::llround(q.p[k][a] * 1e9);
  std::sort(corners.begin(), corners.end());
  QuadKey key;
  for (int k = 0; k < 4; ++k)
    for (int a = 0; a < 3; ++a)
      key[3 * k + a] = corners[k][a];
  return key;
}

std::set<QuadKey> quadKeys(vtkPolyData* surface)
{
  std::set<QuadKey> keys;
  for (const Quad& q : quadsOf(surface))
  {
    keys.insert(quadKey(q));
  }
  return keys;
}

vtkSmartPointer<vtkPolyData> viewSurface(vtkHyperTreeGrid* htg, vtkCamera* camera, int w, int h,
                                         bool lod, bool backFaces = false)
{
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->SetCamera(camera);
  filter->SetViewportSize(w, h);
  filter->SetLevelOfDetail(lod);
  filter->SetSkipBackFaces(backFaces);
  filter->Update();
  return filter->GetPolyDataOutput();
}

TEST(AdaptiveSurface3D, KeptTopologyFollowsMaskAndGridChanges)
{
  // The filter keeps what it reads of the topology between executions (keyed by
  // the grid's, the mask's and the trees' state): after a change of the mask in
  // place, or a new grid, its output must equal a fresh filter's.
  DescriptorForest forest(paperCaseB(true));
  auto htg = buildHyperTreeGrid(forest.description());
  vtkNew<vtkCamera> camera;
  camera->SetFocalPoint(2.25, 1.5, 0.7);
  camera->SetPosition(2.25 + 6, 1.5 - 7, 0.7 + 5);
  camera->SetViewUp(0, 0, 1);
  vtkNew<vtkCanopyAdaptiveSurface> kept;
  kept->SetInputData(htg);
  kept->SetCamera(camera);
  kept->SetViewportSize(800, 600);
  kept->SetLevelOfDetail(false);
  kept->Update();
  EXPECT_EQ(quadKeys(kept->GetPolyDataOutput()),
            quadKeys(viewSurface(htg, camera, 800, 600, false)));
  // Unmask every cell, in place.
  vtkBitArray* mask = htg->GetMask();
  ASSERT_NE(mask, nullptr);
  for (vtkIdType i = 0; i < mask->GetNumberOfValues(); ++i)
  {
    mask->SetValue(i, 0);
  }
  mask->Modified();
  htg->Modified();
  kept->Update();
  const auto unmasked = quadKeys(kept->GetPolyDataOutput());
  EXPECT_EQ(unmasked, quadKeys(viewSurface(htg, camera, 800, 600, false)));
  EXPECT_EQ(unmasked, quadKeys(fullSurface(htg))); // the whole box is in this view
  // A different grid.
  DescriptorForest plain(paperCaseB(false));
  auto other = buildHyperTreeGrid(plain.description());
  kept->SetInputData(other);
  kept->Update();
  EXPECT_EQ(quadKeys(kept->GetPolyDataOutput()),
            quadKeys(viewSurface(other, camera, 800, 600, false)));
}

TEST(AdaptiveSurface3D, WholeGridInViewEqualsTheFullSurface)
{
  for (bool withMask : {false, true})
  {
    DescriptorForest forest(paperCaseB(withMask));
    auto htg = buildHyperTreeGrid(forest.description());
    vtkNew<vtkCamera> camera;
    camera->SetFocalPoint(2.25, 1.5, 0.7);
    camera->SetPosition(2.25 + 6, 1.5 - 7, 0.7 + 5);
    camera->SetViewUp(0, 0, 1);
    camera->SetViewAngle(30);
    const auto full = quadKeys(fullSurface(htg));
    const auto seen = quadKeys(viewSurface(htg, camera, 800, 600, true));
    EXPECT_EQ(seen, full) << (withMask ? "with mask" : "without mask");
  }
}

/// View v of the random views around case B: odd views parallel, even perspective.
vtkSmartPointer<vtkCamera> randomCaseBCamera(std::mt19937_64& random, int v)
{
  std::uniform_real_distribution<double> unit(0, 1);
  auto camera = vtkSmartPointer<vtkCamera>::New();
  camera->SetFocalPoint(4.5 * unit(random), 3 * unit(random), 1.4 * unit(random));
  camera->SetPosition(10 * unit(random) - 3, 10 * unit(random) - 3, 6 * unit(random) - 2);
  camera->SetViewUp(0, 0, 1);
  camera->OrthogonalizeViewUp();
  camera->SetParallelProjection(v % 2);
  camera->SetParallelScale(0.2 + unit(random));
  camera->SetViewAngle(15 + 30 * unit(random));
  return camera;
}

TEST(AdaptiveSurface3D, CulledSurfaceIsASubsetOfTheFullSurface)
{
  DescriptorForest forest(paperCaseB(true));
  auto htg = buildHyperTreeGrid(forest.description());
  const auto full = quadKeys(fullSurface(htg));
  std::mt19937_64 random(42);
  int partial = 0;
  for (int v = 0; v < 20; ++v)
  {
    vtkSmartPointer<vtkCamera> camera = randomCaseBCamera(random, v);
    const auto seen = quadKeys(viewSurface(htg, camera, 640, 480, false));
    std::vector<QuadKey> extra;
    std::set_difference(seen.begin(), seen.end(), full.begin(), full.end(),
                        std::back_inserter(extra));
    EXPECT_TRUE(extra.empty()) << "view " << v << ": " << extra.size()
                               << " quads not in the full surface";
    partial += seen.size() < full.size() && !seen.empty();
    // Back faces skipped: a subset again.
    const auto front = quadKeys(viewSurface(htg, camera, 640, 480, false, true));
    EXPECT_TRUE(std::includes(seen.begin(), seen.end(), front.begin(), front.end()));
    EXPECT_LT(front.size(), seen.size() + (seen.empty() ? 1 : 0));
  }
  EXPECT_GE(partial, 5) << "most views should cull something";
}

TEST(AdaptiveSurface3D, CulledSurfaceIsExactlyTheFullSurfaceInsideTheView)
{
  // A face of a visible node is drawn only if it overlaps the view with positive
  // area: the culled surface is the full surface's faces that VTK's frustum
  // planes clip to a positive area (general-position views: the brute force is
  // given a slack of 1e-9 either way, and no face may fall in between).
  for (bool withMask : {false, true})
  {
    DescriptorForest forest(paperCaseB(withMask));
    auto htg = buildHyperTreeGrid(forest.description());
    const auto fullQuads = quadsOf(fullSurface(htg));
    std::mt19937_64 random(7);
    int culled = 0;
    for (int v = 0; v < 20; ++v)
    {
      vtkSmartPointer<vtkCamera> camera = randomCaseBCamera(random, v);
      const auto seen = quadKeys(viewSurface(htg, camera, 640, 480, false));
      const auto inner = cameraSidePlanes(camera, 640.0 / 480.0, -1e-9);
      const auto outer = cameraSidePlanes(camera, 640.0 / 480.0, 1e-9);
      std::set<QuadKey> surely;
      std::set<QuadKey> maybe;
      for (const Quad& q : fullQuads)
      {
        const std::vector<ClipPoint> polygon(q.p.begin(), q.p.end());
        if (clippedArea(polygon, inner) > 0)
        {
          surely.insert(quadKey(q));
        }
        if (clippedArea(polygon, outer) > 0)
        {
          maybe.insert(quadKey(q));
        }
      }
      EXPECT_TRUE(std::includes(seen.begin(), seen.end(), surely.begin(), surely.end()))
          << "view " << v << ": a face inside the view is missing";
      EXPECT_TRUE(std::includes(maybe.begin(), maybe.end(), seen.begin(), seen.end()))
          << "view " << v << ": a face outside the view is drawn";
      EXPECT_EQ(surely.size(), maybe.size()) << "view " << v << ": not in general position";
      culled += seen.size() < fullQuads.size();
    }
    EXPECT_GE(culled, 10);
  }
}

TEST(AdaptiveSurface3D, SkippedBackFacesFaceAwayFromTheCamera)
{
  DescriptorForest forest(paperCaseB(false));
  auto htg = buildHyperTreeGrid(forest.description());
  vtkNew<vtkCamera> camera;
  camera->SetFocalPoint(2.25, 1.5, 0.7);
  camera->SetPosition(2.25 + 6, 1.5 - 7, 0.7 + 5);
  camera->SetViewUp(0, 0, 1);
  camera->ParallelProjectionOn();
  camera->SetParallelScale(3);
  double dop[3];
  camera->GetDirectionOfProjection(dop);
  auto surface = viewSurface(htg, camera, 640, 480, false, true);
  ASSERT_GT(surface->GetNumberOfCells(), 0);
  for (const Quad& q : quadsOf(surface))
  {
    EXPECT_LT(q.sign * dop[q.axis], 0);
  }
}

TEST(AdaptiveSurfaceStress3D, Depth16TreeHasExactlyTheOuterBoxAsSurface)
{
  // One root refined along a line down to 17 levels (cells of 2^-16), nothing
  // masked: the surface is the root's box, tiled by faces of many sizes.
  std::array<double, 2> x{{-3, 5}}, y{{1e6, 1e6 + 2}}, z{{0, 1}};
  std::vector<std::uint8_t> refinement{1};
  const int depth = 17;
  for (int level = 1; level < depth; ++level)
  {
    for (int c = 0; c < 8; ++c)
    {
      refinement.push_back(level + 1 < depth && c == 0 ? 1 : 0); // refine the corner child
    }
  }
  ForestDescription d;
  d.dimension = 3;
  d.branchFactor = 2;
  d.maxLevels = depth;
  d.rootGrid = {x.data(), y.data(), z.data(), 2, 2, 2};
  TreeDescription t;
  t.refinement = refinement.data();
  t.numberOfNodes = refinement.size();
  d.trees.push_back(t);
  auto htg = buildHyperTreeGrid(d);
  std::array<double, 3> area{{0, 0, 0}};
  std::array<double, 3> volume{{0, 0, 0}};
  const auto quads = quadsOf(fullSurface(htg));
  for (const Quad& q : quads)
  {
    area[q.axis] += q.area;
    volume[q.axis] += q.sign * (q.p[0][q.axis] - (q.axis == 1 ? 1e6 : 0)) * q.area;
  }
  EXPECT_NEAR(area[0], 2 * 2 * 1, 1e-9);
  EXPECT_NEAR(area[1], 2 * 8 * 1, 1e-9);
  EXPECT_NEAR(area[2], 2 * 8 * 2, 1e-9);
  for (int a = 0; a < 3; ++a)
  {
    EXPECT_NEAR(volume[a], 8 * 2 * 1, 1e-9) << "axis " << a;
  }
  // Each level contributes the 3 outer faces of each of its 7 unrefined children
  // touching the corner... at least one quad per level must exist.
  EXPECT_GT(quads.size(), static_cast<std::size_t>(3 * depth));
}

TEST(AdaptiveSurfaceStress3D, CameraInsideTheDomain)
{
  DescriptorForest forest(paperCaseB(true));
  auto htg = buildHyperTreeGrid(forest.description());
  const auto full = quadKeys(fullSurface(htg));
  vtkNew<vtkCamera> camera;
  camera->SetPosition(2.0, 1.4, 0.6); // inside the grid's bounds
  camera->SetFocalPoint(4.0, 2.5, 0.8);
  camera->SetViewUp(0, 0, 1);
  camera->SetViewAngle(60);
  for (bool lod : {false, true})
  {
    const auto seen = quadKeys(viewSurface(htg, camera, 640, 480, lod));
    if (!lod)
    {
      EXPECT_TRUE(std::includes(full.begin(), full.end(), seen.begin(), seen.end()));
      EXPECT_GT(seen.size(), 0u);
    }
  }
}

} // namespace
} // namespace canopy::testing
