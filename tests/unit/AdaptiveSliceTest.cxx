// The adaptive slice against brute force from VTK's own cursors: without level
// of detail exactly the leaves the plane cuts (the face rule of
// AdaptiveSliceBuilder.h), each quad the leaf's cross-section with the leaf's
// value, areas adding up to the plane's area inside the domain minus masked
// parts; with level of detail no gap and no overlap, each drawn node covering
// exactly the cut leaves below it; culling keeping exactly what the view's
// planes clip to a positive area; split trees drawn once over all ranks; and
// the work only the nodes the plane cuts.
#include "CameraPlanes.h"
#include "ErrorMessages.h"
#include "FlatPolygons.h"
#include "HtgWalk.h"
#include "RandomForest.h"
#include "RankPart.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSlice.h>

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <set>

namespace canopy::testing
{
namespace
{

/// A quad of the filter's output, read back through VTK's own accessors.
struct SliceQuad
{
  vtkIdType id;
  int level;
  double lo[3];
  double hi[3];
  double value; ///< the "node" field, NaN when absent
};

std::vector<SliceQuad> quadsOf(vtkPolyData* out)
{
  std::vector<SliceQuad> quads;
  vtkDataArray* ids = out->GetCellData()->GetArray("OriginalCellId");
  vtkDataArray* levels = out->GetCellData()->GetArray("Level");
  vtkDataArray* values = out->GetCellData()->GetArray("node");
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    // A rectangle, with the corners of finer neighbours on its edges.
    rectangleOf(cellPoints(out, c), "cell " + std::to_string(c));
    double b[6];
    out->GetCellBounds(c, b);
    SliceQuad q{static_cast<vtkIdType>(ids->GetTuple1(c)),
                static_cast<int>(levels->GetTuple1(c)),
                {b[0], b[2], b[4]},
                {b[1], b[3], b[5]},
                values ? values->GetTuple1(c) : std::nan("")};
    quads.push_back(q);
  }
  return quads;
}

double area(const double lo[3], const double hi[3], int axis)
{
  const int b = (axis + 1) % 3;
  const int c = (axis + 2) % 3;
  return (hi[b] - lo[b]) * (hi[c] - lo[c]);
}

/// Every node VTK's cursors reach (no masked strict ancestor), with its bounds
/// and its ancestors' global indices: the brute-force reference.
struct CursorNode
{
  vtkIdType global;
  int level;
  double bounds[6];
  bool leaf;
  bool masked;
  std::vector<vtkIdType> ancestors;
};

std::vector<CursorNode> reachableNodes(vtkHyperTreeGrid* htg)
{
  std::vector<CursorNode> nodes;
  forEachReachableNode(htg,
                       [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor,
                           const std::vector<vtkIdType>& ancestors)
                       {
                         CursorNode n;
                         n.global = cursor->GetGlobalNodeIndex();
                         n.level = static_cast<int>(cursor->GetLevel());
                         cursor->GetBounds(n.bounds);
                         n.leaf = cursor->IsLeaf();
                         n.masked = cursor->IsMasked();
                         n.ancestors = ancestors;
                         nodes.push_back(n);
                       });
  return nodes;
}

/// The face rule with a tolerance for grids whose coordinates VTK and Canopy may
/// round differently: a node is cut when its lower face is on the plane, when
/// it straddles the plane, or when the plane is the grid's upper boundary and
/// the node ends there. `tolerance` 0: the rule exactly (exact coordinates).
bool cutBy(const double bounds[6], int axis, double p, double gridHi, double tolerance)
{
  const double lo = bounds[2 * axis];
  const double hi = bounds[2 * axis + 1];
  if (std::abs(p - gridHi) <= tolerance)
  {
    return std::abs(hi - gridHi) <= tolerance;
  }
  return std::abs(lo - p) <= tolerance || (lo < p && p < hi && std::abs(hi - p) > tolerance);
}

struct Plane
{
  int axis;
  double position;
};

vtkSmartPointer<vtkPolyData> runSlice(vtkHyperTreeGrid* htg, const std::vector<Plane>& planes,
                                      const std::function<void(vtkCanopyAdaptiveSlice*)>& configure,
                                      vtkIdType* visited = nullptr)
{
  vtkNew<vtkCanopyAdaptiveSlice> slice;
  slice->SetInputData(htg);
  for (const Plane& p : planes)
  {
    slice->AddPlane(p.axis, p.position);
  }
  configure(slice);
  EXPECT_TRUE(errorsOfUpdate(slice).empty());
  if (visited)
  {
    *visited = slice->GetLastVisited();
  }
  return slice->GetPolyDataOutput();
}

void fullResolution(vtkCanopyAdaptiveSlice* slice)
{
  slice->ViewDependentOff();
}

/// A random forest with a "node" field: value 0.5 + slot, read through the grid.
struct SlicedForest
{
  RandomForest forest;
  std::vector<double> values;
  std::map<vtkIdType, double> valueOfCell;
  vtkSmartPointer<vtkHyperTreeGrid> htg;

