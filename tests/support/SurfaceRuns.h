// The adaptive surface run as the 1D, 2D and 3D surface tests run it: on a view
// given by numbers (with VTK's camera for it and the footprint VTK's projection
// gives a cell: the independent references), or without a view; the cells it
// drew; and the checks the 1D and 2D tests share (full surface, closed-form
// level of detail).
#pragma once

#include "FlatPolygons.h"
#include "HtgWalk.h"
#include "RandomForest.h"

#include <canopy/HtgBuilder.h>
#include <canopy/filters/vtkCanopyAdaptiveSurface.h>

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>

namespace canopy::testing
{

struct View
{
  std::array<double, 3> position;
  std::array<double, 3> focal;
  std::array<double, 3> up;
  bool parallel;
  double scale; ///< parallel scale or view angle
  int width;
  int height;
};

/// A vtkCamera for the view, its clipping range far from the data (`rangeFactor`
/// times the focal distance either way).
inline vtkSmartPointer<vtkCamera> cameraFor(const View& v, double rangeFactor = 1e6)
{
  auto camera = vtkSmartPointer<vtkCamera>::New();
  camera->SetPosition(v.position.data());
  camera->SetFocalPoint(v.focal.data());
  camera->SetViewUp(v.up.data());
  camera->SetParallelProjection(v.parallel);
  if (v.parallel)
  {
    camera->SetParallelScale(v.scale);
  }
  else
  {
    camera->SetViewAngle(v.scale);
  }
  const double distance = camera->GetDistance();
  camera->SetClippingRange(distance / rangeFactor, distance * rangeFactor);
  return camera;
}

/// The adaptive surface of `htg` for the view, given by the filter's Camera*
/// properties.
inline vtkSmartPointer<vtkPolyData> runSurface(vtkHyperTreeGrid* htg, const View& v, bool lod,
                                               double threshold = 1.0)
{
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->SetCameraPosition(v.position.data());
  filter->SetCameraFocalPoint(v.focal.data());
  filter->SetCameraViewUp(v.up.data());
  filter->SetParallelProjection(v.parallel);
  if (v.parallel)
  {
    filter->SetParallelScale(v.scale);
  }
  else
  {
    filter->SetViewAngle(v.scale);
  }
  filter->SetViewportSize(v.width, v.height);
  filter->SetLevelOfDetail(lod);
  filter->SetPixelThreshold(threshold);
  filter->Update();
  vtkSmartPointer<vtkPolyData> out = filter->GetPolyDataOutput();
  return out;
}

/// The full surface: no view (ViewDependent off).
inline vtkSmartPointer<vtkPolyData> fullSurface(vtkHyperTreeGrid* htg)
{
  vtkNew<vtkCanopyAdaptiveSurface> filter;
  filter->SetInputData(htg);
  filter->ViewDependentOff();
  filter->Update();
  vtkSmartPointer<vtkPolyData> out = filter->GetPolyDataOutput();
  return out;
}

/// The full surface of a 1D or 2D grid: one cell of `cellType` (VTK_LINE,
/// VTK_QUAD) per visible leaf, on the leaf's box and at its level. A quad is a
/// VTK_POLYGON where finer neighbours' corners lie on its edges: exactly those.
inline void expectOneCellPerVisibleLeaf(vtkHyperTreeGrid* htg, int cellType,
                                        const std::string& context)
{
  vtkSmartPointer<vtkPolyData> surface = fullSurface(htg);
  const auto leaves = visibleLeafBoxes(htg);
  ASSERT_EQ(surface->GetNumberOfCells(), static_cast<vtkIdType>(leaves.size())) << context;
  std::map<vtkIdType, const LeafBox*> byId;
  for (const LeafBox& leaf : leaves)
  {
    byId[leaf.global] = &leaf;
  }
  auto* ids = vtkIdTypeArray::SafeDownCast(surface->GetCellData()->GetArray("OriginalCellId"));
  auto* levels = vtkUnsignedCharArray::SafeDownCast(surface->GetCellData()->GetArray("Level"));
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    if (cellType == VTK_QUAD && surface->GetCellType(c) == VTK_POLYGON)
    {
      rectangleOf(cellPoints(surface, c), context + " cell " + std::to_string(c));
    }
    else
    {
      ASSERT_EQ(surface->GetCellType(c), cellType) << context << " cell " << c;
    }
    const LeafBox* leaf = byId.at(ids->GetValue(c));
    EXPECT_EQ(levels->GetValue(c), leaf->level) << context << " cell " << c;
    double b[6];
    surface->GetCell(c)->GetBounds(b);
    for (int i = 0; i < 6; ++i)
    {
      ASSERT_NEAR(b[i], leaf->bounds[i], 1e-12) << context << " cell " << c << " bound " << i;
    }
  }
  if (cellType == VTK_QUAD)
  {
    expectEdgeVerticesAreNeighboursCorners(surface, context);
  }
}

