// The adaptive surface on 2D grids against brute-force references: the set of
// emitted cells must be exactly the visible leaves overlapping the view with
// nonzero area (VTK's own camera frustum planes, polygon clipping), level of
// detail must stop exactly where the closed form says, and the emitted cells
// must tile the visible domain.
#include "ErrorMessages.h"
#include "FlatPolygons.h"
#include "HtgWalk.h"
#include "PaperCaseDefinitions.h"
#include "RandomForest.h"
#include "SurfaceRuns.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <gtest/gtest.h>
#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkRenderer.h>
#include <vtkSMPTools.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>

namespace canopy::testing
{
namespace
{

using Point = std::array<double, 3>;
using Plane = std::array<double, 4>; // a x + b y + c z + d >= 0 inside

/// VTK's own frustum planes for the view (an independent implementation).
std::vector<Plane> vtkFrustum(const View& v)
{
  vtkSmartPointer<vtkCamera> camera = cameraFor(v, 1e9);
  double planes[24];
  camera->GetFrustumPlanes(static_cast<double>(v.width) / v.height, planes);
  std::vector<Plane> result;
  for (int p = 0; p < 4; ++p) // left, right, bottom, top (near/far are far away)
  {
    result.push_back({{planes[4 * p], planes[4 * p + 1], planes[4 * p + 2], planes[4 * p + 3]}});
  }
  return result;
}

double polygonArea(const std::vector<Point>& polygon)
{
  // Fan from the first vertex, in coordinates relative to it (large offsets).
  Point sum{{0, 0, 0}};
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
  {
    const Point& o = polygon[0];
    const Point p{{polygon[i][0] - o[0], polygon[i][1] - o[1], polygon[i][2] - o[2]}};
    const Point q{{polygon[i + 1][0] - o[0], polygon[i + 1][1] - o[1], polygon[i + 1][2] - o[2]}};
    sum[0] += p[1] * q[2] - p[2] * q[1];
    sum[1] += p[2] * q[0] - p[0] * q[2];
    sum[2] += p[0] * q[1] - p[1] * q[0];
  }
  return 0.5 * std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
}

std::vector<Point> clip(std::vector<Point> polygon, const std::vector<Plane>& planes)
{
  for (const Plane& h : planes)
  {
    std::vector<Point> out;
    for (std::size_t i = 0; i < polygon.size(); ++i)
    {
      const Point& p = polygon[i];
      const Point& q = polygon[(i + 1) % polygon.size()];
      const double fp = h[0] * p[0] + h[1] * p[1] + h[2] * p[2] + h[3];
      const double fq = h[0] * q[0] + h[1] * q[1] + h[2] * q[2] + h[3];
      if (fp >= 0)
      {
        out.push_back(p);
      }
      if ((fp > 0 && fq < 0) || (fp < 0 && fq > 0))
      {
        const double t = fp / (fp - fq);
        out.push_back(
            {{p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2])}});
      }
    }
    polygon = out;
    if (polygon.size() < 3)
    {
      return {};
    }
  }
  return polygon;
}

std::vector<Point> rectangle(const double b[6])
{
  // Corners of an axis-aligned rectangle with one flat axis, in order.
  int u = -1;
  int v = -1;
  for (int a = 0; a < 3; ++a)
  {
    if (b[2 * a + 1] > b[2 * a])
    {
      (u < 0 ? u : v) = a;
    }
  }
  Point lo{{b[0], b[2], b[4]}};
  std::vector<Point> r(4, lo);
  r[1][u] = b[2 * u + 1];
  r[2][u] = b[2 * u + 1];
  r[2][v] = b[2 * v + 1];
  r[3][v] = b[2 * v + 1];
  return r;
}

std::set<vtkIdType> bruteForceVisible(vtkHyperTreeGrid* htg, const View& view)
{
  const auto planes = vtkFrustum(view);
  std::set<vtkIdType> ids;
  for (const LeafBox& leaf : visibleLeafBoxes(htg))
  {
    const auto r = rectangle(leaf.bounds);
    const double area = polygonArea(r);
    if (polygonArea(clip(r, planes)) > 1e-12 * area)
    {
      ids.insert(leaf.global);
    }
  }
  return ids;
}

/// The paper's view of case A as a vtkCamera.
vtkSmartPointer<vtkCamera> paperCamera()
{
  auto camera = vtkSmartPointer<vtkCamera>::New();
  camera->SetPosition(0.75, 1.5, 10);
  camera->SetFocalPoint(0.75, 1.5, 0);
  camera->ParallelProjectionOn();
  camera->SetParallelScale(1);
  return camera;
}