  explicit SlicedForest(const RandomForestOptions& options) : forest(options)
  {
    values.resize(forest.numberOfNodes());
    for (std::size_t t = 0; t < forest.nodes().size(); ++t)
    {
      for (std::size_t n = 0; n < forest.nodes()[t].size(); ++n)
      {
        const auto slot = forest.nodes()[t][n].slot;
        values[static_cast<std::size_t>(slot)] = 0.5 + static_cast<double>(slot);
        valueOfCell[forest.cellOf(t, n)] = values[static_cast<std::size_t>(slot)];
      }
    }
    forest.description().fields.push_back(
        FieldDescription::aos("node", values.data(), values.size()));
    htg = buildHyperTreeGrid(forest.description());
  }
};

RandomForestOptions sliceOptions(std::uint64_t seed)
{
  RandomForestOptions o;
  o.dimension = 3;
  o.branchFactor = seed % 4 == 3 ? 3 : 2;
  o.rootCells = {{3, 2, 4}};
  o.maxLevels = o.branchFactor == 3 ? 3 : 5;
  o.refineProbability = 0.45;
  o.maskProbability = seed % 2 ? 0.12 : 0.0;
  o.order = seed % 3 == 1 ? StorageOrder::DepthFirst : StorageOrder::BreadthFirst;
  o.skipEveryOtherRoot = seed % 5 == 4;
  o.seed = seed;
  return o;
}

/// Checks a full-resolution slice against the cursors; returns the quads.
std::size_t expectExactSlice(const SlicedForest& sliced, int axis, double p, double tolerance,
                             const std::string& label)
{
  vtkHyperTreeGrid* htg = sliced.htg;
  double gridBounds[6];
  htg->GetBounds(gridBounds);
  vtkIdType visited = 0;
  const auto quads = quadsOf(runSlice(htg, {{axis, p}}, fullResolution, &visited));
  const auto nodes = reachableNodes(htg);
  std::map<vtkIdType, const CursorNode*> expected;
  std::size_t cutReachable = 0;
  double maskedArea = 0;
  for (const CursorNode& n : nodes)
  {
    if (!cutBy(n.bounds, axis, p, gridBounds[2 * axis + 1], tolerance))
    {
      continue;
    }
    ++cutReachable;
    if (n.masked)
    {
      // A topmost masked node (the walk stops there): a hole in the slice.
      double lo[3] = {n.bounds[0], n.bounds[2], n.bounds[4]};
      double hi[3] = {n.bounds[1], n.bounds[3], n.bounds[5]};
      maskedArea += area(lo, hi, axis);
    }
    else if (n.leaf)
    {
      expected[n.global] = &n;
    }
  }
  EXPECT_EQ(static_cast<std::size_t>(visited), cutReachable)
      << label << ": the slice examined other nodes than the ones the plane cuts";
  EXPECT_EQ(quads.size(), expected.size()) << label;
  std::set<vtkIdType> seen;
  double quadArea = 0;
  const double scale =
      std::max({std::abs(gridBounds[1]), std::abs(gridBounds[3]), std::abs(gridBounds[5]), 1.0}) *
      1e-12;
  for (const SliceQuad& q : quads)
  {
    EXPECT_TRUE(seen.insert(q.id).second) << label << ": cell " << q.id << " drawn twice";
    auto e = expected.find(q.id);
    if (e == expected.end())
    {
      ADD_FAILURE() << label << ": cell " << q.id << " is not cut by the plane";
      continue;
    }
    const CursorNode& n = *e->second;
    for (int a = 0; a < 3; ++a)
    {
      const double wantLo = a == axis ? p : n.bounds[2 * a];
      const double wantHi = a == axis ? p : n.bounds[2 * a + 1];
      EXPECT_NEAR(q.lo[a], wantLo, scale) << label << ": cell " << q.id << " axis " << a;
      EXPECT_NEAR(q.hi[a], wantHi, scale) << label << ": cell " << q.id << " axis " << a;
    }
    EXPECT_EQ(q.level, n.level) << label;
    EXPECT_EQ(q.value, sliced.valueOfCell.at(q.id)) << label << ": cell " << q.id;
    quadArea += area(q.lo, q.hi, axis);
  }
  // Areas: the plane's area inside the root cells that have trees, minus holes.
  double planeArea = 0;
  if (p >= gridBounds[2 * axis] && p <= gridBounds[2 * axis + 1])
  {
    for (const CursorNode& n : nodes)
    {
      if (n.level == 0 && cutBy(n.bounds, axis, p, gridBounds[2 * axis + 1], tolerance))
      {
        double lo[3] = {n.bounds[0], n.bounds[2], n.bounds[4]};
        double hi[3] = {n.bounds[1], n.bounds[3], n.bounds[5]};
        planeArea += area(lo, hi, axis);
      }
    }
  }
  EXPECT_NEAR(quadArea, planeArea - maskedArea, 1e-9 * std::max(planeArea, 1.0)) << label;
  return quads.size();
}

TEST(AdaptiveSlice, FullSliceIsExactlyTheCutLeavesOfRandomForests)
{
  std::size_t drawn = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed)
  {
    SlicedForest sliced(sliceOptions(seed));
    const auto& c = sliced.forest.coordinates();
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.02, 0.98);
    for (int axis = 0; axis < 3; ++axis)
    {
      const double lo = c[axis].front();
      const double hi = c[axis].back();
      const std::string label = "seed " + std::to_string(seed) + " axis " + std::to_string(axis);
      // Inside cells (random), on a root face, on both boundaries, outside.
      drawn += expectExactSlice(sliced, axis, lo + unit(random) * (hi - lo), 0, label + " random");
      const double tolerance = 1e-12 * (std::abs(hi) + 1);
      drawn += expectExactSlice(sliced, axis, c[axis][1], tolerance, label + " root face");
      drawn += expectExactSlice(sliced, axis, lo, tolerance, label + " lower boundary");
      drawn += expectExactSlice(sliced, axis, hi, tolerance, label + " upper boundary");
      EXPECT_EQ(expectExactSlice(sliced, axis, hi + 0.5, 0, label + " outside"), 0u);
      EXPECT_EQ(expectExactSlice(sliced, axis, lo - 0.5, 0, label + " outside"), 0u);
    }
  }
  EXPECT_GT(drawn, 2000u);
}

