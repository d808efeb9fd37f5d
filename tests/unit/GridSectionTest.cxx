// GridSection (adaptor/filters/GridSection.h), through its own header: a convex
// region cut by the plane of a 2D grid (any axis-aligned plane, at any height)
// or the line of a 1D grid (along any axis), clipped to the grid's bounds, and
// whether a cell overlaps the section with positive area (2D) or length (1D).
// Against a brute force that clips each cell's rectangle or segment, placed in
// space where the grid lies, by the region's planes (tests/support/ConvexClip.h)
// on random regions and cells; and on hand-worked sections: half-spaces parallel
// to the grid (all or nothing), oblique ones that cut it along a line, cells
// touching the section at a corner or along an edge (not overlapping), and
// sections with no area.
#include "GridSection.h"
#include "ConvexClip.h"

#include <gtest/gtest.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedCursor.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

HalfSpace halfSpace(double nx, double ny, double nz, double offset)
{
  return {{{nx, ny, nz}}, offset};
}

/// A grid with these root coordinates per axis (one value on a flat axis) and
/// one unrefined tree: only its bounds and axes matter to a section.
vtkSmartPointer<vtkHyperTreeGrid> flatGrid(const std::array<std::vector<double>, 3>& axes)
{
  auto grid = vtkSmartPointer<vtkHyperTreeGrid>::New();
  grid->SetBranchFactor(2);
  grid->SetDimensions(static_cast<unsigned int>(axes[0].size()),
                      static_cast<unsigned int>(axes[1].size()),
                      static_cast<unsigned int>(axes[2].size()));
  vtkNew<vtkDoubleArray> coordinates[3];
  for (int a = 0; a < 3; ++a)
  {
    for (double x : axes[a])
    {
      coordinates[a]->InsertNextValue(x);
    }
  }
  grid->SetXCoordinates(coordinates[0]);
  grid->SetYCoordinates(coordinates[1]);
  grid->SetZCoordinates(coordinates[2]);
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cursor;
  grid->InitializeNonOrientedCursor(cursor, 0, true);
  cursor->SetGlobalIndexStart(0);
  return grid;
}

TEST(GridSection, HalfSpacesParallelToTheGridKeepAllOrNothing)
{
  // The XY plane at z = 3: z <= 2.5 misses it, z <= 3.5 holds all of it.
  const auto grid = flatGrid({{{0, 1, 2}, {0, 2}, {3}}});
  const HyperTreeAccess access(grid);
  const Vec3 origin{{0, 0, 0}};
  const GridSection below(access, {halfSpace(0, 0, 1, 2.5)}, origin);
  EXPECT_TRUE(below.empty());
  EXPECT_FALSE(below.overlaps({{0, 0, 3}}, {{2, 2, 3}}));
  const GridSection above(access, {halfSpace(0, 0, 1, 3.5)}, origin);
  EXPECT_FALSE(above.empty());
  EXPECT_TRUE(above.overlaps({{0, 0, 3}}, {{0.25, 0.25, 3}}));
  EXPECT_TRUE(above.overlaps({{1.75, 1.75, 3}}, {{2, 2, 3}}));
  // Only the grid: a cell beyond its bounds, or touching them, overlaps nothing.
  EXPECT_FALSE(above.overlaps({{2, 0, 3}}, {{3, 1, 3}}));
  EXPECT_FALSE(above.overlaps({{-1, -1, 3}}, {{0, 0, 3}}));
  // The same with the anchor far from the plane.
  const GridSection anchored(access, {halfSpace(0, 0, 1, -97.5)}, {{5, -7, 100}});
  EXPECT_TRUE(anchored.empty());
}