View paperView()
{
  return View{{{0.75, 1.5, 10}}, {{0.75, 1.5, 0}}, {{0, 1, 0}}, true, 1.0, 400, 400};
}

TEST(AdaptiveSurface2D, PaperCaseAViewEmitsExactlyTheOverlappingLeaves)
{
  for (bool withMask : {false, true})
  {
    DescriptorForest forest(paperCaseA(withMask));
    auto htg = buildHyperTreeGrid(forest.description());
    const auto expected = bruteForceVisible(htg, paperView());
    auto surface = runSurface(htg, paperView(), true);
    const auto emitted = emittedIds(surface);
    EXPECT_EQ(emitted, expected);
    // The paper's conservative culling kept 67 (54 with the mask).
    std::cout << "case A" << (withMask ? " with mask" : "") << ": " << emitted.size()
              << " quads (paper, circle-based culling: " << (withMask ? 54 : 67) << ")\n";
    EXPECT_LT(emitted.size(), withMask ? 54u : 67u);
    EXPECT_GT(emitted.size(), 0u);
  }
}

TEST(AdaptiveSurface2D, OutputCarriesFieldsIdsLevelsAndDoublePoints)
{
  DescriptorForest forest(paperCaseA(true));
  auto htg = buildHyperTreeGrid(forest.description());
  auto surface = runSurface(htg, paperView(), false);
  ASSERT_GT(surface->GetNumberOfCells(), 0);
  EXPECT_EQ(surface->GetPoints()->GetDataType(), VTK_DOUBLE);
  auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
  auto* levels = vtkUnsignedCharArray::SafeDownCast(surface->GetCellData()->GetArray("Level"));
  vtkDataArray* depth = surface->GetCellData()->GetArray("Depth");
  ASSERT_NE(ids, nullptr);
  ASSERT_NE(levels, nullptr);
  ASSERT_NE(depth, nullptr);
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    // Depth (the field) equals the level of the node shown.
    EXPECT_EQ(depth->GetTuple1(c), forest.depth()[ids->GetValue(c)]);
    EXPECT_EQ(levels->GetValue(c), forest.depth()[ids->GetValue(c)]);
  }
}

/// A random 2D forest in a random plane with an offset origin, and a random view.
struct RandomCase
{
  std::unique_ptr<RandomForest> forest;
  vtkSmartPointer<vtkHyperTreeGrid> htg;
  View view;
};

RandomCase randomCase(std::uint64_t seed)
{
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  RandomForestOptions o;
  o.dimension = 2;
  o.branchFactor = seed % 3 == 0 ? 3 : 2;
  o.flatAxis = static_cast<int>(seed % 3);
  o.rootCells = {{4, 3, 5}};
  o.maxLevels = o.branchFactor == 2 ? 6 : 4;
  o.refineProbability = 0.45;
  o.maskProbability = seed % 2 ? 0.1 : 0.0;
  o.origin = {{-1e3 * unit(random), 500 * unit(random), 1e4 * unit(random)}};
  o.seed = seed;
  RandomCase c;
  c.forest = std::make_unique<RandomForest>(o);
  c.htg = buildHyperTreeGrid(c.forest->description());
  double b[6];
  c.htg->GetBounds(b);
  const int flat = o.flatAxis;
  Point focal;
  double extent = 0;
  for (int a = 0; a < 3; ++a)
  {
    focal[a] = b[2 * a] + unit(random) * (b[2 * a + 1] - b[2 * a]);
    extent = std::max(extent, b[2 * a + 1] - b[2 * a]);
  }
  // Direction: mostly along the plane's normal, tilted by up to 60 degrees.
  Point normal{{0, 0, 0}};
  normal[flat] = unit(random) < 0.5 ? 1 : -1;
  Point tilt{{unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5}};
  tilt[flat] = 0;
  const double t =
      std::tan(unit(random) * 60 * M_PI / 180) /
      std::max(1e-9, std::sqrt(tilt[0] * tilt[0] + tilt[1] * tilt[1] + tilt[2] * tilt[2]));
  const double distance = extent * (0.3 + 2 * unit(random));
  Point direction{{normal[0] + t * tilt[0], normal[1] + t * tilt[1], normal[2] + t * tilt[2]}};
  const double length = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] +
                                  direction[2] * direction[2]);
  for (int a = 0; a < 3; ++a)
  {
    c.view.position[a] = focal[a] + distance * direction[a] / length;
  }
  c.view.focal = focal;
  c.view.up = {{unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5}};
  c.view.parallel = seed % 4 < 2;
  c.view.scale = c.view.parallel ? extent * (0.02 + 0.6 * unit(random)) : 10 + 50 * unit(random);
  const int sizes[][2] = {{400, 400}, {640, 480}, {300, 900}, {1024, 256}};
  c.view.width = sizes[seed % 4][0];
  c.view.height = sizes[seed % 4][1];
  return c;
}