TEST(AdaptiveSlice, PlanesOnFacesCutTheCellOnTheirUpperSide)
{
  // Integer root coordinates and a binary tree: every face is exactly
  // representable, so the rule is checked with no tolerance at all.
  RandomForestOptions o = sliceOptions(2);
  o.maskProbability = 0;
  SlicedForest sliced(o);
  std::array<std::vector<double>, 3> integers;
  for (int a = 0; a < 3; ++a)
  {
    for (std::size_t i = 0; i <= o.rootCells[a]; ++i)
    {
      integers[a].push_back(static_cast<double>(i));
    }
  }
  sliced.forest.description().rootGrid = {integers[0].data(), integers[1].data(),
                                          integers[2].data(), integers[0].size(),
                                          integers[1].size(), integers[2].size()};
  sliced.htg = buildHyperTreeGrid(sliced.forest.description());
  for (int axis = 0; axis < 3; ++axis)
  {
    const auto n = static_cast<double>(o.rootCells[axis]);
    // Root faces, faces at levels 1-4 inside a root, both boundaries.
    for (double p : {0.0, 1.0, 0.5, 1.25, 1.375, 0.0625, n - 0.5, n})
    {
      expectExactSlice(sliced, axis, p, 0,
                       "axis " + std::to_string(axis) + " at " + std::to_string(p));
    }
  }
  // One case spelled out: x = 1 is the face between roots 0 and 1; it cuts
  // root 1's cells only (their lower face is on it).
  const auto quads = quadsOf(runSlice(sliced.htg, {{0, 1.0}}, fullResolution));
  ASSERT_FALSE(quads.empty());
  for (const SliceQuad& q : quads)
  {
    EXPECT_EQ(q.lo[0], 1.0);
    EXPECT_EQ(q.hi[0], 1.0);
  }
}

