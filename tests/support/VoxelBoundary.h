// The boundary of a 3D grid's visible leaves, voxelized at the finest level by
// VTK's own cursors: the reference the 3D surface tests compare with (per-axis
// exposed area, every quad with an occupied voxel behind it and an empty one in
// front, the closed-surface volume identity).
#pragma once

#include "FlatPolygons.h"
#include "HtgWalk.h"

#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace canopy::testing
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

/// A quad from its four corners (in order): its normal's axis, direction, area.
inline Quad quadOf(const std::array<Point, 4>& corners)
{
  Quad q;
  q.p = corners;
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
  return q;
}

/// Each cell's rectangle: its four corners in order (a polygon also carries the
/// corners of the pieces meeting its edges, FlatPolygons.h).
inline std::vector<Quad> quadsOf(vtkPolyData* surface)
{
  std::vector<Quad> quads;
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    quads.push_back(quadOf(rectangleOf(cellPoints(surface, c), "cell " + std::to_string(c))));
  }
  return quads;
}

/// A quad's identity whatever the order of its corners: the corners, measured
/// from `origin` in `unit`s and rounded to 1e-9 of one, sorted.
using QuadKey = std::array<long long, 12>;

template <typename Corners>
QuadKey quadKey(const Corners& corners, const Point& origin = Point{{0, 0, 0}}, double unit = 1)
{
  std::array<std::array<long long, 3>, 4> rounded;
  for (int k = 0; k < 4; ++k)
    for (int a = 0; a < 3; ++a)
      rounded[k][a] = std::llround((corners[k][a] - origin[a]) / unit * 1e9);
  std::sort(rounded.begin(), rounded.end());
  QuadKey key;
  for (int k = 0; k < 4; ++k)
    for (int a = 0; a < 3; ++a)
      key[3 * k + a] = rounded[k][a];
  return key;
}

/// What the voxels hold on either side of a quad, at its centre: `behind` (against
/// its normal) and `front`, each `eps` away (well below the smallest voxel). A
/// boundary quad facing outward has the solid behind it and nothing in front.
struct QuadSides
{
  Point centre;
  bool behind = false;
  bool front = false;
};

inline QuadSides sidesOf(const Voxels& voxels, const Quad& q, double eps)
{
  QuadSides s;
  s.centre = Point{{0, 0, 0}};
  for (const Point& p : q.p)
    for (int a = 0; a < 3; ++a)
      s.centre[a] += p[a] / 4;
  Point inside = s.centre;
  Point outside = s.centre;
  inside[q.axis] -= q.sign * eps;
  outside[q.axis] += q.sign * eps;
  s.behind = voxels.occupiedAt(inside);
  s.front = voxels.occupiedAt(outside);
  return s;
}

/// Checks quads against the voxelization of a grid's visible leaves: the
/// boundary of their union, each piece once, facing outward. Returns the
/// number of quads.
inline std::size_t expectExactBoundary(const Voxels& voxels, const std::vector<Quad>& quads,
                                       const std::string& label)
{
  std::array<double, 3> expectedArea;
  double expectedVolume = 0;
  voxels.boundary(expectedArea, expectedVolume);
  const double eps = 1e-3 * voxels.smallestVoxel();
  std::array<double, 3> area{{0, 0, 0}};
  std::array<double, 3> volume{{0, 0, 0}};
  int misplaced = 0;
  for (const Quad& q : quads)
  {
    area[q.axis] += q.area;
    volume[q.axis] += q.sign * q.p[0][q.axis] * q.area;
    const QuadSides sides = sidesOf(voxels, q, eps);
    misplaced += !(sides.behind && !sides.front);
  }
  EXPECT_EQ(misplaced, 0) << label << ": quads not on the boundary or facing inward";
  for (int a = 0; a < 3; ++a)
  {
    EXPECT_NEAR(area[a], expectedArea[a], 1e-9 * expectedArea[a] + 1e-12)
        << label << ": area normal to axis " << a;
    EXPECT_NEAR(volume[a], expectedVolume, 1e-9 * expectedVolume + 1e-12)
        << label << ": volume identity along axis " << a;
  }
  return quads.size();
}

/// The same for one surface of `htg`.
inline std::size_t expectExactBoundary(vtkHyperTreeGrid* htg, vtkPolyData* surface,
                                       const std::string& label)
{
  return expectExactBoundary(Voxels(htg), quadsOf(surface), label);
}

} // namespace canopy::testing