/// A 3 x 2 forest in the z = 0 plane, some cells masked: the full-surface tests'.
RandomForestOptions smallPlaneForest(int branchFactor, StorageOrder order, std::uint64_t seed)
{
  RandomForestOptions o;
  o.dimension = 2;
  o.branchFactor = branchFactor;
  o.rootCells = {{3, 2, 1}};
  o.maxLevels = branchFactor == 2 ? 6 : 4;
  o.order = order;
  o.maskProbability = 0.1;
  o.seed = seed;
  return o;
}

TEST(AdaptiveSurface2D, EveryQuadSitsOnItsCellInAnyStorageOrder)
{
  for (StorageOrder order : {StorageOrder::BreadthFirst, StorageOrder::DepthFirst})
  {
    for (int f : {2, 3})
    {
      RandomForest forest(smallPlaneForest(f, order, 11 + f));
      auto htg = buildHyperTreeGrid(forest.description());
      expectOneCellPerVisibleLeaf(htg, VTK_QUAD,
                                  "f " + std::to_string(f) +
                                      (order == StorageOrder::DepthFirst ? " depth first" : ""));
    }
  }
}

TEST(AdaptiveSurface2D, FullSurfaceFieldsAreTheSimulationsValuesInEveryLayout)
{
  // Depth-first storage: every field reads through the slot map (Canopy's own
  // array class), AoS, SoA, strided and of an integer type. Each quad's values
  // must be the simulation's at its cell's slot (value = 10 slot + component).
  for (int f : {2, 3})
  {
    RandomForest forest(smallPlaneForest(f, StorageOrder::DepthFirst, 31 + f));
    const std::size_t slots = forest.numberOfNodes();
    std::vector<double> vector3(3 * slots);
    std::vector<double> soa0(slots);
    std::vector<double> soa1(slots);
    struct Record
    {
      float pad;
      float value;
    };
    std::vector<Record> records(slots);
    std::vector<std::int32_t> integers(slots);
    for (std::size_t slot = 0; slot < slots; ++slot)
    {
      for (int c = 0; c < 3; ++c)
        vector3[3 * slot + c] = 10.0 * slot + c;
      soa0[slot] = 10.0 * slot;
      soa1[slot] = 10.0 * slot + 1;
      records[slot] = {-1.0f, static_cast<float>(10 * slot)};
      integers[slot] = static_cast<std::int32_t>(10 * slot);
    }
    ForestDescription& d = forest.description();
    d.fields.push_back(FieldDescription::aos("vector", vector3.data(), slots, 3));
    d.fields.push_back(FieldDescription::soa<double>("pair", {soa0.data(), soa1.data()}, slots));
    d.fields.push_back(
        FieldDescription::strided("strided", &records[0].value, sizeof(Record), slots));
    d.fields.push_back(FieldDescription::aos("integer", integers.data(), slots));
    auto htg = buildHyperTreeGrid(d);
    vtkSmartPointer<vtkPolyData> surface = fullSurface(htg);
    std::map<vtkIdType, std::int64_t> slotOfCell;
    for (std::size_t t = 0; t < forest.nodes().size(); ++t)
      for (std::size_t n = 0; n < forest.nodes()[t].size(); ++n)
        slotOfCell[forest.cellOf(t, n)] = forest.nodes()[t][n].slot;
    auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
    ASSERT_NE(ids, nullptr);
    ASSERT_GT(surface->GetNumberOfCells(), 20);
    for (const char* name : {"vector", "pair", "strided", "integer"})
    {
      vtkDataArray* values = surface->GetCellData()->GetArray(name);
      ASSERT_NE(values, nullptr) << name;
      ASSERT_EQ(values->GetNumberOfTuples(), surface->GetNumberOfCells()) << name;
      for (vtkIdType q = 0; q < surface->GetNumberOfCells(); ++q)
      {
        const double slot = static_cast<double>(slotOfCell.at(ids->GetValue(q)));
        for (int c = 0; c < values->GetNumberOfComponents(); ++c)
        {
          ASSERT_EQ(values->GetComponent(q, c), 10.0 * slot + c)
              << name << " quad " << q << " component " << c << " (f = " << f << ")";
        }
      }
    }
  }
}

