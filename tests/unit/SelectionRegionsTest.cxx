// Selection by box and by frustum against brute force: every visible leaf (VTK's
// cursors) is measured inside the region by clipping (ConvexClip.h) and selected
// when the part has positive length, area or volume in the grid's dimension.
// Random 2D (each plane) and 3D forests, binary and ternary, masked, with holes,
// both storage orders; random boxes and the frusta of random perspective and
// parallel vtkCameras (GetFrustumPlanes, and the corners of the same frustum);
// both output modes; ids and counts exactly equal.
#include "ConvexClip.h"
#include "ErrorMessages.h"
#include "HtgWalk.h"
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyExtractSelection.h>

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkMatrix4x4.h>
#include <vtkSelection.h>
#include <vtkSelectionNode.h>
#include <vtkUnstructuredGrid.h>

#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <set>
#include <sstream>
#include <string>

namespace canopy::testing
{
namespace
{

using Box = std::array<double, 6>;

/// Which leaves a filter configured by `configure` selects, in one output mode:
/// OriginalCellId of the cells (each once), or the visible leaves of the masked grid.
std::set<vtkIdType> selected(vtkHyperTreeGrid* htg,
                             const std::function<void(vtkCanopyExtractSelection*)>& configure,
                             bool preserveTopology)
{
  vtkNew<vtkCanopyExtractSelection> filter;
  filter->SetInputData(htg);
  filter->SetPreserveTopology(preserveTopology);
  configure(filter);
  filter->Update();
  std::set<vtkIdType> ids;
  if (preserveTopology)
  {
    auto* out = vtkHyperTreeGrid::SafeDownCast(filter->GetOutput());
    EXPECT_NE(out, nullptr);
    for (const LeafBox& leaf : visibleLeafBoxes(out))
    {
      ids.insert(leaf.global);
    }
    return ids;
  }
  auto* out = vtkUnstructuredGrid::SafeDownCast(filter->GetOutput());
  auto* original = vtkIdTypeArray::SafeDownCast(out->GetCellData()->GetArray("OriginalCellId"));
  EXPECT_NE(original, nullptr);
  for (vtkIdType c = 0; original && c < original->GetNumberOfTuples(); ++c)
  {
    ids.insert(original->GetValue(c));
  }
  EXPECT_EQ(static_cast<vtkIdType>(ids.size()), out->GetNumberOfCells()) << "a cell twice";
  return ids;
}

/// Brute force for a box: positive-length overlap on every axis along which the
/// leaf has extent (the flat axes of 2D grids are ignored).
std::set<vtkIdType> expectedInBox(vtkHyperTreeGrid* htg, const Box& box)
{
  std::set<vtkIdType> ids;
  for (const LeafBox& leaf : visibleLeafBoxes(htg))
  {
    bool overlaps = true;
    for (int a = 0; a < 3 && overlaps; ++a)
    {
      const double lo = leaf.bounds[2 * a];
      const double hi = leaf.bounds[2 * a + 1];
      overlaps =
          lo == hi || (lo < box[2 * a + 1] && box[2 * a] < hi && box[2 * a] < box[2 * a + 1]);
    }
    if (overlaps)
    {
      ids.insert(leaf.global);
    }
  }
  return ids;
}

/// Brute force for planes: the clipped part of the leaf has positive measure in
/// the leaf's own dimension (a rectangle in its plane, a box in 3D).
std::set<vtkIdType> expectedInPlanes(vtkHyperTreeGrid* htg, const std::vector<ClipPlane>& planes)
{
  std::set<vtkIdType> ids;
  for (const LeafBox& leaf : visibleLeafBoxes(htg))
  {
    const double* b = leaf.bounds;
    std::vector<int> active;
    for (int a = 0; a < 3; ++a)
    {
      if (b[2 * a + 1] > b[2 * a])
      {
        active.push_back(a);
      }
    }
    double whole = 0;
    double inside = 0;
    const ClipPoint lo{{b[0], b[2], b[4]}};
    if (active.size() == 3)
    {
      whole = (b[1] - b[0]) * (b[3] - b[2]) * (b[5] - b[4]);
      inside = clippedVolume(b, planes);
    }
    else if (active.size() == 2)
    {
      const int u = active[0];
      const int v = active[1];
      std::vector<ClipPoint> rectangle(4, lo);
      rectangle[1][u] = b[2 * u + 1];
      rectangle[2][u] = b[2 * u + 1];
      rectangle[2][v] = b[2 * v + 1];
      rectangle[3][v] = b[2 * v + 1];
      whole = polygonArea(rectangle);
      inside = clippedArea(rectangle, planes);
    }
    else
    {
      ClipPoint hi = lo;
      hi[active[0]] = b[2 * active[0] + 1];
      whole = b[2 * active[0] + 1] - b[2 * active[0]];
      inside = clippedLength(lo, hi, planes);
    }
    if (inside > 1e-12 * whole)
    {
      ids.insert(leaf.global);
    }
  }
  return ids;
}

RandomForestOptions randomOptions(std::uint64_t seed, int dimension)
{
  RandomForestOptions o;
  o.dimension = dimension;
  o.flatAxis = static_cast<int>(seed % 3);
  o.activeAxis = static_cast<int>(seed % 3);
  o.branchFactor = seed % 2 ? 3 : 2;
  o.rootCells = dimension == 3 ? std::array<std::size_t, 3>{{3, 2, 2}}
                               : std::array<std::size_t, 3>{{4, 3, 5}};
  const int binaryLevels[4] = {0, 9, 7, 5};
  const int ternaryLevels[4] = {0, 6, 4, 3};
  o.maxLevels = (o.branchFactor == 2 ? binaryLevels : ternaryLevels)[dimension];
  o.refineProbability = 0.5;
  o.maskProbability = seed % 4 < 2 ? 0.12 : 0.0;
  o.skipEveryOtherRoot = seed % 5 == 0;
  o.order = seed % 3 == 1 ? StorageOrder::DepthFirst : StorageOrder::BreadthFirst;
  o.origin = {{-20.5 + seed, 3e3, -1e2 * static_cast<double>(seed % 7)}};
  o.seed = seed;
  return o;
}

/// A random camera around the grid and its frustum; near and far planes cut
/// through the grid so they matter.
struct RandomFrustum
{
  vtkSmartPointer<vtkCamera> camera;
  double aspect = 1;
  std::vector<ClipPlane> planes;
  std::array<ClipPoint, 8> corners; ///< vtkSelectionNode::FRUSTUM's order
};

RandomFrustum randomFrustum(const double b[6], std::mt19937_64& random, bool parallel,
                            int flatAxis /* -1 in 3D */)
{
  std::uniform_real_distribution<double> unit(0, 1);
  double extent = 0;
  ClipPoint focal;
  for (int a = 0; a < 3; ++a)
  {
    focal[a] = b[2 * a] + unit(random) * (b[2 * a + 1] - b[2 * a]);
    extent = std::max(extent, b[2 * a + 1] - b[2 * a]);
  }
  ClipPoint direction{{unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5}};
  if (flatAxis >= 0)
  {
    // Mostly across the plane: tilted by up to about 60 degrees from its normal.
    direction[flatAxis] = (unit(random) < 0.5 ? 1 : -1) * (0.6 + unit(random));
  }
  const double length = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] +
                                  direction[2] * direction[2]);
  const double distance = extent * (0.4 + 2 * unit(random));
  RandomFrustum f;
  f.camera = vtkSmartPointer<vtkCamera>::New();
  f.camera->SetFocalPoint(focal.data());
  f.camera->SetPosition(focal[0] + distance * direction[0] / length,
                        focal[1] + distance * direction[1] / length,
                        focal[2] + distance * direction[2] / length);
  f.camera->SetViewUp(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5);
  f.camera->OrthogonalizeViewUp();
  f.camera->SetParallelProjection(parallel);
  f.camera->SetParallelScale(extent * (0.05 + 0.45 * unit(random)));
  f.camera->SetViewAngle(10 + 50 * unit(random));
  f.camera->SetClippingRange(distance * (0.3 + 0.65 * unit(random)),
                             distance * (1.05 + 0.8 * unit(random)));
  f.aspect = 0.5 + 1.5 * unit(random);
  double planes[24];
  f.camera->GetFrustumPlanes(f.aspect, planes);
  for (int p = 0; p < 6; ++p)
  {
    f.planes.push_back({{planes[4 * p], planes[4 * p + 1], planes[4 * p + 2], planes[4 * p + 3]}});
  }
  // Corners: the normalized-device-coordinate cube's corners mapped back (bit 0
  // far, bit 1 upper, bit 2 right).
  vtkNew<vtkMatrix4x4> inverse;
  vtkMatrix4x4::Invert(f.camera->GetCompositeProjectionTransformMatrix(f.aspect, -1, 1), inverse);
  for (int c = 0; c < 8; ++c)
  {
    const double ndc[4] = {(c & 4) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 1) ? 1.0 : -1.0, 1};
    double world[4];
    inverse->MultiplyPoint(ndc, world);
    f.corners[c] = {{world[0] / world[3], world[1] / world[3], world[2] / world[3]}};
  }
  return f;
}