TEST(GridSection, ObliqueHalfSpacesCutTheGridAlongALine)
{
  // Grid [0, 2] x [0, 2] in the XY plane at z = 0.
  const auto grid = flatGrid({{{0, 2}, {0, 2}, {0}}});
  const HyperTreeAccess access(grid);
  const Vec3 origin{{0, 0, 0}};
  // x + y <= 1: a triangle.
  const GridSection triangle(access, {halfSpace(1, 1, 0, 1)}, origin);
  EXPECT_FALSE(triangle.empty());
  EXPECT_TRUE(triangle.overlaps({{0, 0, 0}}, {{0.5, 0.5, 0}}));
  EXPECT_TRUE(triangle.overlaps({{0.5, 0, 0}}, {{1, 0.5, 0}}));
  EXPECT_FALSE(triangle.overlaps({{0.5, 0.5, 0}}, {{1, 1, 0}})) << "touches at a corner";
  EXPECT_FALSE(triangle.overlaps({{1, 0, 0}}, {{2, 1, 0}})) << "touches at a corner";
  EXPECT_FALSE(triangle.overlaps({{1, 1, 0}}, {{2, 2, 0}}));
  // x + z <= 0.5 through the plane at 45 degrees: x <= 0.5 on it.
  const GridSection strip(access, {halfSpace(1, 0, 1, 0.5)}, origin);
  EXPECT_FALSE(strip.overlaps({{0.5, 0, 0}}, {{1, 2, 0}})) << "touches along an edge";
  EXPECT_TRUE(strip.overlaps({{0.25, 1, 0}}, {{0.75, 2, 0}}));
  // The same strip with the grid at z = 1: x <= -0.5, outside the grid.
  const auto lifted = flatGrid({{{0, 2}, {0, 2}, {1}}});
  const HyperTreeAccess liftedAccess(lifted);
  EXPECT_TRUE(GridSection(liftedAccess, {halfSpace(1, 0, 1, 0.5)}, origin).empty());
  EXPECT_FALSE(GridSection(liftedAccess, {halfSpace(1, 0, 1, 1.5)}, origin).empty());
}

TEST(GridSection, EveryPlaneOfAGridIsCutAlike)
{
  // The triangle u + v <= 1 of the previous test, in the XZ plane (y flat) and
  // the YZ plane (x flat), at height 0.5 along the flat axis, with a normal
  // that also leans along the flat axis.
  for (int flat : {0, 1})
  {
    SCOPED_TRACE("flat axis " + std::to_string(flat));
    std::array<std::vector<double>, 3> axes{{{0, 2}, {0, 2}, {0, 2}}};
    axes[flat] = {0.5};
    const auto grid = flatGrid(axes);
    const HyperTreeAccess access(grid);
    const int u = flat == 0 ? 1 : 0;
    const int v = 2;
    Vec3 normal{{0, 0, 0}};
    normal[u] = 1;
    normal[v] = 1;
    normal[flat] = 2; // at the grid's height: u + v <= 1 + 2 * (0.5 - 0.5)
    const GridSection triangle(access, {{normal, 1}}, {{0.5, 0.5, 0}});
    auto cell = [&](double u0, double v0, double u1, double v1, bool expected)
    {
      Vec3 lo{{0, 0, 0}};
      Vec3 hi{{0, 0, 0}};
      lo[flat] = hi[flat] = 0.5;
      lo[u] = u0;
      lo[v] = v0;
      hi[u] = u1;
      hi[v] = v1;
      // Anchor (0.5, 0.5, 0): along u and v the anchor's own coordinates shift the line.
      EXPECT_EQ(triangle.overlaps(lo, hi), expected)
          << "[" << u0 << ", " << u1 << "] x [" << v0 << ", " << v1 << "]";
    };
    // Relative to the anchor's u (0.5 or 0 on the flat axis) and v (0): the
    // line u + v = 1 + anchor_u. On the XZ plane (u = x, anchor 0.5) it is
    // x + z = 1.5; on the YZ plane (u = y, anchor 0.5) it is y + z = 1.5.
    cell(0, 0, 0.5, 0.5, true);
    cell(0.75, 0.75, 1, 1, false); // touches x + z = 1.5 at a corner
    cell(0.5, 0.5, 1, 1, true);
    cell(1, 1, 2, 2, false);
  }
}