TEST(AdaptiveSurface2D, CellsStayRightAcrossExecutionsThatGrowAndShrink)
{
  // The filter keeps its connectivity between executions and writes only what
  // a longer output adds: after every execution, whatever the order of sizes,
  // each quad must use its own points (four, or more with finer neighbours'
  // corners on its edges), right after the previous quad's, and sit on its cell.
  RandomForestOptions o;
  o.dimension = 2;
  o.rootCells = {{4, 4, 1}};
  o.maxLevels = 6;
  o.refineProbability = 0.6;
  o.seed = 5;
  RandomForest forest(o);
  auto htg = buildHyperTreeGrid(forest.description());
  std::map<vtkIdType, LeafBox> byId;
  for (const LeafBox& leaf : visibleLeafBoxes(htg))
  {
    byId[leaf.global] = leaf;
  }
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->SetLevelOfDetail(false);
  filter->SetViewportSize(400, 400);
  filter->SetCameraPosition(2, 2, 10);
  filter->SetCameraFocalPoint(2, 2, 0);
  std::set<vtkIdType> sizes;
  for (double scale : {0.3, 2.5, 0.7, 0.2, 1.2, 2.5})
  {
    filter->SetParallelScale(scale);
    filter->Update();
    vtkPolyData* surface = filter->GetPolyDataOutput();
    const vtkIdType quads = surface->GetNumberOfCells();
    sizes.insert(quads);
    auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
    ASSERT_NE(ids, nullptr);
    vtkNew<vtkIdList> points;
    vtkIdType next = 0;
    for (vtkIdType q = 0; q < quads; ++q)
    {
      surface->GetPolys()->GetCellAtId(q, points);
      ASSERT_GE(points->GetNumberOfIds(), 4) << "scale " << scale << " quad " << q;
      for (vtkIdType k = 0; k < points->GetNumberOfIds(); ++k)
      {
        ASSERT_EQ(points->GetId(k), next + k) << "scale " << scale << " quad " << q;
      }
      next += points->GetNumberOfIds();
      rectangleOf(cellPoints(surface, q), "scale " + std::to_string(scale));
      double b[6];
      surface->GetCell(q)->GetBounds(b);
      const LeafBox& leaf = byId.at(ids->GetValue(q));
      for (int i = 0; i < 6; ++i)
      {
        ASSERT_NEAR(b[i], leaf.bounds[i], 1e-12) << "scale " << scale << " quad " << q;
      }
    }
    EXPECT_EQ(next, surface->GetNumberOfPoints()) << "scale " << scale;
  }
  EXPECT_GE(sizes.size(), 4u) << "the views must give outputs of different sizes";
}

TEST(AdaptiveSurface2D, EdgesCarryTheCornersOfFinerNeighbours)
{
  // Where a quad meets finer ones (a T-junction), their corners lie on its edge
  // and it is drawn as a polygon through them. With level of detail at several
  // thresholds and culling off (every neighbour drawn), a quad's points other
  // than its corners are exactly the other quads' corners inside its edges;
  // with culling, at least those (full surfaces: SurfaceRuns.h).
  std::size_t vertices = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed)
  {
    RandomCase c = randomCase(seed);
    for (bool cull : {false, true})
    {
      for (double threshold : {1.0, 4.0, 16.0})
      {
        vtkNew<vtkCanopyAdaptiveSurface> filter;
        filter->SetInputData(c.htg);
        filter->SetCameraPosition(c.view.position.data());
        filter->SetCameraFocalPoint(c.view.focal.data());
        filter->SetCameraViewUp(c.view.up.data());
        filter->SetParallelProjection(c.view.parallel);
        if (c.view.parallel)
        {
          filter->SetParallelScale(c.view.scale);
        }
        else
        {
          filter->SetViewAngle(c.view.scale);
        }
        filter->SetViewportSize(c.view.width, c.view.height);
        filter->SetViewCulling(cull);
        filter->SetPixelThreshold(threshold);
        filter->Update();
        vertices += expectEdgeVerticesAreNeighboursCorners(
            filter->GetPolyDataOutput(),
            "seed " + std::to_string(seed) + (cull ? ", culled" : "") + ", threshold " +
                std::to_string(threshold),
            !cull);
      }
    }
  }
  EXPECT_GT(vertices, 1000u) << "these forests should have many T-junctions";
}

TEST(AdaptiveSurface2D, RandomViewsEmitExactlyTheOverlappingLeaves)
{
  int nonTrivial = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed)
  {
    RandomCase c = randomCase(seed);
    const auto expected = bruteForceVisible(c.htg, c.view);
    const auto emitted = emittedIds(runSurface(c.htg, c.view, false));
    EXPECT_EQ(emitted, expected) << "seed " << seed;
    nonTrivial += !expected.empty() && expected.size() < visibleLeafBoxes(c.htg).size();
  }
  // Most views must cut through the grid, or the test proves little.
  EXPECT_GE(nonTrivial, 20);
}