void useBox(vtkCanopyExtractSelection* filter, const double box[6])
{
  filter->SetSelectionMode(vtkCanopyExtractSelection::BOX);
  filter->SetBox(box);
}

void usePlanes(vtkCanopyExtractSelection* filter, const std::vector<ClipPlane>& planes)
{
  double values[24];
  for (int p = 0; p < 6; ++p)
  {
    for (int k = 0; k < 4; ++k)
    {
      values[4 * p + k] = planes[p][k];
    }
  }
  filter->SetSelectionMode(vtkCanopyExtractSelection::FRUSTUM);
  filter->SetFrustumPlanes(values);
}

/// Input 1: a FRUSTUM node as ParaView's rubber band makes it, 8 tuples x y z w.
vtkSmartPointer<vtkSelection> frustumSelection(const std::array<ClipPoint, 8>& corners)
{
  auto selection = vtkSmartPointer<vtkSelection>::New();
  vtkNew<vtkSelectionNode> node;
  node->SetContentType(vtkSelectionNode::FRUSTUM);
  node->SetFieldType(vtkSelectionNode::CELL);
  vtkNew<vtkDoubleArray> list;
  list->SetNumberOfComponents(4);
  for (const ClipPoint& c : corners)
  {
    list->InsertNextTuple4(c[0], c[1], c[2], 1.0);
  }
  node->SetSelectionList(list);
  selection->AddNode(node);
  return selection;
}