/// Each cut leaf of the full slice lies in exactly one drawn quad, whose node is
/// the leaf or one of its ancestors; returns the drawn quads.
std::size_t expectEachLeafCoveredOnce(const std::vector<SliceQuad>& drawn,
                                      const std::vector<SliceQuad>& full,
                                      const std::map<vtkIdType, std::vector<vtkIdType>>& ancestors,
                                      int axis, const std::string& label)
{
  const double eps = 1e-9;
  std::size_t misplaced = 0;
  for (const SliceQuad& leaf : full)
  {
    int covering = 0;
    for (const SliceQuad& q : drawn)
    {
      bool inside = true;
      for (int a = 0; a < 3; ++a)
      {
        inside = inside && q.lo[a] <= leaf.lo[a] + eps && leaf.hi[a] <= q.hi[a] + eps;
      }
      if (!inside)
      {
        continue;
      }
      ++covering;
      const auto& chain = ancestors.at(leaf.id);
      misplaced += q.id != leaf.id && std::find(chain.begin(), chain.end(), q.id) == chain.end();
    }
    EXPECT_EQ(covering, 1) << label << ": leaf " << leaf.id;
  }
  EXPECT_EQ(misplaced, 0u) << label << ": a quad stands for leaves that are not below it";
  double drawnArea = 0;
  double fullArea = 0;
  for (const SliceQuad& q : drawn)
  {
    drawnArea += area(q.lo, q.hi, axis);
  }
  for (const SliceQuad& q : full)
  {
    fullArea += area(q.lo, q.hi, axis);
  }
  EXPECT_NEAR(drawnArea, fullArea, 1e-9 * fullArea) << label << ": gap or overlap";
  return drawn.size();
}

TEST(AdaptiveSlice, LevelOfDetailCoversEachCutLeafExactlyOnce)
{
  int coarsened = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
  {
    RandomForestOptions o = sliceOptions(seed);
    o.skipEveryOtherRoot = false;
    o.maxLevels = o.branchFactor == 3 ? 4 : 7;
    o.refineProbability = 0.6;
    SlicedForest sliced(o);
    std::map<vtkIdType, std::vector<vtkIdType>> ancestors;
    for (const CursorNode& n : reachableNodes(sliced.htg))
    {
      ancestors[n.global] = n.ancestors;
    }
    double b[6];
    sliced.htg->GetBounds(b);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.05, 0.95);
    for (int axis = 0; axis < 3; ++axis)
    {
      const double p = b[2 * axis] + unit(random) * (b[2 * axis + 1] - b[2 * axis]);
      const auto full = quadsOf(runSlice(sliced.htg, {{axis, p}}, fullResolution));
      for (double threshold : {1.0, 6.0})
      {
        // An oblique perspective view of the whole plane; culling off, so the
        // drawn quads must tile the whole cut.
        const auto drawn =
            quadsOf(runSlice(sliced.htg, {{axis, p}},
                             [&](vtkCanopyAdaptiveSlice* s)
                             {
                               s->ViewCullingOff();
                               s->ParallelProjectionOff();
                               s->SetCameraFocalPoint(0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]),
                                                      0.5 * (b[4] + b[5]));
                               s->SetCameraPosition(b[1] + 4, b[3] + 3, b[5] + 5);
                               s->SetViewAngle(30);
                               s->SetViewportSize(160, 120);
                               s->SetPixelThreshold(threshold);
                             }));
        const std::string label = "seed " + std::to_string(seed) + " axis " + std::to_string(axis) +
                                  " threshold " + std::to_string(threshold);
        coarsened += expectEachLeafCoveredOnce(drawn, full, ancestors, axis, label) < full.size();
      }
    }
  }
  EXPECT_GE(coarsened, 20) << "level of detail should coarsen most of these views";
}