TEST(GridSection, SectionsWithoutAreaOrLengthAreEmpty)
{
  const auto plane = flatGrid({{{0, 2}, {0, 2}, {0}}});
  const HyperTreeAccess planeAccess(plane);
  const Vec3 origin{{0, 0, 0}};
  // A line x = 0.5 (two half-spaces facing each other), a corner of the grid.
  for (const auto& halfSpaces :
       {std::vector<HalfSpace>{halfSpace(1, 0, 0, 0.5), halfSpace(-1, 0, 0, -0.5)},
        std::vector<HalfSpace>{halfSpace(1, 1, 0, 0)},
        std::vector<HalfSpace>{halfSpace(1, 0, 0, 0)}})
  {
    const GridSection section(planeAccess, halfSpaces, origin);
    EXPECT_TRUE(section.empty());
    EXPECT_FALSE(section.overlaps({{0, 0, 0}}, {{2, 2, 0}}));
  }
  const auto line = flatGrid({{{0.5}, {0, 4}, {0.25}}});
  const HyperTreeAccess lineAccess(line);
  const GridSection point(lineAccess, {halfSpace(0, 1, 0, 1), halfSpace(0, -1, 0, -1)}, origin);
  EXPECT_TRUE(point.empty());
  EXPECT_FALSE(point.overlaps({{0.5, 0, 0.25}}, {{0.5, 4, 0.25}}));
}

TEST(GridSection, LinesAreCutIntoAnInterval)
{
  // A line along y at x = 0.5, z = 0.25, over [0, 4].
  const auto line = flatGrid({{{0.5}, {0, 1, 4}, {0.25}}});
  const HyperTreeAccess access(line);
  const Vec3 origin{{0, 0, 0}};
  auto segment = [](double y0, double y1) {
    return std::array<Vec3, 2>{{{{0.5, y0, 0.25}}, {{0.5, y1, 0.25}}}};
  };
  // y <= 1 + x: y <= 1.5 on the line.
  const GridSection lower(access, {halfSpace(-1, 1, 0, 1)}, origin);
  EXPECT_FALSE(lower.empty());
  auto s = segment(1.5, 2);
  EXPECT_FALSE(lower.overlaps(s[0], s[1])) << "touches at its end";
  s = segment(1, 2);
  EXPECT_TRUE(lower.overlaps(s[0], s[1]));
  // And y >= 1 - 4 z: y >= 0 on the line, nothing cut off below.
  const GridSection both(access, {halfSpace(-1, 1, 0, 1), halfSpace(0, -1, -4, -1)}, origin);
  s = segment(0, 0.125);
  EXPECT_TRUE(both.overlaps(s[0], s[1]));
  // x <= 0.25: the line (at x = 0.5) lies outside.
  EXPECT_TRUE(GridSection(access, {halfSpace(1, 0, 0, 0.25)}, origin).empty());
  // Beyond the line's ends nothing overlaps.
  const GridSection all(access, {halfSpace(0, 1, 0, 100)}, origin);
  s = segment(4, 5);
  EXPECT_FALSE(all.overlaps(s[0], s[1]));
  s = segment(-1, 0);
  EXPECT_FALSE(all.overlaps(s[0], s[1]));
}

/// ConvexClip's planes (inside where a x + b y + c z + d >= 0) for half-spaces
/// relative to `anchor`, each moved by `slack` (a distance) outward (positive)
/// or inward (negative).
std::vector<ClipPlane> clipPlanes(const std::vector<HalfSpace>& halfSpaces, const Vec3& anchor,
                                  double slack)
{
  std::vector<ClipPlane> planes;
  for (const HalfSpace& h : halfSpaces)
  {
    const double length = std::sqrt(dot(h.normal, h.normal));
    planes.push_back({{-h.normal[0], -h.normal[1], -h.normal[2],
                       h.offset + dot(h.normal, anchor) + slack * length}});
  }
  return planes;
}