TEST(SelectionByBox, RandomBoxesEqualBruteForceIn2DAnd3D)
{
  int nonTrivial = 0;
  for (std::uint64_t seed = 1; seed <= 24; ++seed)
  {
    const int dimension = seed % 3 == 0 ? 3 : 2;
    RandomForest forest(randomOptions(seed, dimension));
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    Box box;
    for (int a = 0; a < 3; ++a)
    {
      const double size = b[2 * a + 1] - b[2 * a];
      double x = b[2 * a] - 0.2 * size + 1.4 * size * unit(random);
      double y = b[2 * a] - 0.2 * size + 1.4 * size * unit(random);
      if (size == 0)
      {
        // The flat axis of a 2D grid: a range away from the plane is ignored.
        x = b[2 * a] + 1 + unit(random);
        y = x + unit(random);
      }
      box[2 * a] = std::min(x, y);
      box[2 * a + 1] = std::max(x, y);
    }
    const auto expected = expectedInBox(htg, box);
    for (bool preserve : {false, true})
    {
      EXPECT_EQ(selected(
                    htg, [&](vtkCanopyExtractSelection* f) { useBox(f, box.data()); }, preserve),
                expected)
          << "seed " << seed << (preserve ? " (masked grid output)" : " (cells)");
    }
    nonTrivial += !expected.empty() && expected.size() < visibleLeafBoxes(htg).size();
  }
  EXPECT_GE(nonTrivial, 16);
}