TEST(AdaptiveSlice, EdgesCarryTheCornersOfFinerNeighbours)
{
  // Where a drawn quad meets finer ones (a T-junction), their corners lie on its
  // edge: the quad is drawn as a polygon through them, so that the neighbours'
  // edges coincide point for point. Exactly those corners: for every quad of a
  // slice, at full resolution and with level of detail (culling off: every
  // neighbour drawn), its points other than its corners are the other quads'
  // corners inside its edges. With culling, a quad keeps the corners of
  // neighbours culled away (they are harmless) and has all the others.
  std::size_t vertices = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed)
  {
    RandomForestOptions o = sliceOptions(seed);
    o.maxLevels = o.branchFactor == 3 ? 4 : 6;
    o.refineProbability = 0.55;
    SlicedForest sliced(o);
    double b[6];
    sliced.htg->GetBounds(b);
    for (int axis = 0; axis < 3; ++axis)
    {
      const double p = b[2 * axis] + 0.41 * (b[2 * axis + 1] - b[2 * axis]);
      const std::string label = "seed " + std::to_string(seed) + " axis " + std::to_string(axis);
      vertices += expectEdgeVerticesAreNeighboursCorners(
          runSlice(sliced.htg, {{axis, p}}, fullResolution), label + ", every cut leaf");
      for (bool cull : {false, true})
      {
        for (double threshold : {1.0, 6.0})
        {
          auto view = [&](vtkCanopyAdaptiveSlice* s)
          {
            s->SetViewCulling(cull);
            s->ParallelProjectionOff();
            s->SetCameraFocalPoint(0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]));
            s->SetCameraPosition(b[0] + 0.7 * (b[1] - b[0]), b[3] + 2, b[5] + 1.5);
            s->SetViewAngle(35);
            s->SetViewportSize(160, 120);
            s->SetPixelThreshold(threshold);
          };
          vertices += expectEdgeVerticesAreNeighboursCorners(
              runSlice(sliced.htg, {{axis, p}}, view),
              label + (cull ? ", culled" : "") + ", threshold " + std::to_string(threshold), !cull);
        }
      }
    }
  }
  EXPECT_GT(vertices, 1000u) << "these forests should have many T-junctions";
}

TEST(AdaptiveSlice, LevelOfDetailMatchesTheClosedForm)
{
  // One cubic root of side 1 refined uniformly to level 6 (64^3 leaves), the
  // plane z = 0.3 seen face-on, parallel, filling 64 x 64 pixels: a pixel is
  // 1/64 wide, so a node at level l is 64 / 2^l pixels wide and descent stops
  // at l = ceil(log2(64 / t)) (AdaptiveSliceBuilder.h), with 4^l quads.
  ForestDescription forest;
  forest.dimension = 3;
  forest.branchFactor = 2;
  forest.maxLevels = 7;
  const std::vector<double> unitAxis{0.0, 1.0};
  forest.rootGrid = {unitAxis.data(), unitAxis.data(), unitAxis.data(), 2, 2, 2};
  std::vector<std::uint8_t> refinement;
  for (std::size_t level = 0, count = 1; level <= 6; ++level, count *= 8)
  {
    refinement.insert(refinement.end(), count, level < 6 ? 1 : 0);
  }
  forest.trees.push_back({0, refinement.data(), refinement.size()});
  auto htg = buildHyperTreeGrid(forest);
  for (double threshold : {1.0, 2.0, 3.0, 8.0, 40.0})
  {
    const int expected = static_cast<int>(std::ceil(std::log2(64.0 / threshold) - 1e-12));
    const auto quads = quadsOf(runSlice(htg, {{2, 0.3}},
                                        [&](vtkCanopyAdaptiveSlice* s)
                                        {
                                          s->SetCameraPosition(0.5, 0.5, 5);
                                          s->SetCameraFocalPoint(0.5, 0.5, 0.3);
                                          s->SetParallelScale(0.5);
                                          s->SetViewportSize(64, 64);
                                          s->SetPixelThreshold(threshold);
                                        }));
    ASSERT_EQ(quads.size(), static_cast<std::size_t>(1) << (2 * expected))
        << "threshold " << threshold;
    for (const SliceQuad& q : quads)
    {
      EXPECT_EQ(q.level, expected) << "threshold " << threshold;
    }
  }
}

