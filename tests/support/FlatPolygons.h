// The filters' flat pieces read back: each an axis-aligned rectangle drawn as a
// polygon, its four corners in order with, on its edges, the corners of the
// finer pieces beyond them (T-junction vertices, adaptor/filters/EdgeVertices.h).
// Helpers to get the rectangle back and to check the edge vertices against the
// other pieces of the same output: the brute-force oracle of those vertices.
#pragma once

#include <gtest/gtest.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace canopy::testing
{

using FlatPoint = std::array<double, 3>;

/// A cell's points, in order.
inline std::vector<FlatPoint> cellPoints(vtkPolyData* surface, vtkIdType cell)
{
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  surface->GetCellPoints(cell, n, ids);
  std::vector<FlatPoint> points(static_cast<std::size_t>(n));
  for (vtkIdType k = 0; k < n; ++k)
  {
    surface->GetPoint(ids[k], points[static_cast<std::size_t>(k)].data());
  }
  return points;
}

/// The axis along which two points differ, -1 if none or several.
inline int axisBetween(const FlatPoint& a, const FlatPoint& b)
{
  int axis = -1;
  for (int k = 0; k < 3; ++k)
  {
    if (a[k] != b[k])
    {
      if (axis >= 0)
      {
        return -1;
      }
      axis = k;
    }
  }
  return axis;
}

/// The polygon's corners (the points where its border turns), in its order,
/// starting at its first point when that is a corner. Adds a failure unless the
/// polygon is an axis-aligned rectangle: four corners, every point on its
/// border, consecutive points differing along one axis, going one way along
/// each edge (no point repeated, none out of order).
inline std::array<FlatPoint, 4> rectangleOf(const std::vector<FlatPoint>& points,
                                            const std::string& label)
{
  std::array<FlatPoint, 4> corners{};
  const std::size_t n = points.size();
  std::vector<std::size_t> turns;
  for (std::size_t k = 0; k < n; ++k)
  {
    const int in = axisBetween(points[(k + n - 1) % n], points[k]);
    const int out = axisBetween(points[k], points[(k + 1) % n]);
    EXPECT_GE(out, 0) << label << ": points " << k << " and " << (k + 1) % n
                      << " are equal or not along an axis";
    if (in != out)
    {
      turns.push_back(k);
    }
    else if (in >= 0)
    {
      // Along the same edge: strictly between its neighbours.
      const double before = points[(k + n - 1) % n][in];
      const double after = points[(k + 1) % n][in];
      EXPECT_TRUE((before < points[k][in] && points[k][in] < after) ||
                  (before > points[k][in] && points[k][in] > after))
          << label << ": point " << k << " is out of order on its edge";
    }
  }
  EXPECT_EQ(turns.size(), 4u) << label << ": not a rectangle (" << turns.size() << " corners)";
  for (std::size_t k = 0; k < 4 && k < turns.size(); ++k)
  {
    corners[k] = points[turns[k]];
  }
  return corners;
}

/// Checks every flat piece of `surface` (all in one plane, or in several
/// planes: pieces meet only within a plane, and in 3D across the edges they
/// share) against the others: a piece's points other than its corners are
/// exactly the other pieces' corners that lie strictly inside one of its
/// edges. With `exact` off, only that every such corner is there (a piece may
/// carry more, e.g. the corners of pieces culled away). Returns the number of
/// such vertices found.
inline std::size_t expectEdgeVerticesAreNeighboursCorners(vtkPolyData* surface,
                                                          const std::string& label,
                                                          bool exact = true)
{
  const vtkIdType cells = surface->GetNumberOfCells();
  std::vector<std::vector<FlatPoint>> pieces;
  std::vector<std::array<FlatPoint, 4>> rectangles;
  // Every piece's corners, by the line they could lie on: for an edge along
  // axis d, the key is (d, the two other coordinates).
  std::map<std::array<double, 3>, std::vector<double>> onLine[3];
  for (vtkIdType c = 0; c < cells; ++c)
  {
    pieces.push_back(cellPoints(surface, c));
    rectangles.push_back(rectangleOf(pieces.back(), label + ", cell " + std::to_string(c)));
    for (const FlatPoint& p : rectangles.back())
    {
      for (int d = 0; d < 3; ++d)
      {
        FlatPoint key = p;
        key[d] = 0;
        onLine[d][key].push_back(p[d]);
      }
    }
  }
  for (auto& line : onLine)
  {
    for (auto& [key, values] : line)
    {
      std::sort(values.begin(), values.end());
      values.erase(std::unique(values.begin(), values.end()), values.end());
    }
  }
  std::size_t found = 0;
  int wrong = 0;
  for (vtkIdType c = 0; c < cells && wrong < 10; ++c)
  {
    const auto& corners = rectangles[static_cast<std::size_t>(c)];
    std::set<FlatPoint> have;
    for (const FlatPoint& p : pieces[static_cast<std::size_t>(c)])
    {
      have.insert(p);
    }
    for (const FlatPoint& p : corners)
    {
      have.erase(p);
    }
    std::set<FlatPoint> want;
    for (int k = 0; k < 4; ++k)
    {
      const FlatPoint& a = corners[static_cast<std::size_t>(k)];
      const FlatPoint& b = corners[static_cast<std::size_t>((k + 1) % 4)];
      const int d = axisBetween(a, b);
      if (d < 0)
      {
        continue;
      }
      FlatPoint key = a;
      key[d] = 0;
      const auto line = onLine[d].find(key);
      if (line == onLine[d].end())
      {
        continue;
      }
      const double lo = std::min(a[d], b[d]);
      const double hi = std::max(a[d], b[d]);
      for (double x : line->second)
      {
        if (x > lo && x < hi)
        {
          FlatPoint p = a;
          p[d] = x;
          want.insert(p);
        }
      }
    }
    found += have.size();
    bool ok =
        exact ? have == want : std::includes(have.begin(), have.end(), want.begin(), want.end());
    if (!ok)
    {
      ++wrong;
      ADD_FAILURE() << label << ", cell " << c << ": " << have.size()
                    << " vertices on its edges, where the other pieces have " << want.size()
                    << " corners";
    }
  }
  return found;
}

} // namespace canopy::testing