TEST(AdaptiveSurface2D, LevelOfDetailStopsAtTheFirstNodeBelowThreshold)
{
  int coarseEmitted = 0;
  for (std::uint64_t seed = 101; seed <= 120; ++seed)
  {
    RandomCase c = randomCase(seed);
    c.view.width /= 8; // coarse viewports so that level of detail engages
    c.view.height /= 8;
    const double threshold = 2.5;
    auto surface = runSurface(c.htg, c.view, true, threshold);
    auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
    for (vtkIdType q = 0; q < surface->GetNumberOfCells(); ++q)
    {
      double b[6];
      surface->GetCell(q)->GetBounds(b);
      const vtkIdType global = ids->GetValue(q);
      // Find the node: it is a leaf, or its footprint is at most the threshold.
      bool leaf = false;
      for (std::size_t t = 0; t < c.forest->nodes().size(); ++t)
      {
        for (std::size_t n = 0; n < c.forest->nodes()[t].size(); ++n)
        {
          if (c.forest->cellOf(t, n) == global)
          {
            leaf = c.forest->refinement()[t][n] == 0;
          }
        }
      }
      const double footprint = vtkFootprint(c.view, b);
      if (!leaf)
      {
        ++coarseEmitted;
        EXPECT_LE(footprint, threshold * (1 + 1e-9)) << "seed " << seed;
      }
    }
  }
  EXPECT_GT(coarseEmitted, 20) << "level of detail must actually stop above the leaves";
}

TEST(AdaptiveSurface2D, ConsumersKeepTheirDataWhenTheFilterReexecutes)
{
  DescriptorForest forest(paperCaseA(false));
  auto htg = buildHyperTreeGrid(forest.description());
  vtkSmartPointer<vtkCamera> camera = paperCamera();
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->SetCamera(camera);
  filter->SetViewportSize(400, 400);
  filter->Update();
  // A consumer keeps a shallow copy of two output arrays (shares their memory).
  vtkNew<vtkIdTypeArray> kept;
  kept->ShallowCopy(filter->GetPolyDataOutput()->GetCellData()->GetArray("OriginalCellId"));
  vtkNew<vtkDoubleArray> keptDepth;
  keptDepth->ShallowCopy(filter->GetPolyDataOutput()->GetCellData()->GetArray("Depth"));
  std::vector<vtkIdType> before(kept->GetPointer(0),
                                kept->GetPointer(0) + kept->GetNumberOfTuples());
  std::vector<double> depthBefore(keptDepth->GetPointer(0),
                                  keptDepth->GetPointer(0) + keptDepth->GetNumberOfTuples());
  camera->SetFocalPoint(2.0, 2.5, 0);
  camera->SetPosition(2.0, 2.5, 10);
  filter->Update();
  EXPECT_EQ(
      std::vector<vtkIdType>(kept->GetPointer(0), kept->GetPointer(0) + kept->GetNumberOfTuples()),
      before);
  EXPECT_EQ(std::vector<double>(keptDepth->GetPointer(0),
                                keptDepth->GetPointer(0) + keptDepth->GetNumberOfTuples()),
            depthBefore);
  // And the new output's cached range is the new one.
  double range[2];
  filter->GetPolyDataOutput()->GetCellData()->GetArray("Depth")->GetRange(range);
  double expected[2] = {1e300, -1e300};
  vtkDataArray* depth = filter->GetPolyDataOutput()->GetCellData()->GetArray("Depth");
  for (vtkIdType i = 0; i < depth->GetNumberOfTuples(); ++i)
  {
    expected[0] = std::min(expected[0], depth->GetTuple1(i));
    expected[1] = std::max(expected[1], depth->GetTuple1(i));
  }
  EXPECT_EQ(range[0], expected[0]);
  EXPECT_EQ(range[1], expected[1]);
}

TEST(AdaptiveSurface2D, FollowsTheRendererAndDoesNotKeepItAlive)
{
  DescriptorForest forest(paperCaseA(false));
  auto htg = buildHyperTreeGrid(forest.description());
  bool filterDeleted = false;
  {
    vtkNew<vtkRenderer> renderer;
    renderer->SetActiveCamera(paperCamera());
    vtkNew<vtkCanopyAdaptiveSurface> filter;
    vtkNew<vtkCallbackCommand> onDelete;
    onDelete->SetClientData(&filterDeleted);
    onDelete->SetCallback([](vtkObject*, unsigned long, void* data, void*)
                          { *static_cast<bool*>(data) = true; });
    filter->AddObserver(vtkCommand::DeleteEvent, onDelete);
    filter->SetInputData(htg);
    filter->SetRenderer(renderer);
    // The usual cycle: renderer -> actor -> mapper -> filter -> renderer.
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(filter->GetOutputPort());
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    renderer->AddActor(actor);
    // No window: the renderer reports size 0, so use a camera-only check.
    filter->ViewDependentOff();
    filter->Update();
    const vtkMTimeType before = filter->GetMTime();
    // Swapping in an older camera must still count as a change.
    vtkNew<vtkCamera> b;
    renderer->SetActiveCamera(b);
    EXPECT_GT(filter->GetMTime(), before);
  }
  EXPECT_TRUE(filterDeleted) << "a renderer must not keep the filter alive";
}