TEST(AdaptiveSlice, CullingKeepsExactlyTheCutLeavesTheViewSees)
{
  // Level of detail off: the drawn quads are the full slice's quads that VTK's
  // frustum planes clip to a positive area (general position: a 1e-9 slack
  // either way, and nothing may fall in between).
  int culled = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed)
  {
    SlicedForest sliced(sliceOptions(seed));
    double b[6];
    sliced.htg->GetBounds(b);
    std::mt19937_64 random(100 + seed);
    std::uniform_real_distribution<double> unit(0, 1);
    for (int v = 0; v < 6; ++v)
    {
      const int axis = v % 3;
      const double p = b[2 * axis] + (0.1 + 0.8 * unit(random)) * (b[2 * axis + 1] - b[2 * axis]);
      vtkNew<vtkCamera> camera;
      camera->SetFocalPoint(b[0] + unit(random) * (b[1] - b[0]),
                            b[2] + unit(random) * (b[3] - b[2]),
                            b[4] + unit(random) * (b[5] - b[4]));
      camera->SetPosition(b[1] + 6 * unit(random) - 2, b[3] + 6 * unit(random) - 1,
                          b[5] + 6 * unit(random));
      camera->SetViewUp(0, 1, 0);
      camera->OrthogonalizeViewUp();
      camera->SetParallelProjection(v % 2);
      camera->SetParallelScale(0.5 + unit(random));
      camera->SetViewAngle(15 + 30 * unit(random));
      const auto full = quadsOf(runSlice(sliced.htg, {{axis, p}}, fullResolution));
      const auto seen = quadsOf(runSlice(sliced.htg, {{axis, p}},
                                         [&](vtkCanopyAdaptiveSlice* s)
                                         {
                                           s->SetCamera(camera);
                                           s->SetViewportSize(640, 480);
                                           s->LevelOfDetailOff();
                                         }));
      std::set<vtkIdType> drawn;
      for (const SliceQuad& q : seen)
      {
        drawn.insert(q.id);
      }
      const auto inner = cameraSidePlanes(camera, 640.0 / 480.0, -1e-9);
      const auto outer = cameraSidePlanes(camera, 640.0 / 480.0, 1e-9);
      std::set<vtkIdType> surely;
      std::set<vtkIdType> maybe;
      for (const SliceQuad& q : full)
      {
        const int u = (axis + 1) % 3;
        const int w = (axis + 2) % 3;
        std::vector<ClipPoint> polygon(4);
        const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (int k = 0; k < 4; ++k)
        {
          polygon[k][axis] = p;
          polygon[k][u] = corner[k][0] ? q.hi[u] : q.lo[u];
          polygon[k][w] = corner[k][1] ? q.hi[w] : q.lo[w];
        }
        if (clippedArea(polygon, inner) > 0)
        {
          surely.insert(q.id);
        }
        if (clippedArea(polygon, outer) > 0)
        {
          maybe.insert(q.id);
        }
      }
      const std::string label = "seed " + std::to_string(seed) + " view " + std::to_string(v);
      EXPECT_TRUE(std::includes(drawn.begin(), drawn.end(), surely.begin(), surely.end()))
          << label << ": a cut leaf inside the view is missing";
      EXPECT_TRUE(std::includes(maybe.begin(), maybe.end(), drawn.begin(), drawn.end()))
          << label << ": a cut leaf outside the view is drawn";
      EXPECT_EQ(surely.size(), maybe.size()) << label << ": not in general position";
      culled += drawn.size() < full.size();
    }
  }
  EXPECT_GE(culled, 20);
}