TEST(SelectionByBox, BoxesOnAndJustOffRootCellBoundariesEqualBruteForce)
{
  // A masked selection marks a tree the box misses or holds whole without a
  // walk: boxes whose faces lie on root-cell boundaries, or a millionth of a
  // root cell inside or outside them, decide that exactly (inverted or not).
  int wholeTrees = 0;
  for (std::uint64_t seed = 1; seed <= 24; ++seed)
  {
    const int dimension = seed % 3 == 0 ? 3 : 2;
    RandomForestOptions o = randomOptions(seed, dimension);
    o.maskProbability = seed % 2 ? 0.0 : 0.05;
    // Binary trees over dyadic coordinates: the brute force's cell bounds (VTK's
    // cursor) are exact, so a face on a root boundary touches exactly.
    o.branchFactor = 2;
    o.maxLevels = dimension == 3 ? 5 : 7;
    RandomForest forest(o);
    auto& coords = const_cast<std::array<std::vector<double>, 3>&>(forest.coordinates());
    for (auto& axis : coords)
    {
      for (std::size_t i = 0; i < axis.size(); ++i)
      {
        axis[i] = 0.5 * static_cast<double>(i) - 1;
      }
    }
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    vtkDataArray* coordinates[3] = {htg->GetXCoordinates(), htg->GetYCoordinates(),
                                    htg->GetZCoordinates()};
    std::mt19937_64 random(seed);
    // On the boundary, a millionth of a root cell off it, or a third into the
    // next root cell (where a tree is neither missed nor held whole).
    const double offsets[5] = {-0.3, -1e-6, 0, 1e-6, 0.3};
    Box box;
    for (int a = 0; a < 3; ++a)
    {
      const vtkIdType points = coordinates[a]->GetNumberOfTuples();
      if (points < 2)
      {
        box[2 * a] = b[2 * a] - 1; // a flat axis: ignored
        box[2 * a + 1] = b[2 * a + 1] + 1;
        continue;
      }
      vtkIdType i = static_cast<vtkIdType>(random() % static_cast<std::uint64_t>(points));
      vtkIdType j = static_cast<vtkIdType>(random() % static_cast<std::uint64_t>(points));
      if (i > j)
        std::swap(i, j);
      if (i == j)
        j = std::min<vtkIdType>(points - 1, i + 1), i = j - 1;
      const double root = coordinates[a]->GetTuple1(1) - coordinates[a]->GetTuple1(0);
      box[2 * a] = coordinates[a]->GetTuple1(i) + offsets[random() % 5] * root;
      box[2 * a + 1] = coordinates[a]->GetTuple1(j) + offsets[random() % 5] * root;
    }
    // Trees the box holds or misses whole (along the active axes).
    for (const TreeDescription& tree : forest.description().trees)
    {
      double origin[3];
      double size[3];
      htg->GetLevelZeroOriginAndSizeFromIndex(tree.rootIndex, origin, size);
      bool holds = true;
      bool misses = false;
      for (int a = 0; a < 3; ++a)
      {
        if (size[a] > 0)
        {
          holds = holds && box[2 * a] <= origin[a] && origin[a] + size[a] <= box[2 * a + 1];
          misses = misses || origin[a] + size[a] <= box[2 * a] || box[2 * a + 1] <= origin[a];
        }
      }
      wholeTrees += holds || misses;
    }
    const auto inside = expectedInBox(htg, box);
    std::set<vtkIdType> outside;
    for (const LeafBox& leaf : visibleLeafBoxes(htg))
    {
      if (!inside.count(leaf.global))
        outside.insert(leaf.global);
    }
    for (bool invert : {false, true})
    {
      vtkNew<vtkCanopyExtractSelection> filter;
      filter->SetInputData(htg);
      filter->PreserveTopologyOn();
      useBox(filter, box.data());
      filter->SetInvert(invert);
      filter->Update();
      std::set<vtkIdType> got;
      for (const LeafBox& leaf :
           visibleLeafBoxes(vtkHyperTreeGrid::SafeDownCast(filter->GetOutput())))
      {
        got.insert(leaf.global);
      }
      EXPECT_EQ(got, invert ? outside : inside) << "seed " << seed << (invert ? " inverted" : "");
    }
  }
  EXPECT_GE(wholeTrees, 40) << "the boxes held or missed whole trees";
}

