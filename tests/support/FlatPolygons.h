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
/// starting at its first point when that is a corner. Returns what is wrong
/// unless the polygon is an axis-aligned rectangle: four corners, every point on
/// its border, consecutive points differing along one axis, going one way along
/// each edge (no point repeated, none out of order); empty when it is one.
inline std::string rectangleProblem(const std::vector<FlatPoint>& points,
                                    std::array<FlatPoint, 4>& corners)
{
  const std::size_t n = points.size();
  std::vector<std::size_t> turns;
  for (std::size_t k = 0; k < n; ++k)
  {
    const int in = axisBetween(points[(k + n - 1) % n], points[k]);
    const int out = axisBetween(points[k], points[(k + 1) % n]);
    if (out < 0)
    {
      return "points " + std::to_string(k) + " and " + std::to_string((k + 1) % n) +
             " are equal or not along an axis";
    }
    if (in != out)
    {
      turns.push_back(k);
    }
    else
    {
      // Along the same edge: strictly between its neighbours.
      const double before = points[(k + n - 1) % n][in];
      const double after = points[(k + 1) % n][in];
      if (!((before < points[k][in] && points[k][in] < after) ||
            (before > points[k][in] && points[k][in] > after)))
      {
        return "point " + std::to_string(k) + " is out of order on its edge";
      }
    }
  }
  if (turns.size() != 4)
  {
    return "not a rectangle (" + std::to_string(turns.size()) + " corners)";
  }
  for (std::size_t k = 0; k < 4; ++k)
  {
    corners[k] = points[turns[k]];
  }
  return {};
}

/// The same, as a GoogleTest check: the corners, and a failure when it is not one.
inline std::array<FlatPoint, 4> rectangleOf(const std::vector<FlatPoint>& points,
                                            const std::string& label)
{
  std::array<FlatPoint, 4> corners{};
  const std::string problem = rectangleProblem(points, corners);
  EXPECT_TRUE(problem.empty()) << label << ": " << problem;
  return corners;
}

/// Checks flat pieces (rectangles as polygons, all in one plane or in several:
/// pieces meet within a plane, and in 3D across the edges they share) against
/// one another: a piece's points other than its corners must be exactly the
/// other pieces' corners that lie strictly inside one of its edges. With
/// `exact` off, only that every such corner is there (a piece may carry more,
/// e.g. the corners of pieces culled away). Returns what is wrong with the
/// first wrong piece (empty when none is); `found` gets the number of such
/// vertices the pieces have.
inline std::string edgeVertexProblem(const std::vector<std::vector<FlatPoint>>& pieces, bool exact,
                                     std::size_t& found)
{
  std::vector<std::array<FlatPoint, 4>> rectangles(pieces.size());
  // Every piece's corners, by the line they could lie on: for an edge along
  // axis d, the key is the corner with its coordinate along d set to 0.
  std::map<FlatPoint, std::vector<double>> onLine[3];
  for (std::size_t c = 0; c < pieces.size(); ++c)
  {
    const std::string problem = rectangleProblem(pieces[c], rectangles[c]);
    if (!problem.empty())
    {
      return "piece " + std::to_string(c) + ": " + problem;
    }
    for (const FlatPoint& p : rectangles[c])
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
    for (auto& entry : line)
    {
      std::sort(entry.second.begin(), entry.second.end());
      entry.second.erase(std::unique(entry.second.begin(), entry.second.end()), entry.second.end());
    }
  }
  found = 0;
  std::string problem;
  for (std::size_t c = 0; c < pieces.size(); ++c)
  {
    const auto& corners = rectangles[c];
    std::set<FlatPoint> have(pieces[c].begin(), pieces[c].end());
    for (const FlatPoint& p : corners)
    {
      have.erase(p);
    }
    std::set<FlatPoint> want;
    for (std::size_t k = 0; k < 4; ++k)
    {
      const FlatPoint& a = corners[k];
      const FlatPoint& b = corners[(k + 1) % 4];
      const int d = axisBetween(a, b);
      FlatPoint key = a;
      key[d] = 0;
      const auto line = onLine[d].find(key);
      for (double x : line->second)
      {
        if (x > std::min(a[d], b[d]) && x < std::max(a[d], b[d]))
        {
          FlatPoint p = a;
          p[d] = x;
          want.insert(p);
        }
      }
    }
    found += have.size();
    const bool right =
        exact ? have == want : std::includes(have.begin(), have.end(), want.begin(), want.end());
    if (!right && problem.empty())
    {
      problem = "piece " + std::to_string(c) + " has " + std::to_string(have.size()) +
                " vertices on its edges, where the other pieces have " +
                std::to_string(want.size()) + " corners";
    }
  }
  return problem;
}

/// The same for every cell of `surface`, as a GoogleTest check; returns the
/// number of vertices on the cells' edges.
inline std::size_t expectEdgeVerticesAreNeighboursCorners(vtkPolyData* surface,
                                                          const std::string& label,
                                                          bool exact = true)
{
  std::vector<std::vector<FlatPoint>> pieces;
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    pieces.push_back(cellPoints(surface, c));
  }
  std::size_t found = 0;
  const std::string problem = edgeVertexProblem(pieces, exact, found);
  EXPECT_TRUE(problem.empty()) << label << ": " << problem;
  return found;
}

} // namespace canopy::testing