TEST(AdaptiveSlice, SplitTreesDrawEveryPointOfThePlaneOnExactlyOneRank)
{
  RandomForestOptions o;
  o.dimension = 3;
  o.rootCells = {{2, 2, 2}};
  o.maxLevels = 6;
  o.refineProbability = 0.55;
  o.seed = 17;
  RandomForest whole(o);
  const auto& c = whole.coordinates();
  const double b[6] = {c[0].front(), c[0].back(),  c[1].front(),
                       c[1].back(),  c[2].front(), c[2].back()};
  for (int axis = 0; axis < 3; ++axis)
  {
    const double p = b[2 * axis] + 0.43 * (b[2 * axis + 1] - b[2 * axis]);
    const int u = (axis + 1) % 3;
    const int w = (axis + 2) % 3;
    const double planeArea = (b[2 * u + 1] - b[2 * u]) * (b[2 * w + 1] - b[2 * w]);
    for (int ranks : {1, 2, 3, 4})
    {
      for (double threshold : {0.0, 1.0, 8.0})
      {
        std::vector<std::vector<SliceQuad>> perRank;
        std::multiset<double> leafValues;
        for (int rank = 0; rank < ranks; ++rank)
        {
          RankPart part(whole.description(), rank, ranks, rank % 2 == 1);
          auto htg = buildHyperTreeGrid(part.description);
          perRank.push_back(quadsOf(
              runSlice(htg, {{axis, p}},
                       [&](vtkCanopyAdaptiveSlice* s)
                       {
                         if (threshold == 0.0)
                         {
                           s->ViewDependentOff();
                           return;
                         }
                         // Face-on, the whole plane in a 96 x 72 view.
                         std::array<double, 3> focal{
                             {0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])}};
                         std::array<double, 3> eye = focal;
                         eye[axis] += 10;
                         std::array<double, 3> up{{0, 0, 0}};
                         up[u] = 1;
                         s->SetCameraFocalPoint(focal.data());
                         s->SetCameraPosition(eye.data());
                         s->SetCameraViewUp(up.data());
                         s->SetParallelScale(
                             0.6 * std::max(b[2 * u + 1] - b[2 * u], b[2 * w + 1] - b[2 * w]));
                         s->SetViewportSize(96, 72);
                         s->SetPixelThreshold(threshold);
                       })));
          for (const SliceQuad& q : perRank.back())
          {
            EXPECT_FALSE(std::isnan(q.value));
            leafValues.insert(q.value);
          }
        }
        const std::string label = "axis " + std::to_string(axis) + ", " + std::to_string(ranks) +
                                  " ranks, threshold " + std::to_string(threshold);
        double drawnArea = 0;
        for (const auto& quads : perRank)
        {
          for (const SliceQuad& q : quads)
          {
            drawnArea += area(q.lo, q.hi, axis);
          }
        }
        EXPECT_NEAR(drawnArea, planeArea, 1e-9 * planeArea) << label;
        std::size_t overlaps = 0;
        for (int r = 0; r < ranks; ++r)
        {
          for (int s = r + 1; s < ranks; ++s)
          {
            for (const SliceQuad& q : perRank[static_cast<std::size_t>(r)])
            {
              for (const SliceQuad& t : perRank[static_cast<std::size_t>(s)])
              {
                const double du = std::min(q.hi[u], t.hi[u]) - std::max(q.lo[u], t.lo[u]);
                const double dw = std::min(q.hi[w], t.hi[w]) - std::max(q.lo[w], t.lo[w]);
                overlaps += du > 1e-12 && dw > 1e-12;
              }
            }
          }
        }
        EXPECT_EQ(overlaps, 0u) << label;
        if (threshold == 0.0)
        {
          // Full resolution: the whole forest's cut leaves, each once, with its value.
          std::multiset<double> expected;
          std::vector<double> values(whole.numberOfNodes());
          for (std::size_t t = 0; t < whole.nodes().size(); ++t)
          {
            for (std::size_t n = 0; n < whole.nodes()[t].size(); ++n)
            {
              values[static_cast<std::size_t>(whole.nodes()[t][n].slot)] = wholeValue(t, n);
            }
          }
          ForestDescription described = whole.description();
          described.fields.push_back(FieldDescription::aos("node", values.data(), values.size()));
          for (const SliceQuad& q :
               quadsOf(runSlice(buildHyperTreeGrid(described), {{axis, p}}, fullResolution)))
          {
            expected.insert(q.value);
          }
          EXPECT_EQ(leafValues, expected) << label;
        }
      }
    }
  }
}