TEST(SelectionByBox, CellsTouchingTheBoxAreNotSelected)
{
  // Binary trees over dyadic coordinates: VTK's cursor bounds are exact, so a
  // box equal to a leaf's bounds touches its neighbours exactly.
  for (int dimension : {2, 3})
  {
    RandomForestOptions o = randomOptions(4, dimension);
    o.branchFactor = 2;
    o.maskProbability = 0;
    RandomForest forest(o);
    auto& coords = const_cast<std::array<std::vector<double>, 3>&>(forest.coordinates());
    for (int a = 0; a < 3; ++a)
    {
      for (std::size_t i = 0; i < coords[a].size(); ++i)
      {
        coords[a][i] = 0.75 * static_cast<double>(i) + (i % 2 ? 0.25 : 0.0);
      }
    }
    auto htg = buildHyperTreeGrid(forest.description());
    const auto leaves = visibleLeafBoxes(htg);
    int checked = 0;
    for (std::size_t i = 0; i < leaves.size(); i += leaves.size() / 17 + 1)
    {
      Box box;
      std::copy(leaves[i].bounds, leaves[i].bounds + 6, box.begin());
      const auto one = selected(
          htg, [&](vtkCanopyExtractSelection* f) { useBox(f, box.data()); }, false);
      EXPECT_EQ(one, std::set<vtkIdType>{leaves[i].global}) << "dimension " << dimension;
      // A box of zero thickness along an active axis has no volume: nothing.
      const int axis = dimension == 3 ? 1 : (o.flatAxis + 1) % 3;
      box[2 * axis + 1] = box[2 * axis] = 0.5 * (box[2 * axis] + box[2 * axis + 1]);
      auto flat = [&](bool preserve)
      {
        return selected(
            htg, [&](vtkCanopyExtractSelection* f) { useBox(f, box.data()); }, preserve);
      };
      EXPECT_TRUE(flat(false).empty());
      EXPECT_TRUE(flat(true).empty());
      ++checked;
    }
    EXPECT_GE(checked, 10);
    // The grid's own bounds select every visible leaf.
    double b[6];
    htg->GetBounds(b);
    EXPECT_EQ(selected(
                  htg, [&](vtkCanopyExtractSelection* f) { useBox(f, b); }, false)
                  .size(),
              leaves.size());
  }
}

TEST(SelectionByFrustum, CameraFrustaEqualBruteForceIn3D)
{
  int nonTrivial = 0;
  for (std::uint64_t seed = 1; seed <= 16; ++seed)
  {
    RandomForest forest(randomOptions(seed, 3));
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    std::mt19937_64 random(100 + seed);
    const RandomFrustum f = randomFrustum(b, random, seed % 2 == 0, -1);
    const auto expected = expectedInPlanes(htg, f.planes);
    for (bool preserve : {false, true})
    {
      EXPECT_EQ(selected(
                    htg, [&](vtkCanopyExtractSelection* filter) { usePlanes(filter, f.planes); },
                    preserve),
                expected)
          << "seed " << seed << (seed % 2 == 0 ? " parallel" : " perspective")
          << (preserve ? " (masked grid output)" : " (cells)");
    }
    nonTrivial += !expected.empty() && expected.size() < visibleLeafBoxes(htg).size();
  }
  EXPECT_GE(nonTrivial, 10);
}

TEST(SelectionByFrustum, CameraFrustaEqualBruteForceIn2D)
{
  int nonTrivial = 0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed)
  {
    RandomForest forest(randomOptions(seed, 2));
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    std::mt19937_64 random(200 + seed);
    const RandomFrustum f = randomFrustum(b, random, seed % 4 < 2, randomOptions(seed, 2).flatAxis);
    const auto expected = expectedInPlanes(htg, f.planes);
    for (bool preserve : {false, true})
    {
      EXPECT_EQ(selected(
                    htg, [&](vtkCanopyExtractSelection* filter) { usePlanes(filter, f.planes); },
                    preserve),
                expected)
          << "seed " << seed << (preserve ? " (masked grid output)" : " (cells)");
    }
    nonTrivial += !expected.empty() && expected.size() < visibleLeafBoxes(htg).size();
  }
  EXPECT_GE(nonTrivial, 15);
}

TEST(SelectionByFrustum, PlanesCornersAndVtkSelectionAgree)
{
  for (std::uint64_t seed = 1; seed <= 8; ++seed)
  {
    const int dimension = seed % 2 ? 3 : 2;
    RandomForest forest(randomOptions(seed, dimension));
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    std::mt19937_64 random(300 + seed);
    const RandomFrustum f = randomFrustum(b, random, seed % 4 == 0,
                                          dimension == 2 ? randomOptions(seed, 2).flatAxis : -1);
    const auto expected = expectedInPlanes(htg, f.planes);
    EXPECT_FALSE(expected.empty()) << "seed " << seed;
    const auto byCorners = selected(
        htg,
        [&](vtkCanopyExtractSelection* filter)
        {
          filter->SetSelectionMode(vtkCanopyExtractSelection::FRUSTUM);
          for (const ClipPoint& c : f.corners)
          {
            filter->AddFrustumCorner(c[0], c[1], c[2]);
          }
        },
        false);
    EXPECT_EQ(byCorners, expected) << "seed " << seed << ": corners";
    auto selection = frustumSelection(f.corners);
    for (bool preserve : {false, true})
    {
      EXPECT_EQ(selected(
                    htg,
                    [&](vtkCanopyExtractSelection* filter)
                    {
                      filter->SetInputData(1, selection);
                      // Input 1 takes precedence over the properties.
                      filter->SetSelectionMode(vtkCanopyExtractSelection::IDS);
                    },
                    preserve),
                expected)
          << "seed " << seed << ": vtkSelection";
    }
  }
}