/// The part of the cell [lo, hi] (its active axes) inside the planes, measured
/// in the grid's dimension, after cutting it to the grid's bounds.
double measureInside(const std::array<double, 6>& grid, const std::vector<int>& active, Vec3 lo,
                     Vec3 hi, const std::vector<ClipPlane>& planes)
{
  for (int a : active)
  {
    lo[a] = std::max(lo[a], grid[2 * a]);
    hi[a] = std::min(hi[a], grid[2 * a + 1]);
    if (!(lo[a] < hi[a]))
    {
      return 0;
    }
  }
  if (active.size() == 1)
  {
    return clippedLength(lo, hi, planes);
  }
  const int u = active[0];
  const int v = active[1];
  std::vector<ClipPoint> rectangle(4, lo);
  rectangle[1][u] = hi[u];
  rectangle[2][u] = hi[u];
  rectangle[2][v] = hi[v];
  rectangle[3][v] = hi[v];
  return clippedArea(rectangle, planes);
}

TEST(GridSection, OverlapsEqualBruteForceOnRandomRegionsAndCells)
{
  // Every plane and line orientation, at a height off the origin; random convex
  // regions (2 to 6 half-spaces through points near the grid, any normal) and
  // random cells in and around the grid. No part even with the planes moved
  // outward: must not overlap; a part even moved inward: must.
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(0, 1);
  std::normal_distribution<double> gauss(0, 1);
  int overlapping = 0;
  int apart = 0;
  for (int layout = 0; layout < 6; ++layout)
  {
    // 0-2: 2D with flat axis 0, 1, 2; 3-5: 1D along axis 0, 1, 2.
    std::array<std::vector<double>, 3> axes;
    for (int a = 0; a < 3; ++a)
    {
      const bool active = layout < 3 ? a != layout : a == layout - 3;
      axes[a] = active ? std::vector<double>{-1.0 + a, 0.5 + a, 2.0 + a}
                       : std::vector<double>{0.3 + 0.7 * a};
    }
    const auto grid = flatGrid(axes);
    const HyperTreeAccess access(grid);
    const auto& bounds = access.bounds();
    const std::vector<int>& active = access.activeAxes();
    SCOPED_TRACE("layout " + std::to_string(layout));
    for (int region = 0; region < 40; ++region)
    {
      auto near = [&]
      {
        Vec3 p;
        for (int a = 0; a < 3; ++a)
        {
          p[a] = bounds[2 * a] - 0.5 + (bounds[2 * a + 1] - bounds[2 * a] + 1) * unit(random);
        }
        return p;
      };
      const Vec3 anchor = near();
      std::vector<HalfSpace> halfSpaces;
      const int count = 2 + static_cast<int>(random() % 5);
      for (int i = 0; i < count; ++i)
      {
        const Vec3 normal{{gauss(random), gauss(random), gauss(random)}};
        halfSpaces.push_back({normal, dot(normal, sub(near(), anchor))});
      }
      const GridSection section(access, halfSpaces, anchor);
      const auto outward = clipPlanes(halfSpaces, anchor, 1e-9);
      const auto inward = clipPlanes(halfSpaces, anchor, -1e-9);
      for (int c = 0; c < 100; ++c)
      {
        Vec3 lo{{bounds[0], bounds[2], bounds[4]}};
        Vec3 hi = lo;
        for (int a : active)
        {
          const double extent = bounds[2 * a + 1] - bounds[2 * a];
          const double size = extent * (c % 2 == 0 ? 0.05 : 0.4) * (0.1 + unit(random));
          lo[a] = bounds[2 * a] - 0.2 * extent + 1.4 * extent * unit(random);
          hi[a] = lo[a] + size;
        }
        const bool surely = measureInside(bounds, active, lo, hi, inward) > 0;
        const bool surelyNot = measureInside(bounds, active, lo, hi, outward) == 0;
        const bool answer = section.overlaps(lo, hi);
        if (surely)
        {
          ++overlapping;
          EXPECT_TRUE(answer) << "region " << region << ", cell " << c;
        }
        else if (surelyNot)
        {
          ++apart;
          EXPECT_FALSE(answer) << "region " << region << ", cell " << c;
        }
      }
    }
  }
  // Both answers asked for often (fixed seed): the comparison is not vacuous.
  EXPECT_GT(overlapping, 1500);
  EXPECT_GT(apart, 10000);
}

} // namespace
} // namespace canopy::testing