TEST(AdaptiveSlice, PlanesComeOutAxisByAxisInTheOrderAdded)
{
  SlicedForest sliced(sliceOptions(4));
  double b[6];
  sliced.htg->GetBounds(b);
  const Plane z{2, 0.5 * (b[4] + b[5])};
  const Plane x1{0, b[0] + 0.3 * (b[1] - b[0])};
  const Plane y{1, 0.5 * (b[2] + b[3])};
  const Plane x2{0, b[0] + 0.7 * (b[1] - b[0])};
  std::vector<SliceQuad> expected;
  for (const Plane& p : {x1, x2, y, z})
  {
    const auto one = quadsOf(runSlice(sliced.htg, {p}, fullResolution));
    ASSERT_FALSE(one.empty());
    expected.insert(expected.end(), one.begin(), one.end());
  }
  const auto together = quadsOf(runSlice(sliced.htg, {z, x1, y, x2}, fullResolution));
  ASSERT_EQ(together.size(), expected.size());
  for (std::size_t i = 0; i < together.size(); ++i)
  {
    EXPECT_EQ(together[i].id, expected[i].id) << i;
    EXPECT_EQ(together[i].lo[0], expected[i].lo[0]) << i;
    EXPECT_EQ(together[i].lo[1], expected[i].lo[1]) << i;
    EXPECT_EQ(together[i].lo[2], expected[i].lo[2]) << i;
  }
}

TEST(AdaptiveSlice, FieldsAreReadInPlaceAndNeverWritten)
{
  SlicedForest sliced(sliceOptions(6));
  vtkDataArray* field = sliced.htg->GetCellData()->GetArray("node");
  ASSERT_NE(field, nullptr);
  EXPECT_EQ(field->GetVoidPointer(0), static_cast<void*>(sliced.values.data()));
  const std::uint64_t before =
      checksum(sliced.values.data(), sliced.values.size() * sizeof(double));
  double b[6];
  sliced.htg->GetBounds(b);
  const auto quads =
      quadsOf(runSlice(sliced.htg, {{0, 0.5 * (b[0] + b[1])}, {2, 0.5 * (b[4] + b[5])}},
                       [](vtkCanopyAdaptiveSlice* s)
                       {
                         s->SetCameraPosition(20, 15, 25);
                         s->SetCameraFocalPoint(2, 1.5, 3);
                         s->ParallelProjectionOff();
                       }));
  EXPECT_FALSE(quads.empty());
  // The grid still reads the simulation's own array, unchanged.
  EXPECT_EQ(sliced.htg->GetCellData()->GetArray("node")->GetVoidPointer(0),
            static_cast<void*>(sliced.values.data()));
  EXPECT_EQ(checksum(sliced.values.data(), sliced.values.size() * sizeof(double)), before);
}

TEST(AdaptiveSlice, BadInputIsReportedByName)
{
  SlicedForest sliced(sliceOptions(3));
  struct Bad
  {
    std::string what;
    std::function<void(vtkCanopyAdaptiveSlice*)> apply;
    std::string says;
  };
  const std::vector<Bad> cases = {
      {"axis 3", [](vtkCanopyAdaptiveSlice* s) { s->AddPlane(3, 0.5); }, "axis 3"},
      {"NaN position", [](vtkCanopyAdaptiveSlice* s) { s->AddPlane(1, std::nan("")); },
       "not finite"},
      {"zero threshold", [](vtkCanopyAdaptiveSlice* s) { s->SetPixelThreshold(0); },
       "PixelThreshold"},
      {"camera at its focal point",
       [](vtkCanopyAdaptiveSlice* s) { s->SetCameraPosition(0, 0, 0); }, "invalid view"},
  };
  for (const Bad& bad : cases)
  {
    vtkNew<vtkCanopyAdaptiveSlice> slice;
    slice->SetInputData(sliced.htg);
    slice->AddPlane(0, 1.0);
    bad.apply(slice);
    const auto errors = errorsOfUpdate(slice);
    ASSERT_EQ(errors.size(), 1u) << bad.what;
    EXPECT_NE(errors[0].find(bad.says), std::string::npos) << bad.what << ": " << errors[0];
    EXPECT_EQ(slice->GetPolyDataOutput()->GetNumberOfCells(), 0) << bad.what;
  }
  // A 2D grid cannot be sliced.
  RandomForestOptions flat;
  flat.dimension = 2;
  RandomForest plane(flat);
  vtkNew<vtkCanopyAdaptiveSlice> slice;
  slice->SetInputData(buildHyperTreeGrid(plane.description()));
  slice->AddPlane(0, 1.0);
  const auto errors = errorsOfUpdate(slice);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("3D"), std::string::npos) << errors[0];
}

} // namespace
} // namespace canopy::testing