TEST(SelectionByFrustum, SixAxisAlignedPlanesSelectWhatTheBoxSelects)
{
  for (std::uint64_t seed = 1; seed <= 10; ++seed)
  {
    const int dimension = seed % 2 ? 3 : 2;
    RandomForest forest(randomOptions(seed, dimension));
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    std::mt19937_64 random(400 + seed);
    std::uniform_real_distribution<double> unit(0, 1);
    Box box;
    std::vector<ClipPlane> planes;
    for (int a = 0; a < 3; ++a)
    {
      const double size = b[2 * a + 1] - b[2 * a];
      box[2 * a] = b[2 * a] - 0.1 * size + 0.5 * size * unit(random);
      box[2 * a + 1] = box[2 * a] + 0.2 * size + 0.5 * size * unit(random);
      if (size == 0)
      {
        // A frustum is cut by a 2D grid's plane: the box must contain it to agree.
        box[2 * a] = b[2 * a] - unit(random);
        box[2 * a + 1] = b[2 * a] + unit(random);
      }
      ClipPlane low{{0, 0, 0, -box[2 * a]}};
      low[a] = 1; // x >= xmin
      ClipPlane high{{0, 0, 0, box[2 * a + 1]}};
      high[a] = -1; // x <= xmax
      planes.push_back(low);
      planes.push_back(high);
    }
    const auto byBox = selected(
        htg, [&](vtkCanopyExtractSelection* f) { useBox(f, box.data()); }, false);
    EXPECT_FALSE(byBox.empty());
    EXPECT_EQ(selected(
                  htg, [&](vtkCanopyExtractSelection* f) { usePlanes(f, planes); }, false),
              byBox)
        << "seed " << seed;
  }
}

TEST(SelectionOnLines, BoxesAndFrustaEqualBruteForce)
{
  // 1D grids along x, y and z: a box's flat-axis extent is ignored, a frustum is
  // cut by the line; the leaves sharing a part of positive length are selected.
  int nonTrivialBoxes = 0;
  int nonTrivialFrusta = 0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed)
  {
    RandomForest forest(randomOptions(seed, 1));
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    const std::size_t visible = visibleLeafBoxes(htg).size();
    std::mt19937_64 random(500 + seed);
    std::uniform_real_distribution<double> unit(0, 1);
    Box box;
    for (int a = 0; a < 3; ++a)
    {
      const double size = std::max(b[2 * a + 1] - b[2 * a], 1.0);
      const double x = b[2 * a] - 0.2 * size + 1.4 * size * unit(random);
      const double y = b[2 * a] - 0.2 * size + 1.4 * size * unit(random);
      box[2 * a] = std::min(x, y);
      box[2 * a + 1] = std::max(x, y);
    }
    const auto inBox = expectedInBox(htg, box);
    const RandomFrustum f = randomFrustum(b, random, seed % 3 == 0, -1);
    const auto inFrustum = expectedInPlanes(htg, f.planes);
    for (bool preserve : {false, true})
    {
      EXPECT_EQ(selected(
                    htg, [&](vtkCanopyExtractSelection* filter) { useBox(filter, box.data()); },
                    preserve),
                inBox)
          << "seed " << seed << " box" << (preserve ? " (masked grid output)" : "");
      EXPECT_EQ(selected(
                    htg, [&](vtkCanopyExtractSelection* filter) { usePlanes(filter, f.planes); },
                    preserve),
                inFrustum)
          << "seed " << seed << " frustum" << (preserve ? " (masked grid output)" : "");
    }
    EXPECT_EQ(selected(
                  htg,
                  [&](vtkCanopyExtractSelection* filter)
                  {
                    filter->SetSelectionMode(vtkCanopyExtractSelection::FRUSTUM);
                    for (const ClipPoint& c : f.corners)
                    {
                      filter->AddFrustumCorner(c[0], c[1], c[2]);
                    }
                  },
                  false),
              inFrustum)
        << "seed " << seed << " corners";
    auto selection = frustumSelection(f.corners);
    EXPECT_EQ(selected(
                  htg,
                  [&](vtkCanopyExtractSelection* filter) { filter->SetInputData(1, selection); },
                  false),
              inFrustum)
        << "seed " << seed << " vtkSelection";
    nonTrivialBoxes += !inBox.empty() && inBox.size() < visible;
    nonTrivialFrusta += !inFrustum.empty() && inFrustum.size() < visible;
  }
  EXPECT_GE(nonTrivialBoxes, 15);
  EXPECT_GE(nonTrivialFrusta, 10);
}