TEST(AdaptiveSurface2D, LevelOfDetailMatchesTheClosedForm)
{
  // A uniformly refined grid of square roots.
  expectLevelsMatchClosedForm(2);
}

TEST(AdaptiveSurface2D, EmittedCellsTileTheVisibleDomain)
{
  for (std::uint64_t seed = 201; seed <= 230; ++seed)
  {
    if (seed % 2)
    {
      continue; // unmasked forests only: masked holes are not tiled
    }
    RandomCase c = randomCase(seed);
    double b[6];
    c.htg->GetBounds(b);
    for (bool lod : {false, true})
    {
      View v = c.view;
      v.width /= lod ? 16 : 1;
      v.height /= lod ? 16 : 1;
      const auto planes = vtkFrustum(v);
      const double visibleDomain = polygonArea(clip(rectangle(b), planes));
      auto surface = runSurface(c.htg, v, lod);
      double covered = 0;
      for (vtkIdType q = 0; q < surface->GetNumberOfCells(); ++q)
      {
        double qb[6];
        surface->GetCell(q)->GetBounds(qb);
        covered += polygonArea(clip(rectangle(qb), planes));
      }
      // Only trees present in the forest count; this forest has every root.
      EXPECT_NEAR(covered, visibleDomain,
                  1e-9 * (b[1] - b[0] + b[3] - b[2] + b[5] - b[4]) *
                      (b[1] - b[0] + b[3] - b[2] + b[5] - b[4]))
          << "seed " << seed << (lod ? " with" : " without") << " level of detail";
    }
  }
}

TEST(AdaptiveSurface2D, InvalidSettingsAreReportedNotCrashed)
{
  DescriptorForest forest(paperCaseA(false));
  auto htg = buildHyperTreeGrid(forest.description());
  struct Bad
  {
    const char* what;
    std::function<void(vtkCanopyAdaptiveSurface*)> apply;
  };
  const std::vector<Bad> cases{
      {"threshold 0", [](vtkCanopyAdaptiveSurface* f) { f->SetPixelThreshold(0); }},
      {"threshold NaN", [](vtkCanopyAdaptiveSurface* f) { f->SetPixelThreshold(std::nan("")); }},
      {"zero viewport", [](vtkCanopyAdaptiveSurface* f) { f->SetViewportSize(0, 400); }},
      {"camera at focal point",
       [](vtkCanopyAdaptiveSurface* f) { f->SetCameraPosition(0.75, 1.5, 0); }},
      {"view up along the view", [](vtkCanopyAdaptiveSurface* f) { f->SetCameraViewUp(0, 0, 1); }},
      {"zero parallel scale", [](vtkCanopyAdaptiveSurface* f) { f->SetParallelScale(0); }},
  };
  for (const Bad& bad : cases)
  {
    vtkNew<vtkCanopyAdaptiveSurface> filter;
    filter->SetInputData(htg);
    const View v = paperView();
    filter->SetCameraPosition(v.position.data());
    filter->SetCameraFocalPoint(v.focal.data());
    filter->SetViewportSize(400, 400);
    bad.apply(filter);
    EXPECT_GE(errorsOfUpdate(filter).size(), 1u) << bad.what;
    EXPECT_EQ(filter->GetPolyDataOutput()->GetNumberOfCells(), 0) << bad.what;
  }
}

TEST(AdaptiveSurface2D, ReexecutesOnlyWhenSomethingChanged)
{
  DescriptorForest forest(paperCaseA(false));
  auto htg = buildHyperTreeGrid(forest.description());
  vtkSmartPointer<vtkCamera> camera = paperCamera();
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->SetCamera(camera);
  filter->SetViewportSize(400, 400);
  int executions = 0;
  vtkNew<vtkCallbackCommand> onStart;
  onStart->SetClientData(&executions);
  onStart->SetCallback([](vtkObject*, unsigned long, void* data, void*)
                       { ++*static_cast<int*>(data); });
  filter->AddObserver(vtkCommand::StartEvent, onStart);
  filter->Update();
  filter->Update();
  EXPECT_EQ(executions, 1);
  const vtkIdType before = filter->GetPolyDataOutput()->GetNumberOfCells();
  camera->SetParallelScale(0.25); // zoom in: fewer cells
  filter->Update();
  EXPECT_EQ(executions, 2);
  EXPECT_LT(filter->GetPolyDataOutput()->GetNumberOfCells(), before);
  filter->SetViewportSize(100, 100);
  filter->Update();
  EXPECT_EQ(executions, 3);
  filter->SetPixelThreshold(2);
  filter->Update();
  EXPECT_EQ(executions, 4);
  filter->Update();
  EXPECT_EQ(executions, 4);
}

