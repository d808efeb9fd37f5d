// The adaptive surface on 3D grids against a voxelization at the finest level:
// the output must cover exactly the boundary of the union of unmasked leaves
// (per-axis area equal to the exposed voxel faces, every quad with an occupied
// voxel behind it and an empty one in front, closed-surface volume identity),
// and culling must only ever remove pieces of that surface.
#include "CameraPlanes.h"
#include "ChangingForest.h"
#include "FlatPolygons.h"
#include "HtgWalk.h"
#include "PaperCaseDefinitions.h"
#include "RandomForest.h"
#include "SurfaceRuns.h"
#include "VoxelBoundary.h"

#include <canopy/GridBuilder.h>
#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

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

TEST(AdaptiveSurface3D, CaseBFullSurfaceIsExactlyTheBoundary)
{
  DescriptorForest plain(paperCaseB(false));
  auto htg = buildHyperTreeGrid(plain.description());
  const std::size_t outer = expectExactBoundary(htg, fullSurface(htg), "case B");
  EXPECT_EQ(outer, 466u); // faces with no neighbour (../shared/testdata/paper_cases.md)

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

QuadKey quadKey(const Quad& q)
{
  return ::canopy::testing::quadKey(q.p);
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

TEST(AdaptiveSurface3D, KeptTopologyAcrossSimulationSteps)
{
  // A simulation's grid from GridBuilder: the same grid object, modified at every
  // step. A step that changes only values keeps the filter's topology (and the
  // surface's memos); a mask, a tree or the coordinates changing does not. At
  // every step the output equals a fresh filter's.
  ChangingForest forest(3, 27, false, 31);
  GridBuilder builder;
  vtkNew<vtkCamera> camera;
  camera->SetFocalPoint(0.6, 0.7, 0.8);
  camera->SetPosition(0.6 + 4, 0.7 - 5, 0.8 + 3);
  camera->SetViewUp(0, 0, 1);
  vtkNew<vtkCanopyAdaptiveSurface> kept;
  kept->SetCamera(camera);
  kept->SetViewportSize(800, 600);
  kept->SetLevelOfDetail(false);
  enum class Change
  {
    Values,
    Mask,
    Tree,
    Coordinates
  };
  const std::vector<std::pair<Change, bool>> steps{
      {Change::Values, false}, {Change::Values, true},       {Change::Values, true},
      {Change::Mask, false},   {Change::Values, true},       {Change::Tree, false},
      {Change::Values, true},  {Change::Coordinates, false}, {Change::Values, true}};
  for (std::size_t step = 0; step < steps.size(); ++step)
  {
    const auto [change, keep] = steps[step];
    if (change == Change::Mask)
      forest.toggleMask(13);
    else if (change == Change::Tree)
    {
      // Re-refined until it has another shape (a draw may give the same tree).
      const std::size_t before = forest.numberOfNodes(5);
      while (forest.numberOfNodes(5) == before)
        forest.refine(5);
    }
    else if (change == Change::Coordinates)
      forest.shiftCoordinates(0.125);
    const ForestDescription description = forest.describe(10.0 * static_cast<double>(step));
    vtkSmartPointer<vtkHyperTreeGrid> grid = builder.build(description);
    kept->SetInputData(grid);
    kept->Update();
    EXPECT_EQ(kept->GetLastTopologyKept(), keep) << "step " << step;
    EXPECT_EQ(quadKeys(kept->GetPolyDataOutput()),
              quadKeys(viewSurface(grid, camera, 800, 600, false)))
        << "step " << step;
  }
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

/// Two roots along x, seen along +y with parallel projection, so that a node's
/// footprint is max(dx, dz) / pixel: the left root [0, 4] is refined to level 3,
/// the right one [4, 5] is four times narrower, so level of detail stops there
/// two levels coarser than on the left. Below the right root's coarse nodes,
/// masked nodes touch the face x = 4 between them.
struct CoarseStopNextToFineForest
{
  std::array<double, 3> x{{0, 4, 5}};
  std::array<double, 2> y{{0, 1}};
  std::array<double, 2> z{{0, 1}};
  static constexpr int Levels = 4;
  static constexpr double PixelSize = 0.052; ///< parallel scale 2.6 over 100 pixels

  struct Node
  {
    int level;
    std::array<long, 3> ijk;
  };
  static bool refined(int tree, const Node& n)
  {
    if (tree == 0)
    {
      return n.level < 3;
    }
    const auto at = [&](int level, long i, long j, long k) {
      return n.level == level && n.ijk == std::array<long, 3>{{i, j, k}};
    };
    return n.level == 0 || at(1, 0, 0, 0) || at(1, 0, 1, 1) || at(2, 0, 3, 3);
  }
  static bool masked(int tree, const Node& n)
  {
    const auto at = [&](int level, long i, long j, long k) {
      return n.level == level && n.ijk == std::array<long, 3>{{i, j, k}};
    };
    return tree == 1 && (at(2, 0, 0, 0) || at(2, 0, 1, 1) || at(3, 0, 7, 6));
  }
  void box(int tree, const Node& n, double b[6]) const
  {
    const double lo[3] = {x[static_cast<std::size_t>(tree)], y[0], z[0]};
    const double size[3] = {x[static_cast<std::size_t>(tree) + 1] - lo[0], y[1] - y[0],
                            z[1] - z[0]};
    const double cells = std::ldexp(1.0, n.level);
    for (int a = 0; a < 3; ++a)
    {
      b[2 * a] = lo[a] + size[a] * static_cast<double>(n.ijk[a]) / cells;
      b[2 * a + 1] = lo[a] + size[a] * static_cast<double>(n.ijk[a] + 1) / cells;
    }
  }
  /// Where the walk stops at `threshold` pixels: a leaf, or a node at most that
  /// wide on the screen (nothing is absent here).
  bool stops(int tree, const Node& n, double threshold) const
  {
    double b[6];
    box(tree, n, b);
    return !refined(tree, n) || std::max(b[1] - b[0], b[5] - b[4]) <= threshold * PixelSize;
  }

  /// Breadth-first refinement and mask bytes of each tree; with `threshold` > 0,
  /// of the grid pruned where the walk stops (those nodes become leaves), the
  /// solid a surface with level of detail bounds. `stopBoxes` gets the boxes of
  /// the unmasked nodes where it stops.
  void describe(double threshold, std::vector<std::vector<std::uint8_t>>& refinement,
                std::vector<std::vector<std::uint8_t>>& mask,
                std::vector<std::array<double, 6>>* stopBoxes = nullptr) const
  {
    refinement.assign(2, {});
    mask.assign(2, {});
    for (int tree = 0; tree < 2; ++tree)
    {
      std::vector<Node> queue{Node{0, {{0, 0, 0}}}};
      for (std::size_t q = 0; q < queue.size(); ++q)
      {
        const Node n = queue[q];
        const bool hidden = masked(tree, n);
        const bool stop = !hidden && threshold > 0 && stops(tree, n, threshold);
        const bool refine = !hidden && refined(tree, n) && !stop;
        refinement[static_cast<std::size_t>(tree)].push_back(refine ? 1 : 0);
        mask[static_cast<std::size_t>(tree)].push_back(hidden ? 1 : 0);
        if (stop && stopBoxes)
        {
          std::array<double, 6> b;
          box(tree, n, b.data());
          stopBoxes->push_back(b);
        }
        for (int c = 0; refine && c < 8; ++c)
        {
          queue.push_back({n.level + 1,
                           {{2 * n.ijk[0] + (c & 1), 2 * n.ijk[1] + ((c >> 1) & 1),
                             2 * n.ijk[2] + ((c >> 2) & 1)}}});
        }
      }
    }
  }

  vtkSmartPointer<vtkHyperTreeGrid> build(const std::vector<std::vector<std::uint8_t>>& refinement,
                                          const std::vector<std::vector<std::uint8_t>>& mask) const
  {
    ForestDescription d;
    d.dimension = 3;
    d.branchFactor = 2;
    d.maxLevels = Levels;
    d.rootGrid = {x.data(), y.data(), z.data(), 3, 2, 2};
    for (std::size_t t = 0; t < 2; ++t)
    {
      TreeDescription tree;
      tree.rootIndex = static_cast<std::int64_t>(t);
      tree.refinement = refinement[t].data();
      tree.numberOfNodes = refinement[t].size();
      tree.masked = mask[t].data();
      d.trees.push_back(tree);
    }
    return buildHyperTreeGrid(d);
  }
};

TEST(AdaptiveSurface3D, LevelOfDetailDrawsNoFaceInsideACoarserStopNode)
{
  // A fine node drawn next to a coarser node where the neighbour's walk stops
  // (drawn as a solid) must not draw its face toward it, even where a masked
  // node lies below that coarse node at or above the fine node's level (at 12
  // pixels: fine level 3 next to the right root's level 1; at 25: level 2 next
  // to the right root itself). At each threshold the surface is exactly the
  // boundary of the union of the nodes where descent stops.
  const CoarseStopNextToFineForest forest;
  std::vector<std::vector<std::uint8_t>> refinement;
  std::vector<std::vector<std::uint8_t>> mask;
  forest.describe(0, refinement, mask);
  auto htg = forest.build(refinement, mask);
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->SetCameraPosition(2.5, -10, 0.5);
  filter->SetCameraFocalPoint(2.5, 0.5, 0.5);
  filter->SetCameraViewUp(0, 0, 1);
  filter->SetParallelProjection(true);
  filter->SetParallelScale(2.6);
  filter->SetViewportSize(100, 100);
  filter->SetViewCulling(false); // the whole surface of the stop nodes, not the part in view
  // Footprints are 4, 2, 1, 0.5 (left) and 1, 0.5, 0.25, 0.125 (right) units,
  // pixels 0.052 units: no threshold below falls on a footprint.
  for (double threshold : {1.0, 5.0, 12.0, 25.0, 50.0})
  {
    const std::string label = "threshold " + std::to_string(threshold);
    filter->SetPixelThreshold(threshold);
    filter->Update();
    vtkPolyData* surface = filter->GetPolyDataOutput();
    ASSERT_GT(surface->GetNumberOfCells(), 0) << label;
    std::vector<std::vector<std::uint8_t>> prunedRefinement;
    std::vector<std::vector<std::uint8_t>> prunedMask;
    std::vector<std::array<double, 6>> stopBoxes;
    forest.describe(threshold, prunedRefinement, prunedMask, &stopBoxes);
    // (a) Nothing solid in front of any face: no stop node holds the point just
    // in front of its centre.
    const auto quads = quadsOf(surface);
    int inside = 0;
    for (const Quad& q : quads)
    {
      Point front{{0, 0, 0}};
      for (const Point& p : q.p)
        for (int a = 0; a < 3; ++a)
          front[a] += p[a] / 4;
      front[q.axis] += q.sign * 1e-6;
      for (const auto& b : stopBoxes)
      {
        bool holds = true;
        for (int a = 0; a < 3; ++a)
        {
          holds = holds && b[2 * a] < front[a] && front[a] < b[2 * a + 1];
        }
        inside += holds;
      }
    }
    EXPECT_EQ(inside, 0) << label << ": faces inside the solid of the nodes where descent stops";
    // (b) Exactly the boundary of that solid: per-axis area against its voxels,
    // every face on it, facing out.
    expectExactBoundary(Voxels(forest.build(prunedRefinement, prunedMask)), quads, label);
  }
}

TEST(AdaptiveSurface3D, FacesCarryTheCornersOfThePiecesMeetingTheirEdges)
{
  // Where a face meets smaller ones along an edge (in its plane, or across a
  // concave or convex edge of the solid), their corners lie on its edge and the
  // face is drawn as a polygon through them: every corner of another face
  // strictly inside one of its edges is one of its points. (A face may carry a
  // few more: the bounds of every cell around the edge are taken, also where
  // they bound no face.) Full surfaces and views with level of detail, culled
  // or not, back faces skipped or not, on random masked forests with holes.
  std::size_t vertices = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed)
  {
    RandomForestOptions o;
    o.dimension = 3;
    o.branchFactor = seed % 4 == 3 ? 3 : 2;
    o.rootCells = {{3, 2, 2}};
    o.maxLevels = o.branchFactor == 2 ? 5 : 3;
    o.refineProbability = 0.45;
    o.maskProbability = seed % 2 ? 0.15 : 0.0;
    o.skipEveryOtherRoot = seed % 3 == 2;
    o.seed = seed;
    RandomForest forest(o);
    auto htg = buildHyperTreeGrid(forest.description());
    const std::string label = "seed " + std::to_string(seed);
    vertices += expectEdgeVerticesAreNeighboursCorners(fullSurface(htg), label + ", full", false);
    double b[6];
    htg->GetBounds(b);
    vtkNew<vtkCamera> camera;
    camera->SetFocalPoint((b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2);
    camera->SetPosition(b[1] + 2, b[2] - 3, b[5] + 2.5);
    camera->SetViewUp(0, 0, 1);
    camera->SetViewAngle(30);
    for (double threshold : {1.0, 6.0, 20.0})
      for (bool cull : {false, true})
        for (bool backFaces : {false, true})
        {
          vtkNew<vtkCanopyAdaptiveSurface> filter;
          filter->SetInputData(htg);
          filter->SetCamera(camera);
          filter->SetViewportSize(320, 240);
          filter->SetPixelThreshold(threshold);
          filter->SetViewCulling(cull);
          filter->SetSkipBackFaces(backFaces);
          filter->Update();
          vertices += expectEdgeVerticesAreNeighboursCorners(
              filter->GetPolyDataOutput(),
              label + ", threshold " + std::to_string(threshold) + (cull ? ", culled" : "") +
                  (backFaces ? ", back faces skipped" : ""),
              false);
        }
  }
  EXPECT_GT(vertices, 1000u) << "these forests should have many T-junctions";
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