TEST(SelectionByRegion, OnlySubtreesThatOverlapAreDescended)
{
  // Uniformly refined forests: a small region's selection must cost about what
  // it selects. Every node examined is a root or a child of an overlapping coarse
  // node, and each overlapping coarse node has a selected leaf below it.
  for (int dimension : {2, 3})
  {
    RandomForestOptions o;
    o.dimension = dimension;
    o.branchFactor = 2;
    o.rootCells = {{4, 4, 4}};
    o.maxLevels = dimension == 3 ? 6 : 9;
    o.refineProbability = 1.0;
    RandomForest forest(o);
    auto htg = buildHyperTreeGrid(forest.description());
    double b[6];
    htg->GetBounds(b);
    const double c[3] = {0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])};
    const double r = 0.01 * (b[1] - b[0]);
    const Box box{{c[0] - r, c[0] + 2 * r, c[1] - r, c[1] + r, c[2] - r, c[2] + r}};
    std::vector<ClipPlane> planes;
    for (int a = 0; a < 3; ++a)
    {
      ClipPlane low{{0, 0, 0, -(c[a] - r)}};
      low[a] = 1;
      ClipPlane high{{0, 0, 0, c[a] + r}};
      high[a] = -1;
      planes.push_back(low);
      planes.push_back(high);
    }
    const std::size_t trees = forest.description().trees.size();
    const std::size_t children = forest.childrenPerNode();
    for (bool frustum : {false, true})
    {
      vtkNew<vtkCanopyExtractSelection> filter;
      filter->SetInputData(htg);
      if (frustum)
      {
        usePlanes(filter, planes);
      }
      else
      {
        useBox(filter, box.data());
      }
      filter->Update();
      const auto count = static_cast<std::size_t>(
          vtkUnstructuredGrid::SafeDownCast(filter->GetOutput())->GetNumberOfCells());
      const auto visited = static_cast<std::size_t>(filter->GetLastVisited());
      ASSERT_GT(count, 0u);
      EXPECT_LE(visited, trees + children * static_cast<std::size_t>(o.maxLevels - 1) * count)
          << "dimension " << dimension << (frustum ? " frustum" : " box");
      EXPECT_LT(visited * 50, forest.numberOfNodes());
    }
  }
}