/// One 2D tree refined down to `depth` levels along the point `target` (one
/// refined child per level), on a root cell [origin, origin + size]^2.
struct DeepTree
{
  std::array<double, 2> x;
  std::array<double, 2> y;
  std::array<double, 1> z{{0.0}};
  std::vector<std::uint8_t> refinement;
  ForestDescription d;

  DeepTree(double origin, double size, int depth, double tx, double ty)
      : x{{origin, origin + size}}, y{{origin, origin + size}}
  {
    // Breadth-first: root, then 4 children per level, one of them refined.
    refinement.push_back(1);
    double lo[2] = {origin, origin};
    double s = size;
    for (int level = 1; level < depth; ++level)
    {
      s /= 2;
      const int cx = tx >= lo[0] + s ? 1 : 0;
      const int cy = ty >= lo[1] + s ? 1 : 0;
      lo[0] += cx * s;
      lo[1] += cy * s;
      for (int c = 0; c < 4; ++c)
      {
        refinement.push_back(level + 1 < depth && c == cx + 2 * cy ? 1 : 0);
      }
    }
    d.dimension = 2;
    d.branchFactor = 2;
    d.maxLevels = depth;
    d.rootGrid = {x.data(), y.data(), z.data(), 2, 2, 1};
    TreeDescription t;
    t.refinement = refinement.data();
    t.numberOfNodes = refinement.size();
    d.trees.push_back(t);
  }
};

/// For a parallel camera looking down -z with view up +y, the view region in the
/// XY plane is the rectangle focal +- (scale * aspect, scale): exact reference
/// without VTK's projection matrices (which lose precision at extreme scales).
std::set<vtkIdType> axisAlignedReference(vtkHyperTreeGrid* htg, const View& v)
{
  const double halfWidth = v.scale * v.width / v.height;
  const double halfHeight = v.scale;
  std::set<vtkIdType> ids;
  for (const LeafBox& leaf : visibleLeafBoxes(htg))
  {
    // Positive-area overlap, computed relative to the focal point.
    const double x0 = leaf.bounds[0] - v.focal[0];
    const double x1 = leaf.bounds[1] - v.focal[0];
    const double y0 = leaf.bounds[2] - v.focal[1];
    const double y1 = leaf.bounds[3] - v.focal[1];
    if (x0 < halfWidth && x1 > -halfWidth && y0 < halfHeight && y1 > -halfHeight)
    {
      ids.insert(leaf.global);
    }
  }
  return ids;
}

/// Emitted cells equal the exact reference and their corners equal VTK's exact
/// dyadic bounds (to the last bit).
void expectExactDeepView(const DeepTree& tree, double tx, double ty,
                         const std::vector<double>& scales)
{
  auto htg = buildHyperTreeGrid(tree.d);
  const auto leaves = visibleLeafBoxes(htg);
  for (double scale : scales)
  {
    const View v{{{tx, ty, 10}}, {{tx, ty, 0}}, {{0, 1, 0}}, true, scale, 640, 480};
    const auto expected = axisAlignedReference(htg, v);
    EXPECT_FALSE(expected.empty());
    auto surface = runSurface(htg, v, false);
    EXPECT_EQ(emittedIds(surface), expected) << "scale " << scale;
    auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
    for (vtkIdType q = 0; q < surface->GetNumberOfCells(); ++q)
    {
      const auto leaf =
          std::find_if(leaves.begin(), leaves.end(),
                       [&](const LeafBox& l) { return l.global == ids->GetValue(q); });
      ASSERT_NE(leaf, leaves.end());
      double b[6];
      surface->GetCell(q)->GetBounds(b);
      for (int i = 0; i < 4; ++i)
      {
        // Dyadic positions are representable here: both must be exact.
        ASSERT_EQ(b[i], leaf->bounds[i]) << "bound " << i << " at level " << leaf->level;
      }
    }
  }
}

TEST(AdaptiveSurfaceStress, Depth30TreeIsExact)
{
  // 31 levels: cells of 2^-30 of the root, down to scales of 1e-9.
  const DeepTree tree(0.0, 1.0, 31, 0.3, 0.7);
  expectExactDeepView(tree, 0.3, 0.7, {1e-9, 1e-6, 1e-3, 1.0});
}