/// The input cells the surface drew ("OriginalCellId"); each must be drawn once.
inline std::set<vtkIdType> emittedIds(vtkPolyData* surface)
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

/// The pixel footprint of the box b (xmin, xmax, ymin, ymax, zmin, zmax; a cell
/// of a 1D or 2D grid too) by VTK's own projection matrix: the largest side of
/// its corners' screen-space bounding box.
inline double vtkFootprint(const View& v, const double b[6])
{
  // The camera owns the matrix: it must outlive its use (a temporary camera here was
  // a heap-use-after-free, found by the sanitizer build).
  const vtkSmartPointer<vtkCamera> camera = cameraFor(v);
  vtkMatrix4x4* m =
      camera->GetCompositeProjectionTransformMatrix(double(v.width) / v.height, -1, 1);
  double lo[2] = {1e300, 1e300};
  double hi[2] = {-1e300, -1e300};
  for (int k = 0; k < 8; ++k)
  {
    const double p[4] = {b[(k & 1) ? 1 : 0], b[(k & 2) ? 3 : 2], b[(k & 4) ? 5 : 4], 1};
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

/// AdaptiveSurface1D and 2D.LevelOfDetailMatchesTheClosedForm: uniformly refined
/// roots of side 10 (3 along x in 1D, 3 x 3 in the z = 0 plane in 2D), seen
/// face-on by a parallel camera, for branch factors 2 and 3. Every drawn node is
/// at level ceil(log(S / (t p)) / log f), capped by the depth
/// (AdaptiveSurfaceBuilder.h derives it).
inline void expectLevelsMatchClosedForm(int dimension)
{
  for (int f : {2, 3})
  {
    RandomForestOptions o;
    o.dimension = dimension;
    o.activeAxis = 0;
    o.branchFactor = f;
    o.rootCells = {{3, dimension == 2 ? 3u : 1u, 1}};
    o.maxLevels = dimension == 1 ? (f == 2 ? 12 : 8) : (f == 2 ? 9 : 6);
    o.refineProbability = 1.0;
    RandomForest forest(o);
    // Make the roots uniform (and square in 2D).
    auto& g = const_cast<std::array<std::vector<double>, 3>&>(forest.coordinates());
    for (int a = 0; a < dimension; ++a)
    {
      for (std::size_t i = 0; i < g[a].size(); ++i)
      {
        g[a][i] = 10.0 * static_cast<double>(i);
      }
    }
    auto htg = buildHyperTreeGrid(forest.description());
    // The middle of the grid, in the plane of a 1D grid's line.
    const double y = dimension == 1 ? g[1][0] : 15;
    for (double scale : {3.0, 15.0, 40.0, 200.0})
    {
      for (double threshold : {1.0, 3.0})
      {
        const View v{{{15, y, 50}}, {{15, y, 0}}, {{0, 1, 0}}, true, scale, 512, 512};
        auto surface = runSurface(htg, v, true, threshold);
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
              << dimension << "D, f " << f << " scale " << scale << " threshold " << threshold;
        }
      }
    }
  }
}

} // namespace canopy::testing