TEST(SelectionByRegion, BadRegionsAreReportedNotCrashed)
{
  RandomForest forest(randomOptions(2, 3));
  auto htg = buildHyperTreeGrid(forest.description());
  const std::vector<std::pair<const char*, std::function<void(vtkCanopyExtractSelection*)>>> bad{
      {"box min > max",
       [](vtkCanopyExtractSelection* f)
       {
         f->SetSelectionMode(vtkCanopyExtractSelection::BOX);
         f->SetBox(1, 0, 0, 1, 0, 1);
       }},
      {"box NaN",
       [](vtkCanopyExtractSelection* f)
       {
         f->SetSelectionMode(vtkCanopyExtractSelection::BOX);
         f->SetBox(0, 1, 0, std::nan(""), 0, 1);
       }},
      {"frustum planes never set (zero normals)", [](vtkCanopyExtractSelection* f)
       { f->SetSelectionMode(vtkCanopyExtractSelection::FRUSTUM); }},
      {"frustum plane not finite",
       [](vtkCanopyExtractSelection* f)
       {
         double planes[24] = {1, 0,  0, 0, -1, 0, 0, 1, 0, 1, 0,  0,
                              0, -1, 0, 1, 0,  0, 1, 0, 0, 0, -1, 1};
         planes[7] = std::numeric_limits<double>::infinity();
         f->SetSelectionMode(vtkCanopyExtractSelection::FRUSTUM);
         f->SetFrustumPlanes(planes);
       }},
      {"five corners",
       [](vtkCanopyExtractSelection* f)
       {
         f->SetSelectionMode(vtkCanopyExtractSelection::FRUSTUM);
         for (int c = 0; c < 5; ++c)
         {
           f->AddFrustumCorner(c, 0, 0);
         }
       }},
      {"corners without area",
       [](vtkCanopyExtractSelection* f)
       {
         f->SetSelectionMode(vtkCanopyExtractSelection::FRUSTUM);
         for (int c = 0; c < 8; ++c)
         {
           f->AddFrustumCorner(1, 2, 3);
         }
       }},
  };
  for (const auto& [what, configure] : bad)
  {
    vtkNew<vtkCanopyExtractSelection> f;
    f->SetInputData(htg);
    configure(f);
    EXPECT_EQ(errorsOfUpdate(f).size(), 1u) << what;
  }
  // A FRUSTUM node with the wrong number of values, and a content type the
  // filter does not select by.
  for (int type : {vtkSelectionNode::FRUSTUM, vtkSelectionNode::BLOCKS})
  {
    vtkNew<vtkSelection> selection;
    vtkNew<vtkSelectionNode> node;
    node->SetContentType(type);
    vtkNew<vtkDoubleArray> list;
    list->SetNumberOfComponents(4);
    for (int c = 0; c < 7; ++c)
    {
      list->InsertNextTuple4(c, c, c, 1);
    }
    node->SetSelectionList(list);
    selection->AddNode(node);
    vtkNew<vtkCanopyExtractSelection> f;
    f->SetInputData(0, htg);
    f->SetInputData(1, selection);
    EXPECT_EQ(errorsOfUpdate(f).size(), 1u) << vtkSelectionNode::GetContentTypeAsString(type);
  }
  // Planes that exclude each other (x >= 1 and x <= 0) are a valid, empty region.
  vtkNew<vtkCanopyExtractSelection> f;
  f->SetInputData(htg);
  usePlanes(f, {{{1, 0, 0, -1}},
                {{-1, 0, 0, 0}},
                {{0, 1, 0, 1e9}},
                {{0, -1, 0, 1e9}},
                {{0, 0, 1, 1e9}},
                {{0, 0, -1, 1e9}}});
  EXPECT_EQ(errorsOfUpdate(f).size(), 0u);
  EXPECT_EQ(vtkUnstructuredGrid::SafeDownCast(f->GetOutput())->GetNumberOfCells(), 0);
}

TEST(SelectionByRegion, PropertiesRoundTripAndPrint)
{
  vtkNew<vtkCanopyExtractSelection> filter;
  filter->SetSelectionMode(vtkCanopyExtractSelection::FRUSTUM);
  EXPECT_EQ(filter->GetSelectionMode(), vtkCanopyExtractSelection::FRUSTUM);
  filter->SetBox(1, 2, 3, 4, 5, 6);
  double planes[24];
  std::string listed;
  for (int i = 0; i < 24; ++i)
  {
    planes[i] = i + 0.5;
    listed += " " + std::to_string(i) + ".5";
  }
  const vtkMTimeType before = filter->GetMTime();
  filter->SetFrustumPlanes(planes);
  EXPECT_GT(filter->GetMTime(), before);
  EXPECT_TRUE(std::equal(planes, planes + 24, filter->GetFrustumPlanes()));
  filter->AddFrustumCorner(0, 0, 0);
  filter->AddFrustumCorner(1, 1, 1);
  std::ostringstream out;
  filter->Print(out);
  const std::string printed = out.str();
  for (const std::string& expected :
       {std::string("SelectionMode: 4"), std::string("Box: 1 2 3 4 5 6"), "FrustumPlanes:" + listed,
        std::string("FrustumCorners: 2"), std::string("LastVisited: 0")})
  {
    EXPECT_NE(printed.find(expected), std::string::npos) << expected << " in\n" << printed;
  }
}

} // namespace
} // namespace canopy::testing