TEST(AdaptiveSurfaceStress, DomainOffsetBy1e9IsExact)
{
  // At 1e9 a double resolves 2^-23; 21 levels (cells of 2^-20) stay exact.
  const double origin = 1e9;
  const DeepTree tree(origin, 1.0, 21, origin + 0.3, origin + 0.7);
  expectExactDeepView(tree, origin + 0.3, origin + 0.7, {1e-5, 1e-3, 1.0});
}

TEST(AdaptiveSurfaceStress, ExtremeScalesAndViewportsMatchBruteForce)
{
  DescriptorForest forest(paperCaseA(true));
  auto htg = buildHyperTreeGrid(forest.description());
  for (double scale : {1e-9, 1e-3, 1.0, 1e3, 1e9})
  {
    for (int size : {1, 7, 400, 16384})
    {
      const View v{{{0.75, 1.5, 10}}, {{0.75, 1.5, 0}}, {{0, 1, 0}}, true, scale, size, size};
      EXPECT_EQ(emittedIds(runSurface(htg, v, false)), axisAlignedReference(htg, v))
          << "scale " << scale << " viewport " << size;
      // With level of detail: never more cells than without, never empty when visible.
      auto lod = runSurface(htg, v, true);
      EXPECT_LE(lod->GetNumberOfCells(), runSurface(htg, v, false)->GetNumberOfCells());
      EXPECT_GT(lod->GetNumberOfCells(), 0);
    }
  }
}

TEST(AdaptiveSurfaceStress, CameraLookingAlongThePlane)
{
  DescriptorForest forest(paperCaseA(false));
  auto htg = buildHyperTreeGrid(forest.description());
  const std::vector<View> views{
      {{{-5, 1.5, 0}}, {{0.75, 1.5, 0}}, {{0, 0, 1}}, true, 1.0, 400, 300},
      {{{-5, 1.5, 0}}, {{0.75, 1.5, 0}}, {{0, 0, 1}}, false, 30.0, 400, 300},
      {{{0.75, -4, 0.001}}, {{0.75, 1.5, 0}}, {{0, 0, 1}}, false, 45.0, 640, 480},
  };
  for (const View& v : views)
  {
    EXPECT_EQ(emittedIds(runSurface(htg, v, false)), bruteForceVisible(htg, v));
    runSurface(htg, v, true); // level of detail seen edge-on: no crash
  }
}

TEST(AdaptiveSurfaceStress, NonFiniteFieldValuesPassThrough)
{
  DescriptorForest forest(paperCaseA(false));
  std::vector<double> weird(forest.numberOfNodes(), 1.0);
  weird[0] = std::nan("");
  weird[5] = std::numeric_limits<double>::infinity();
  weird[9] = -std::numeric_limits<double>::infinity();
  forest.description().fields.push_back(FieldDescription::aos("weird", weird.data(), weird.size()));
  auto htg = buildHyperTreeGrid(forest.description());
  View v = paperView();
  v.scale = 10; // everything in view
  auto surface = runSurface(htg, v, false);
  EXPECT_EQ(surface->GetNumberOfCells(), 75);
  auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
  vtkDataArray* out = surface->GetCellData()->GetArray("weird");
  for (vtkIdType q = 0; q < surface->GetNumberOfCells(); ++q)
  {
    const double expected = weird[static_cast<std::size_t>(ids->GetValue(q))];
    const double got = out->GetTuple1(q);
    EXPECT_TRUE((std::isnan(expected) && std::isnan(got)) || expected == got);
  }
}

TEST(AdaptiveSurfaceStress, OutputIsIdenticalForAnyThreadCount)
{
  RandomCase c = randomCase(7);
  View v = c.view;
  auto run = [&](const char* backend, int threads)
  {
    vtkSMPTools::SetBackend(backend);
    vtkSMPTools::Initialize(threads);
    auto surface = runSurface(c.htg, v, true);
    std::vector<double> points(static_cast<std::size_t>(3 * surface->GetNumberOfPoints()));
    for (vtkIdType p = 0; p < surface->GetNumberOfPoints(); ++p)
    {
      surface->GetPoint(p, &points[static_cast<std::size_t>(3 * p)]);
    }
    return points;
  };
  // VTK keeps the thread count of the first Initialize: 1 (Sequential) and 2.
  const auto sequential = run("Sequential", 1);
  ASSERT_FALSE(sequential.empty());
  EXPECT_EQ(run("STDThread", 2), sequential);
  vtkSMPTools::SetBackend("Sequential");
}

} // namespace
} // namespace canopy::testing
