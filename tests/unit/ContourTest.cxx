// vtkCanopyContour against oracles that share none of its code: grids are built
// and walked with VTK's own cursors, fields are computed at the leaves' centres
// from formulas, and the output is checked for what a correct contour must be:
// watertight inside the domain (every 2D segment end shared by exactly two
// segments, every 3D triangle edge by exactly two triangles), exact for linear
// fields (on the line or plane, of the length or area of its intersection with
// the domain: no crack and no uncovered boundary strip), and, on uniform
// forests, through the same edge crossings as VTK's contour of an image of the
// leaf centres.
#include <canopy/filters/vtkCanopyContour.h>

#include "ContourField.h"
#include "DualTraversal.h"
#include "ErrorMessages.h"
#include "HyperTreeAccess.h"
#include "LevelJumpForest.h"
#include "NodeRanges.h"
#include "RandomForest.h"
#include "RankPart.h"
#include <canopy/HtgBuilder.h>

#include <gtest/gtest.h>
#include <vtkBitArray.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkContourFilter.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkSmartPointer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace canopy::testing
{
namespace
{

using Point = std::array<double, 3>;

struct Box
{
  Point lo;
  Point hi;
};

/// VTK's cursors compute a node's box from its parent's: its faces can miss the
/// neighbours' (and the domain's) by rounding. The oracles allow for that.
constexpr double Slack = 1e-10;

/// Closed boxes that share at least a point (to rounding).
bool touch(const Box& a, const Box& b)
{
  for (int k = 0; k < 3; ++k)
  {
    if (a.hi[k] < b.lo[k] - Slack || b.hi[k] < a.lo[k] - Slack)
    {
      return false;
    }
  }
  return true;
}

/// In the closed box (to rounding).
bool inside(const Box& b, const Point& x)
{
  for (int k = 0; k < 3; ++k)
  {
    if (x[k] < b.lo[k] - Slack || x[k] > b.hi[k] + Slack)
    {
      return false;
    }
  }
  return true;
}

/// Strictly inside along the axes where the box has extent.
bool strictlyInside(const Box& b, const Point& x)
{
  for (int k = 0; k < 3; ++k)
  {
    if (b.hi[k] > b.lo[k] && !(x[k] > b.lo[k] && x[k] < b.hi[k]))
    {
      return false;
    }
  }
  return true;
}

using Field = std::function<double(const Point&)>;

/// What a test knows of a grid, from VTK's cursors.
struct TestGrid
{
  vtkSmartPointer<vtkHyperTreeGrid> htg;
  Box domain;
  std::vector<Box> leaves; ///< visible leaves
  std::vector<Box> hidden; ///< masked nodes and root cells without a tree
  int deepest = 0;
};

Box cursorBox(vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
{
  double b[6];
  cursor->GetBounds(b);
  return {{{b[0], b[2], b[4]}}, {{b[1], b[3], b[5]}}};
}

/// Adds cell field "f" (and "g" = 2 f + 1) at every node's centre and records
/// the leaves and hidden regions, walking with VTK's cursors (never below a
/// masked node: they assert there).
void describe(TestGrid& grid, const Field& field)
{
  vtkHyperTreeGrid* htg = grid.htg;
  vtkNew<vtkDoubleArray> f;
  f->SetName("f");
  f->SetNumberOfTuples(htg->GetNumberOfCells());
  f->Fill(std::nan(""));
  vtkNew<vtkDoubleArray> g;
  g->SetName("g");
  g->SetNumberOfTuples(htg->GetNumberOfCells());
  double bounds[6];
  htg->GetBounds(bounds);
  grid.domain = {{{bounds[0], bounds[2], bounds[4]}}, {{bounds[1], bounds[3], bounds[5]}}};
  unsigned int dims[3];
  htg->GetDimensions(dims);
  vtkDataArray* coords[3] = {htg->GetXCoordinates(), htg->GetYCoordinates(),
                             htg->GetZCoordinates()};
  const unsigned cells[3] = {std::max(1u, dims[0] - 1), std::max(1u, dims[1] - 1),
                             std::max(1u, dims[2] - 1)};
  vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> cursor;
  for (unsigned k = 0; k < cells[2]; ++k)
  {
    for (unsigned j = 0; j < cells[1]; ++j)
    {
      for (unsigned i = 0; i < cells[0]; ++i)
      {
        const vtkIdType index = i + cells[0] * (j + cells[1] * k);
        if (htg->GetTree(index) == nullptr)
        {
          const unsigned at[3] = {i, j, k};
          Box b;
          for (int a = 0; a < 3; ++a)
          {
            b.lo[a] = coords[a]->GetComponent(at[a], 0);
            b.hi[a] = coords[a]->GetComponent(dims[a] > 1 ? at[a] + 1 : 0, 0);
          }
          grid.hidden.push_back(b);
          continue;
        }
        htg->InitializeNonOrientedGeometryCursor(cursor, index);
        auto walk = [&](auto& self, int level) -> void
        {
          const Box box = cursorBox(cursor);
          const Point centre{{0.5 * (box.lo[0] + box.hi[0]), 0.5 * (box.lo[1] + box.hi[1]),
                              0.5 * (box.lo[2] + box.hi[2])}};
          const vtkIdType id = cursor->GetGlobalNodeIndex();
          f->SetValue(id, field(centre));
          g->SetValue(id, 2 * field(centre) + 1);
          if (cursor->IsMasked())
          {
            grid.hidden.push_back(box);
            return;
          }
          if (cursor->IsLeaf())
          {
            grid.leaves.push_back(box);
            grid.deepest = std::max(grid.deepest, level);
            return;
          }
          for (unsigned char c = 0; c < cursor->GetNumberOfChildren(); ++c)
          {
            cursor->ToChild(c);
            self(self, level + 1);
            cursor->ToParent();
          }
        };
        walk(walk, 0);
      }
    }
  }
  htg->GetCellData()->AddArray(f);
  htg->GetCellData()->AddArray(g);
}

/// A grid built with VTK's API alone: `refine` and `mask` decide per node.
struct GridSpec
{
  int dimension = 2;
  int branchFactor = 2;
  std::array<int, 3> roots{{3, 2, 1}};
  bool irregular = true; ///< root sides that no binary or ternary fraction gives
  int maxLevel = 5;
  std::function<bool(int, const Box&)> refine;
  std::function<bool(int, const Box&)> mask;
  std::vector<vtkIdType> missingTrees;
};

TestGrid makeGrid(const GridSpec& spec, const Field& field)
{
  TestGrid grid;
  grid.htg = vtkSmartPointer<vtkHyperTreeGrid>::New();
  vtkHyperTreeGrid* htg = grid.htg;
  htg->SetBranchFactor(spec.branchFactor);
  const int roots[3] = {spec.roots[0], spec.roots[1], spec.dimension == 3 ? spec.roots[2] : 0};
  htg->SetDimensions(roots[0] + 1, roots[1] + 1, roots[2] + 1);
  vtkNew<vtkDoubleArray> coords[3];
  for (int a = 0; a < 3; ++a)
  {
    double x = a == 0 ? -1.25 : 0.5 * a;
    coords[a]->InsertNextValue(x);
    for (int i = 0; i < roots[a]; ++i)
    {
      x += spec.irregular ? 0.7 + 0.6 * ((i * 7 + a * 3) % 10) / 9.0 + 1e-3 / 3.0 : 1.0;
      coords[a]->InsertNextValue(x);
    }
  }
  htg->SetXCoordinates(coords[0]);
  htg->SetYCoordinates(coords[1]);
  htg->SetZCoordinates(coords[2]);
  const vtkIdType trees = spec.roots[0] * spec.roots[1] * (spec.dimension == 3 ? spec.roots[2] : 1);
  vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> cursor;
  vtkIdType offset = 0;
  for (vtkIdType t = 0; t < trees; ++t)
  {
    if (std::find(spec.missingTrees.begin(), spec.missingTrees.end(), t) != spec.missingTrees.end())
    {
      continue;
    }
    htg->InitializeNonOrientedGeometryCursor(cursor, t, true);
    cursor->SetGlobalIndexStart(offset);
    auto build = [&](auto& self, int level) -> void
    {
      if (level < spec.maxLevel && spec.refine(level, cursorBox(cursor)))
      {
        cursor->SubdivideLeaf();
        for (unsigned char c = 0; c < cursor->GetNumberOfChildren(); ++c)
        {
          cursor->ToChild(c);
          self(self, level + 1);
          cursor->ToParent();
        }
      }
    };
    build(build, 0);
    offset += cursor->GetTree()->GetNumberOfVertices();
  }
  if (spec.mask)
  {
    vtkNew<vtkBitArray> bits;
    bits->SetNumberOfTuples(offset);
    bits->Fill(0);
    for (vtkIdType t = 0; t < trees; ++t)
    {
      if (htg->GetTree(t) == nullptr)
      {
        continue;
      }
      htg->InitializeNonOrientedGeometryCursor(cursor, t);
      auto walk = [&](auto& self, int level) -> void
      {
        if (spec.mask(level, cursorBox(cursor)))
        {
          bits->SetValue(cursor->GetGlobalNodeIndex(), 1);
          return;
        }
        if (cursor->IsLeaf())
        {
          return;
        }
        for (unsigned char c = 0; c < cursor->GetNumberOfChildren(); ++c)
        {
          cursor->ToChild(c);
          self(self, level + 1);
          cursor->ToParent();
        }
      };
      walk(walk, 0);
    }
    htg->SetMask(bits);
  }
  describe(grid, field);
  return grid;
}

/// A reproducible coin per node.
double coin(std::uint64_t seed, int level, const Box& b)
{
  std::uint64_t x = seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(level);
  for (int k = 0; k < 3; ++k)
  {
    x ^= static_cast<std::uint64_t>(std::llround(b.lo[k] * 1e6)) + 0x632BE59BD9B4E019ull +
         (x << 6) + (x >> 2);
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  }
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  return static_cast<double>(x >> 11) / 9007199254740992.0;
}

/// Random refinement, and deep refinement around one point: neighbours differ
/// by one level and by several.
GridSpec randomSpec(int dimension, int branchFactor, std::uint64_t seed)
{
  GridSpec spec;
  spec.dimension = dimension;
  spec.branchFactor = branchFactor;
  spec.roots = dimension == 2 ? std::array<int, 3>{{3, 2, 1}} : std::array<int, 3>{{2, 2, 2}};
  spec.maxLevel = branchFactor == 2 ? (dimension == 2 ? 6 : 4) : (dimension == 2 ? 4 : 3);
  const Point hot{{0.1 + 0.05 * static_cast<double>(seed % 3), 1.3, 1.4}};
  spec.refine = [seed, hot, dimension](int level, const Box& b)
  {
    Box probe = b;
    if (dimension == 2)
    {
      probe.lo[2] = probe.hi[2] = hot[2];
    }
    if (inside(probe, hot))
    {
      return true;
    }
    return coin(seed, level, b) < (level == 0 ? 0.8 : 0.4);
  };
  return spec;
}

/// Refinement graded as AMR codes grade it: a node is refined when it lies
/// within one of its own sizes of a point (or a second one), so neighbours
/// differ by at most a level or so.
GridSpec gradedSpec(int dimension, int branchFactor, std::uint64_t seed)
{
  GridSpec spec = randomSpec(dimension, branchFactor, seed);
  const double t = 0.37 * static_cast<double>(seed);
  const Point hot{{-0.4 + 0.9 * std::sin(t), 1.2 + 0.5 * std::cos(t), 1.6 + 0.6 * std::sin(2 * t)}};
  const Point cold{{0.6, 0.9, 1.1}};
  spec.refine = [hot, cold, dimension](int, const Box& b)
  {
    double size = 0;
    double near = 1e300;
    for (const Point& p : {hot, cold})
    {
      double d2 = 0;
      for (int k = 0; k < dimension; ++k)
      {
        const double gap = std::max({b.lo[k] - p[k], 0.0, p[k] - b.hi[k]});
        d2 += gap * gap;
      }
      near = std::min(near, std::sqrt(d2));
    }
    for (int k = 0; k < dimension; ++k)
    {
      size = std::max(size, b.hi[k] - b.lo[k]);
    }
    return near < 0.6 * size;
  };
  return spec;
}

/// Refined everywhere to a level, more in places: many leaves below a pixel of
/// the level-of-detail tests' small viewports.
GridSpec belowPixelSpec(int dimension)
{
  GridSpec spec = dimension == 2 ? randomSpec(2, 2, 6) : gradedSpec(3, 2, 6);
  const auto refine = spec.refine;
  const int uniform = dimension == 2 ? 5 : 3;
  spec.refine = [refine, uniform](int level, const Box& b)
  { return level < uniform || refine(level, b); };
  return spec;
}

/// The middle of the grid's domain.
Point middleOf(const TestGrid& grid)
{
  return {{0.5 * (grid.domain.lo[0] + grid.domain.hi[0]),
           0.5 * (grid.domain.lo[1] + grid.domain.hi[1]),
           0.5 * (grid.domain.lo[2] + grid.domain.hi[2])}};
}

vtkSmartPointer<vtkPolyData> contour(vtkHyperTreeGrid* htg, const std::vector<double>& values,
                                     const std::vector<std::string>& interpolate = {})
{
  vtkNew<vtkCanopyContour> filter;
  filter->SetInputData(htg);
  filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    filter->SetValue(static_cast<int>(i), values[i]);
  }
  for (const auto& name : interpolate)
  {
    filter->AddInterpolatedField(name.c_str());
  }
  filter->Update();
  return filter->GetOutput();
}

Point pointOf(vtkPolyData* out, vtkIdType id)
{
  Point x;
  out->GetPoint(id, x.data());
  return x;
}

/// The output's segments (2D) or triangles (3D).
vtkCellArray* drawnCells(vtkPolyData* out)
{
  return out->GetNumberOfPolys() > 0 ? out->GetPolys() : out->GetLines();
}

/// Cells of the output as lists of point ids.
std::vector<std::vector<vtkIdType>> cellsOf(vtkCellArray* cells)
{
  std::vector<std::vector<vtkIdType>> result;
  vtkNew<vtkIdList> ids;
  cells->InitTraversal();
  while (cells->GetNextCell(ids))
  {
    result.emplace_back(ids->begin(), ids->end());
  }
  return result;
}

/// Whether x lies in a visible leaf that touches a hidden region: where a
/// contour may end inside the domain.
bool nextToHidden(const TestGrid& grid, const Point& x)
{
  for (const Box& leaf : grid.leaves)
  {
    if (!inside(leaf, x))
    {
      continue;
    }
    for (const Box& h : grid.hidden)
    {
      if (touch(leaf, h))
      {
        return true;
      }
    }
  }
  return false;
}

/// 2D: every segment end strictly inside the domain is shared by exactly two
/// segments, except next to a hidden region (one); never more. Returns the
/// number of segments.
std::size_t expectWatertight2D(vtkPolyData* out, const TestGrid& grid, const std::string& what)
{
  EXPECT_EQ(out->GetNumberOfPolys(), 0) << what;
  const auto segments = cellsOf(out->GetLines());
  std::vector<int> uses(static_cast<std::size_t>(out->GetNumberOfPoints()), 0);
  for (const auto& s : segments)
  {
    EXPECT_EQ(s.size(), 2u) << what;
    EXPECT_NE(s[0], s[1]) << what;
    for (vtkIdType id : s)
    {
      ++uses[static_cast<std::size_t>(id)];
    }
  }
  int failures = 0;
  for (vtkIdType p = 0; p < out->GetNumberOfPoints() && failures < 5; ++p)
  {
    const int n = uses[static_cast<std::size_t>(p)];
    const Point x = pointOf(out, p);
    const bool interior = strictlyInside(grid.domain, x);
    const bool ok = n == 2 || (n == 1 && (!interior || nextToHidden(grid, x)));
    if (!ok)
    {
      ++failures;
      ADD_FAILURE() << what << ": point " << p << " at (" << x[0] << ", " << x[1] << ", " << x[2]
                    << ") ends " << n << " segments";
    }
  }
  return segments.size();
}

/// 3D: every triangle edge strictly inside the domain is shared by exactly
/// two triangles, except next to a hidden region (one); never more. Returns
/// the number of triangles.
std::size_t expectWatertight3D(vtkPolyData* out, const TestGrid& grid, const std::string& what)
{
  EXPECT_EQ(out->GetNumberOfLines(), 0) << what;
  const auto triangles = cellsOf(out->GetPolys());
  std::map<std::pair<vtkIdType, vtkIdType>, int> uses;
  for (const auto& t : triangles)
  {
    EXPECT_EQ(t.size(), 3u) << what;
    EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) << what;
    for (int k = 0; k < 3; ++k)
    {
      const vtkIdType a = t[static_cast<std::size_t>(k)];
      const vtkIdType b = t[static_cast<std::size_t>((k + 1) % 3)];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  int failures = 0;
  for (const auto& [edge, n] : uses)
  {
    const Point a = pointOf(out, edge.first);
    const Point b = pointOf(out, edge.second);
    const Point mid{{0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])}};
    // An edge on the boundary has both ends on the same boundary plane.
    bool onBoundary = false;
    for (int k = 0; k < 3; ++k)
    {
      for (double side : {grid.domain.lo[k], grid.domain.hi[k]})
      {
        onBoundary = onBoundary || (a[k] == side && b[k] == side);
      }
    }
    const bool ok =
        n == 2 || (n == 1 && (onBoundary || (nextToHidden(grid, a) && nextToHidden(grid, b)) ||
                              nextToHidden(grid, mid)));
    if (!ok && failures++ < 5)
    {
      ADD_FAILURE() << what << ": edge (" << a[0] << ", " << a[1] << ", " << a[2] << ") - (" << b[0]
                    << ", " << b[1] << ", " << b[2] << ") in " << n << " triangles";
    }
  }
  return triangles.size();
}

/// Whether no leaf containing x touches the domain's boundary (so x is on a
/// dual edge between two leaves' centres, not one to a boundary vertex).
bool awayFromBoundary(const TestGrid& grid, const Point& x)
{
  bool found = false;
  for (const Box& leaf : grid.leaves)
  {
    if (!inside(leaf, x))
    {
      continue;
    }
    found = true;
    for (int k = 0; k < 3; ++k)
    {
      if (leaf.hi[k] > leaf.lo[k] && (std::abs(leaf.lo[k] - grid.domain.lo[k]) < Slack ||
                                      std::abs(leaf.hi[k] - grid.domain.hi[k]) < Slack))
      {
        return false;
      }
    }
  }
  return found;
}

double length(const Point& a, const Point& b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

/// Length of the line {x : a.x = c} (2D, axes 0 and 1) inside the box.
double lineLengthInBox(const std::array<double, 2>& a, double c, const Box& box)
{
  // A point of the line and its direction, clipped (Liang-Barsky).
  const double n2 = a[0] * a[0] + a[1] * a[1];
  const Point p{{a[0] * c / n2, a[1] * c / n2, 0}};
  const Point d{{-a[1], a[0], 0}};
  double t0 = -1e300;
  double t1 = 1e300;
  for (int k = 0; k < 2; ++k)
  {
    if (d[k] == 0)
    {
      if (p[k] < box.lo[k] || p[k] > box.hi[k])
      {
        return 0;
      }
      continue;
    }
    double ta = (box.lo[k] - p[k]) / d[k];
    double tb = (box.hi[k] - p[k]) / d[k];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  return t1 > t0 ? (t1 - t0) * std::sqrt(n2) : 0;
}

/// Area of the plane {x : a.x = c} inside the box: the polygon through its
/// crossings of the box's 12 edges, ordered around their centroid.
double planeAreaInBox(const Point& a, double c, const Box& box)
{
  std::vector<Point> crossings;
  for (int axis = 0; axis < 3; ++axis)
  {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    for (int corner = 0; corner < 4; ++corner)
    {
      Point p;
      p[u] = corner & 1 ? box.hi[u] : box.lo[u];
      p[v] = corner & 2 ? box.hi[v] : box.lo[v];
      if (a[axis] == 0)
      {
        continue;
      }
      p[axis] = (c - a[u] * p[u] - a[v] * p[v]) / a[axis];
      if (p[axis] >= box.lo[axis] && p[axis] <= box.hi[axis])
      {
        crossings.push_back(p);
      }
    }
  }
  if (crossings.size() < 3)
  {
    return 0;
  }
  Point m{{0, 0, 0}};
  for (const Point& p : crossings)
  {
    for (int k = 0; k < 3; ++k)
    {
      m[k] += p[k] / static_cast<double>(crossings.size());
    }
  }
  // A basis of the plane.
  Point e1 = a[0] != 0 || a[1] != 0 ? Point{{-a[1], a[0], 0}} : Point{{1, 0, 0}};
  const Point e2{
      {a[1] * e1[2] - a[2] * e1[1], a[2] * e1[0] - a[0] * e1[2], a[0] * e1[1] - a[1] * e1[0]}};
  auto angle = [&](const Point& p)
  {
    const Point d{{p[0] - m[0], p[1] - m[1], p[2] - m[2]}};
    return std::atan2(d[0] * e2[0] + d[1] * e2[1] + d[2] * e2[2],
                      d[0] * e1[0] + d[1] * e1[1] + d[2] * e1[2]);
  };
  std::sort(crossings.begin(), crossings.end(),
            [&](const Point& p, const Point& q) { return angle(p) < angle(q); });
  double area = 0;
  for (std::size_t i = 0; i < crossings.size(); ++i)
  {
    const Point& p = crossings[i];
    const Point& q = crossings[(i + 1) % crossings.size()];
    const Point d1{{p[0] - m[0], p[1] - m[1], p[2] - m[2]}};
    const Point d2{{q[0] - m[0], q[1] - m[1], q[2] - m[2]}};
    const Point n{{d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2],
                   d1[0] * d2[1] - d1[1] * d2[0]}};
    area += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  }
  return area;
}

double triangleArea(const Point& p, const Point& q, const Point& r)
{
  const Point u{{q[0] - p[0], q[1] - p[1], q[2] - p[2]}};
  const Point v{{r[0] - p[0], r[1] - p[1], r[2] - p[2]}};
  const Point n{{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]}};
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

// ---- 2D -------------------------------------------------------------------

double wavy(const Point& x)
{
  return std::sin(1.3 * x[0] + 0.2) * std::cos(0.9 * x[1] - 0.4) + 0.25 * x[0];
}

TEST(Contour2D, WatertightOnRandomAdaptiveForests)
{
  for (std::uint64_t seed = 1; seed <= 8; ++seed)
  {
    for (int branch : {2, 3})
    {
      const std::string what =
          "seed " + std::to_string(seed) + ", branch factor " + std::to_string(branch);
      TestGrid grid = makeGrid(randomSpec(2, branch, seed), wavy);
      auto out = contour(grid.htg, {-0.6, -0.1, 0.0, 0.35, 0.8});
      const std::size_t segments = expectWatertight2D(out, grid, what);
      EXPECT_GT(segments, 20u) << what;
      EXPECT_GE(grid.deepest, branch == 2 ? 5 : 3) << what;
    }
  }
}

TEST(Contour2D, WatertightAroundMasksAndMissingTrees)
{
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
  {
    for (int branch : {2, 3})
    {
      const std::string what =
          "seed " + std::to_string(seed) + ", branch factor " + std::to_string(branch);
      GridSpec spec = randomSpec(2, branch, seed);
      spec.mask = [seed](int level, const Box& b) { return coin(seed + 99, level, b) < 0.12; };
      spec.missingTrees = {static_cast<vtkIdType>(seed % 6)};
      TestGrid grid = makeGrid(spec, wavy);
      ASSERT_FALSE(grid.hidden.empty());
      auto out = contour(grid.htg, {-0.6, -0.1, 0.0, 0.35, 0.8});
      expectWatertight2D(out, grid, what);
      // Nothing inside a hidden region.
      for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
      {
        const Point x = pointOf(out, p);
        for (const Box& h : grid.hidden)
        {
          ASSERT_FALSE(strictlyInside(h, x)) << what;
        }
      }
    }
  }
}

TEST(Contour2D, LinearFieldIsExactUpToTheBoundary)
{
  // Every vertex on the line, and the length of the line inside the domain:
  // a crack, an overlap or an uncovered boundary strip would change it.
  const std::array<double, 2> a{{0.37, -0.81}};
  const double b = 0.05;
  auto linear = [&](const Point& x) { return a[0] * x[0] + a[1] * x[1] + b; };
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
  {
    for (int branch : {2, 3})
    {
      const std::string what =
          "seed " + std::to_string(seed) + ", branch factor " + std::to_string(branch);
      TestGrid grid = makeGrid(randomSpec(2, branch, seed), linear);
      const std::vector<double> values{-1.2, -0.77, -0.3, 0.0123, 0.4};
      auto out = contour(grid.htg, values);
      vtkDataArray* contourValue = out->GetPointData()->GetArray("f");
      ASSERT_NE(contourValue, nullptr);
      std::vector<double> total(values.size(), 0.0);
      for (const auto& s : cellsOf(out->GetLines()))
      {
        const Point p = pointOf(out, s[0]);
        const Point q = pointOf(out, s[1]);
        const double c = contourValue->GetComponent(s[0], 0);
        EXPECT_EQ(c, contourValue->GetComponent(s[1], 0));
        EXPECT_NEAR(linear(p), c, 1e-12) << what;
        EXPECT_NEAR(linear(q), c, 1e-12) << what;
        const auto k = std::find(values.begin(), values.end(), c) - values.begin();
        total[static_cast<std::size_t>(k)] += length(p, q);
      }
      for (std::size_t k = 0; k < values.size(); ++k)
      {
        const double expected = lineLengthInBox(a, values[k] - b, grid.domain);
        EXPECT_NEAR(total[k], expected, 1e-11 * (1 + expected)) << what << ", value " << values[k];
      }
      EXPECT_GT(total[2], 1.0) << what;
    }
  }
}

/// VTK's own contour (vtkContourFilter) of an image of `dims` points, `h` apart
/// from `origin` (a single layer: 2D), holding `f` at its points; `imageBox`
/// receives the image's bounds. The oracle of the uniform-forest tests.
vtkSmartPointer<vtkPolyData> vtkContourOfCentres(const std::array<int, 3>& dims, double h,
                                                 const Point& origin, const Field& f,
                                                 const std::vector<double>& values, Box& imageBox)
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(dims.data());
  image->SetSpacing(h, h, dims[2] > 1 ? h : 1);
  image->SetOrigin(origin.data());
  vtkNew<vtkDoubleArray> scalars;
  scalars->SetName("f");
  scalars->SetNumberOfTuples(image->GetNumberOfPoints());
  for (vtkIdType p = 0; p < image->GetNumberOfPoints(); ++p)
  {
    Point x;
    image->GetPoint(p, x.data());
    scalars->SetValue(p, f(x));
  }
  image->GetPointData()->SetScalars(scalars);
  vtkNew<vtkContourFilter> reference;
  reference->SetInputData(image);
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    reference->SetValue(static_cast<int>(i), values[i]);
  }
  reference->Update();
  double ib[6];
  image->GetBounds(ib);
  imageBox = {{{ib[0], ib[2], ib[4]}}, {{ib[1], ib[3], ib[5]}}};
  return reference->GetOutput();
}

TEST(Contour2D, UniformForestCrossesImageEdgesLikeVtk)
{
  // Every leaf at one level: the leaf centres are an image. VTK's contour of
  // that image crosses its edges where this contour crosses the same
  // (axis-aligned) dual edges; this one also crosses each quad's diagonal and
  // covers the boundary strip outside the image.
  for (int branch : {2, 3})
  {
    const int level = branch == 2 ? 4 : 2;
    GridSpec spec;
    spec.branchFactor = branch;
    spec.roots = {{3, 2, 1}};
    spec.irregular = false;
    spec.maxLevel = level;
    spec.refine = [](int, const Box&) { return true; };
    auto circle = [](const Point& x)
    { return std::hypot(x[0] - 0.3, x[1] - 1.4) + 0.1 * std::sin(3 * x[0]); };
    TestGrid grid = makeGrid(spec, circle);
    const std::vector<double> values{0.45, 0.9, 1.3};
    auto out = contour(grid.htg, values);

    const int per = level == 4 ? 16 : 9;
    const double h = 1.0 / per;
    Box imageBox;
    const vtkSmartPointer<vtkPolyData> vtk = vtkContourOfCentres(
        {{3 * per, 2 * per, 1}}, h,
        {{grid.domain.lo[0] + h / 2, grid.domain.lo[1] + h / 2, grid.domain.lo[2]}}, circle, values,
        imageBox);
    ASSERT_GT(vtk->GetNumberOfPoints(), 50);

    // Our points on the image's edges: inside its box, one coordinate on a
    // row or column of centres.
    auto onLine = [&](double x, int axis)
    {
      const double i = (x - imageBox.lo[axis]) / h;
      return std::abs(i - std::round(i)) < 1e-9;
    };
    std::vector<Point> ours;
    for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
    {
      const Point x = pointOf(out, p);
      if (inside(imageBox, x) && (onLine(x[0], 0) || onLine(x[1], 1)))
      {
        ours.push_back(x);
      }
    }
    std::vector<Point> theirs;
    for (vtkIdType p = 0; p < vtk->GetNumberOfPoints(); ++p)
    {
      theirs.push_back(pointOf(vtk, p));
    }
    auto sorted = [](std::vector<Point> v)
    {
      std::sort(v.begin(), v.end());
      return v;
    };
    ours = sorted(ours);
    theirs = sorted(theirs);
    ASSERT_EQ(ours.size(), theirs.size()) << "branch factor " << branch;
    // Matched greedily by nearest (coordinates agree to rounding).
    std::vector<bool> used(ours.size(), false);
    for (const Point& x : theirs)
    {
      double best = 1e300;
      std::size_t at = 0;
      for (std::size_t i = 0; i < ours.size(); ++i)
      {
        if (!used[i] && length(ours[i], x) < best)
        {
          best = length(ours[i], x);
          at = i;
        }
      }
      // VTK's 2D image contours write float points.
      ASSERT_LT(best, 1e-6) << "branch factor " << branch;
      used[at] = true;
    }
    expectWatertight2D(out, grid, "uniform, branch factor " + std::to_string(branch));
  }
}

TEST(Contour2D, InterpolatedFieldAndCanopyBuiltForests)
{
  // A forest as a simulation describes it (Canopy's builder, depth-first
  // storage, masks): still watertight; "g" = 2 f + 1 interpolated on the
  // contour of f is 2 c + 1 wherever the contour is not extrapolated.
  for (std::uint64_t seed = 1; seed <= 4; ++seed)
  {
    RandomForestOptions o;
    o.dimension = 2;
    o.branchFactor = seed % 2 ? 2 : 3;
    o.rootCells = {{3, 3, 1}};
    o.maxLevels = o.branchFactor == 2 ? 6 : 4;
    o.refineProbability = 0.45;
    o.maskProbability = seed > 2 ? 0.1 : 0.0;
    o.order = StorageOrder::DepthFirst;
    o.seed = seed;
    RandomForest forest(o);
    TestGrid grid;
    grid.htg = buildHyperTreeGrid(forest.description());
    describe(grid, wavy);
    auto out = contour(grid.htg, {-0.2, 0.3}, {"g"});
    const std::string what = "random forest " + std::to_string(seed);
    EXPECT_GT(expectWatertight2D(out, grid, what), 10u) << what;
    vtkDataArray* g = out->GetPointData()->GetArray("g");
    vtkDataArray* f = out->GetPointData()->GetArray("f");
    ASSERT_TRUE(g && f) << what;
    for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
    {
      if (awayFromBoundary(grid, pointOf(out, p)))
      {
        // Both edge ends are leaves: no extrapolation.
        EXPECT_NEAR(g->GetComponent(p, 0), 2 * f->GetComponent(p, 0) + 1, 1e-12)
            << what << " at " << pointOf(out, p)[0] << " " << pointOf(out, p)[1] << " domain "
            << grid.domain.lo[0] << " " << grid.domain.hi[0] << " " << grid.domain.lo[1] << " "
            << grid.domain.hi[1];
      }
    }
  }
}

// ---- 3D -------------------------------------------------------------------

double wavy3(const Point& x)
{
  return std::sin(1.3 * x[0] + 0.2) * std::cos(0.9 * x[1] - 0.4) + 0.3 * std::sin(1.7 * x[2]) +
         0.25 * x[0];
}

TEST(Contour3D, WatertightOnRandomAdaptiveForests)
{
  for (std::uint64_t seed = 1; seed <= 4; ++seed)
  {
    for (int branch : {2, 3})
    {
      const std::string what =
          "seed " + std::to_string(seed) + ", branch factor " + std::to_string(branch);
      TestGrid grid = makeGrid(randomSpec(3, branch, seed), wavy3);
      auto out = contour(grid.htg, {-0.5, 0.0, 0.45});
      const std::size_t triangles = expectWatertight3D(out, grid, what);
      EXPECT_GT(triangles, 200u) << what;
      EXPECT_GE(grid.deepest, branch == 2 ? 4 : 3) << what;
    }
  }
}

TEST(Contour3D, WatertightAroundMasksAndMissingTrees)
{
  for (std::uint64_t seed = 1; seed <= 3; ++seed)
  {
    for (int branch : {2, 3})
    {
      const std::string what =
          "seed " + std::to_string(seed) + ", branch factor " + std::to_string(branch);
      GridSpec spec = randomSpec(3, branch, seed);
      // Root cells of one shape: where trees of other aspect ratios meet, an
      // edge between two leaves' centres can cut a corner of a third leaf
      // (docs/filters.md).
      spec.irregular = false;
      spec.mask = [seed](int level, const Box& b) { return coin(seed + 99, level, b) < 0.1; };
      spec.missingTrees = {static_cast<vtkIdType>(seed % 8)};
      TestGrid grid = makeGrid(spec, wavy3);
      auto out = contour(grid.htg, {-0.5, 0.0, 0.45});
      EXPECT_GT(expectWatertight3D(out, grid, what), 100u) << what;
      // No triangle inside a hidden region: neither its corners nor its centroid.
      for (const auto& t : cellsOf(out->GetPolys()))
      {
        const Point a = pointOf(out, t[0]);
        const Point b = pointOf(out, t[1]);
        const Point c = pointOf(out, t[2]);
        const Point m{
            {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3}};
        for (const Box& h : grid.hidden)
        {
          for (const Point& x : {a, b, c, m})
          {
            ASSERT_FALSE(strictlyInside(h, x))
                << what << " x " << x[0] << " " << x[1] << " " << x[2] << " box " << h.lo[0] << " "
                << h.hi[0] << " " << h.lo[1] << " " << h.hi[1] << " " << h.lo[2] << " " << h.hi[2];
          }
        }
      }
    }
  }
}

enum class Forests
{
  Graded,    ///< gradedSpec: level jumps of one
  Unbalanced ///< randomSpec: jumps of up to four levels
};

void expectExactPlanes(bool irregular, Forests forests = Forests::Graded)
{
  // Every vertex on the plane, normals against the gradient, and the area of
  // the plane inside the domain: a crack, an overlap or an uncovered boundary
  // strip would change it.
  const Point a{{0.37, -0.81, 0.52}};
  const double b = 0.05;
  auto linear = [&](const Point& x) { return a[0] * x[0] + a[1] * x[1] + a[2] * x[2] + b; };
  const double norm = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  for (std::uint64_t seed = 1; seed <= 4; ++seed)
  {
    for (int branch : {2, 3})
    {
      const std::string what = "seed " + std::to_string(seed) + ", branch factor " +
                               std::to_string(branch) + (irregular ? ", irregular" : "");
      GridSpec spec =
          forests == Forests::Graded ? gradedSpec(3, branch, seed) : randomSpec(3, branch, seed);
      spec.irregular = irregular;
      TestGrid grid = makeGrid(spec, linear);
      const std::vector<double> values{-1.2, -0.3, 0.0123, 0.4};
      auto out = contour(grid.htg, values, {"g"});
      vtkDataArray* contourValue = out->GetPointData()->GetArray("f");
      vtkDataArray* normals = out->GetPointData()->GetNormals();
      vtkDataArray* g = out->GetPointData()->GetArray("g");
      ASSERT_TRUE(contourValue && normals && g) << what;
      for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
      {
        const double c = contourValue->GetComponent(p, 0);
        ASSERT_NEAR(linear(pointOf(out, p)), c, 1e-12) << what;
        for (int k = 0; k < 3; ++k)
        {
          ASSERT_NEAR(normals->GetComponent(p, k), -a[static_cast<std::size_t>(k)] / norm, 1e-9)
              << what << " point " << p << " at " << pointOf(out, p)[0] << " " << pointOf(out, p)[1]
              << " " << pointOf(out, p)[2] << " cells "
              << [&]
          {
            vtkNew<vtkIdList> cells;
            out->BuildLinks();
            out->GetPointCells(p, cells);
            std::string r;
            for (vtkIdType c : *cells)
            {
              vtkNew<vtkIdList> pts;
              out->GetCellPoints(c, pts);
              for (vtkIdType q : *pts)
              {
                const Point x = pointOf(out, q);
                r += "(" + std::to_string(x[0]) + "," + std::to_string(x[1]) + "," +
                     std::to_string(x[2]) + ")";
              }
              r += "; ";
            }
            return r;
          }();
        }
        if (awayFromBoundary(grid, pointOf(out, p)))
        {
          ASSERT_NEAR(g->GetComponent(p, 0), 2 * c + 1, 1e-12) << what;
        }
      }
      std::vector<double> total(values.size(), 0.0);
      for (const auto& t : cellsOf(out->GetPolys()))
      {
        const double c = contourValue->GetComponent(t[0], 0);
        const auto k = std::find(values.begin(), values.end(), c) - values.begin();
        total[static_cast<std::size_t>(k)] +=
            triangleArea(pointOf(out, t[0]), pointOf(out, t[1]), pointOf(out, t[2]));
      }
      for (std::size_t k = 0; k < values.size(); ++k)
      {
        // Unbalanced forests: a few dual cells around jumps of several levels
        // fold (docs/filters.md): watertight, on the plane, not exact in area.
        const double expected = planeAreaInBox(a, values[k] - b, grid.domain);
        EXPECT_NEAR(total[k], expected,
                    (forests == Forests::Unbalanced ? 0.01 : 1e-10) * (1 + expected))
            << what << ", value " << values[k];
      }
      EXPECT_GT(total[2], 1.0) << what;
      EXPECT_GE(grid.deepest, branch == 2 ? 4 : 3) << what;
    }
  }
}

TEST(Contour3D, LinearFieldIsExactUpToTheBoundary)
{
  expectExactPlanes(false);
}

TEST(Contour3D, LinearFieldOnUnbalancedForests)
{
  expectExactPlanes(false, Forests::Unbalanced);
}

TEST(Contour3D, LinearFieldIsExactAcrossTreesOfOtherShapes)
{
  expectExactPlanes(true);
}

TEST(Contour3D, UniformForestCrossesImageEdgesLikeVtk)
{
  // Every leaf at one level: VTK's contour of the image of leaf centres
  // crosses the image's edges where this contour crosses the same dual edges;
  // marching tetrahedra also crosses the diagonals (more, smaller triangles:
  // the area is compared, not the count) and covers the boundary strip.
  for (int branch : {2, 3})
  {
    const int level = branch == 2 ? 3 : 2;
    GridSpec spec;
    spec.dimension = 3;
    spec.branchFactor = branch;
    spec.roots = {{2, 2, 2}};
    spec.irregular = false;
    spec.maxLevel = level;
    spec.refine = [](int, const Box&) { return true; };
    auto sphere = [](const Point& x)
    {
      return std::sqrt((x[0] - 0.1) * (x[0] - 0.1) + (x[1] - 1.4) * (x[1] - 1.4) +
                       (x[2] - 1.9) * (x[2] - 1.9));
    };
    TestGrid grid = makeGrid(spec, sphere);
    const std::vector<double> values{0.55, 0.8};
    auto out = contour(grid.htg, values);

    const int per = level == 3 ? 8 : 9;
    const double h = 1.0 / per;
    Box imageBox;
    const vtkSmartPointer<vtkPolyData> vtk = vtkContourOfCentres(
        {{2 * per, 2 * per, 2 * per}}, h,
        {{grid.domain.lo[0] + h / 2, grid.domain.lo[1] + h / 2, grid.domain.lo[2] + h / 2}}, sphere,
        values, imageBox);
    ASSERT_GT(vtk->GetNumberOfPoints(), 100);
    auto onLine = [&](double x, int axis)
    {
      const double i = (x - imageBox.lo[axis]) / h;
      return std::abs(i - std::round(i)) < 1e-9;
    };
    // On an image edge: on grid lines along two axes.
    std::vector<Point> ours;
    double ourArea = 0;
    for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
    {
      const Point x = pointOf(out, p);
      const int lines = onLine(x[0], 0) + onLine(x[1], 1) + onLine(x[2], 2);
      if (inside(imageBox, x) && lines >= 2)
      {
        ours.push_back(x);
      }
    }
    std::vector<Point> theirs;
    for (vtkIdType p = 0; p < vtk->GetNumberOfPoints(); ++p)
    {
      theirs.push_back(pointOf(vtk, p));
    }
    ASSERT_EQ(ours.size(), theirs.size()) << "branch factor " << branch;
    std::vector<bool> used(ours.size(), false);
    for (const Point& x : theirs)
    {
      double best = 1e300;
      std::size_t at = 0;
      for (std::size_t i = 0; i < ours.size(); ++i)
      {
        if (!used[i] && length(ours[i], x) < best)
        {
          best = length(ours[i], x);
          at = i;
        }
      }
      ASSERT_LT(best, 1e-6) << "branch factor " << branch; // VTK writes float points
      used[at] = true;
    }
    // Areas inside the image's box: both approximate the same spheres.
    double theirArea = 0;
    for (const auto& t : cellsOf(vtk->GetPolys()))
    {
      theirArea += triangleArea(pointOf(vtk, t[0]), pointOf(vtk, t[1]), pointOf(vtk, t[2]));
    }
    std::size_t ourInside = 0;
    for (const auto& t : cellsOf(out->GetPolys()))
    {
      const Point a = pointOf(out, t[0]);
      const Point b = pointOf(out, t[1]);
      const Point c = pointOf(out, t[2]);
      if (inside(imageBox, a) && inside(imageBox, b) && inside(imageBox, c))
      {
        ourArea += triangleArea(a, b, c);
        ++ourInside;
      }
    }
    EXPECT_NEAR(ourArea, theirArea, 0.02 * theirArea) << "branch factor " << branch;
    EXPECT_GT(ourInside, static_cast<std::size_t>(vtk->GetNumberOfPolys()));
    expectWatertight3D(out, grid, "uniform, branch factor " + std::to_string(branch));
  }
}

// ---- Pruning ----------------------------------------------------------------

/// Both outputs alike, bit for bit: points, cells, point arrays.
void expectSameOutput(vtkPolyData* a, vtkPolyData* b, const std::string& what)
{
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints()) << what;
  for (vtkIdType p = 0; p < a->GetNumberOfPoints(); ++p)
  {
    ASSERT_EQ(pointOf(a, p), pointOf(b, p)) << what;
  }
  for (auto cells :
       {std::make_pair(a->GetLines(), b->GetLines()), std::make_pair(a->GetPolys(), b->GetPolys())})
  {
    ASSERT_EQ(cellsOf(cells.first), cellsOf(cells.second)) << what;
  }
  ASSERT_EQ(a->GetPointData()->GetNumberOfArrays(), b->GetPointData()->GetNumberOfArrays());
  for (int i = 0; i < a->GetPointData()->GetNumberOfArrays(); ++i)
  {
    vtkDataArray* x = a->GetPointData()->GetArray(i);
    vtkDataArray* y = b->GetPointData()->GetArray(x->GetName());
    ASSERT_NE(y, nullptr) << what;
    for (vtkIdType t = 0; t < x->GetNumberOfTuples(); ++t)
    {
      for (int c = 0; c < x->GetNumberOfComponents(); ++c)
      {
        ASSERT_EQ(x->GetComponent(t, c), y->GetComponent(t, c)) << what;
      }
    }
  }
}

TEST(ContourPruning, SameOutputLessWorkOnASphere)
{
  // A forest refined everywhere and more around a sphere, as a simulation
  // refines around a front; the sphere's distance field contoured at its
  // radius. Pruned, only the nodes along the surface are descended.
  for (int dimension : {2, 3})
  {
    for (int branch : {2, 3})
    {
      const std::string what =
          std::to_string(dimension) + "D, branch factor " + std::to_string(branch);
      const Point centre{{0.25, 2.0, 2.5}}; // the domain's middle
      auto distance = [&](const Point& x)
      {
        double d2 = 0;
        for (int k = 0; k < dimension; ++k)
        {
          d2 += (x[k] - centre[k]) * (x[k] - centre[k]);
        }
        return std::sqrt(d2);
      };
      const double radius = 0.45;
      GridSpec spec;
      spec.dimension = dimension;
      spec.branchFactor = branch;
      spec.irregular = false;
      spec.roots = {{3, 3, 3}};
      spec.maxLevel = branch == 2 ? (dimension == 2 ? 7 : 5) : (dimension == 2 ? 5 : 3);
      const int uniform = spec.maxLevel - (branch == 2 ? 2 : 1);
      spec.refine = [&](int level, const Box& b)
      {
        // Refined everywhere to a level, and deeper where the box comes within
        // its own size of the sphere: most nodes are far from the surface.
        if (level < uniform)
        {
          return true;
        }
        Point mid;
        double size = 0;
        for (int k = 0; k < 3; ++k)
        {
          mid[k] = 0.5 * (b.lo[k] + b.hi[k]);
          size = std::max(size, b.hi[k] - b.lo[k]);
        }
        return std::abs(distance(mid) - radius) < size;
      };
      spec.mask = [](int level, const Box& b) { return level > 1 && coin(7, level, b) < 0.05; };
      TestGrid grid = makeGrid(spec, distance);
      vtkIdType visited[2] = {0, 0};
      vtkSmartPointer<vtkPolyData> outputs[2];
      for (int prune : {0, 1})
      {
        vtkNew<vtkCanopyContour> filter;
        filter->SetInputData(grid.htg);
        filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
        filter->SetValue(0, radius);
        filter->SetValue(1, radius * 0.97);
        filter->AddInterpolatedField("g");
        filter->SetPruning(prune != 0);
        filter->Update();
        outputs[prune] = filter->GetOutput();
        visited[prune] = filter->GetLastVisited();
        EXPECT_EQ(filter->GetLastPruned() > 0, prune != 0) << what;
      }
      EXPECT_GT(outputs[0]->GetNumberOfCells(), 50) << what;
      expectSameOutput(outputs[0], outputs[1], what);
      std::cout << what << ": groups descended " << visited[0] << " without pruning, " << visited[1]
                << " with\n";
      EXPECT_LT(3 * visited[1], visited[0]) << what;
    }
  }
}

// ---- Zero copy ----------------------------------------------------------------

TEST(ContourZeroCopy, FieldsAreReadInPlace)
{
  // A simulation's depth-first field (read through the cell -> slot table) and a
  // strided one: contouring them and interpolating one onto the contour neither
  // writes the simulation's memory nor detaches a copy (a later change of the
  // simulation's values is seen through the grid, and by the next contour).
  RandomForestOptions o;
  o.dimension = 3;
  o.rootCells = {{3, 2, 2}};
  o.maxLevels = 4;
  o.refineProbability = 0.5;
  o.order = StorageOrder::DepthFirst;
  o.seed = 5;
  RandomForest forest(o);
  const std::size_t n = forest.numberOfNodes();
  struct Record
  {
    double value;
    double other;
  };
  std::vector<Record> records(n);
  for (std::size_t s = 0; s < n; ++s)
  {
    records[s] = {std::sin(0.37 * static_cast<double>(s)), static_cast<double>(s)};
  }
  auto& d = forest.description();
  d.fields.push_back(FieldDescription::strided("value", &records[0].value, sizeof(Record), n));
  d.fields.push_back(FieldDescription::strided("other", &records[0].other, sizeof(Record), n));
  auto htg = buildHyperTreeGrid(d);
  const std::uint64_t before = checksum(records.data(), n * sizeof(Record));
  vtkNew<vtkCanopyContour> filter;
  filter->SetInputData(htg);
  filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "value");
  filter->SetValue(0, 0.1);
  filter->AddInterpolatedField("other");
  filter->Update();
  const vtkIdType first = filter->GetOutput()->GetNumberOfCells();
  EXPECT_GT(first, 100);
  EXPECT_EQ(checksum(records.data(), n * sizeof(Record)), before) << "simulation memory written";
  // Every value moved above the contour value: seen through the grid's arrays
  // (not detached), and the contour of the same grid is now empty.
  for (Record& r : records)
  {
    r.value = 2.0;
  }
  vtkDataArray* value = htg->GetCellData()->GetArray("value");
  for (vtkIdType c = 0; c < value->GetNumberOfTuples(); c += 7)
  {
    ASSERT_EQ(value->GetComponent(c, 0), 2.0) << "the field was copied";
  }
  htg->Modified();
  filter->Update();
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);
}

// ---- Convergence ----------------------------------------------------------------

TEST(ContourConvergence, SphereAreaAndVolume)
{
  // f = |x - c|, the forest refined around the sphere |x - c| = r (one level
  // more at each step): the isosurface's area and enclosed volume (divergence
  // theorem over the oriented triangles: it needs every triangle oriented
  // alike) converge to 4 pi r^2 and 4 pi r^3 / 3; the observed order is
  // printed and must be at least 1.5 (linear interpolation: 2). 2D: the
  // circle's length and area.
  const double pi = std::acos(-1.0);
  for (int dimension : {2, 3})
  {
    const Point centre{{0.27, 2.03, 2.41}};
    const double r = 0.61;
    auto distance = [&](const Point& x)
    {
      double d2 = 0;
      for (int k = 0; k < dimension; ++k)
      {
        d2 += (x[k] - centre[k]) * (x[k] - centre[k]);
      }
      return std::sqrt(d2);
    };
    std::vector<double> sizeErrors;
    std::vector<double> volumeErrors;
    const int first = 2;
    const int last = dimension == 2 ? 7 : 5;
    for (int levels = first; levels <= last; ++levels)
    {
      GridSpec spec;
      spec.dimension = dimension;
      spec.irregular = false;
      spec.roots = {{3, 3, 3}};
      spec.maxLevel = levels;
      spec.refine = [&](int, const Box& b)
      {
        Point mid;
        double size = 0;
        for (int k = 0; k < 3; ++k)
        {
          mid[k] = 0.5 * (b.lo[k] + b.hi[k]);
          size = std::max(size, b.hi[k] - b.lo[k]);
        }
        return std::abs(distance(mid) - r) < size;
      };
      TestGrid grid = makeGrid(spec, distance);
      auto out = contour(grid.htg, {r});
      double size = 0;   // length or area
      double volume = 0; // area or volume, signed by orientation
      if (dimension == 2)
      {
        for (const auto& seg : cellsOf(out->GetLines()))
        {
          const Point a = pointOf(out, seg[0]);
          const Point b = pointOf(out, seg[1]);
          size += length(a, b);
          volume += 0.5 * ((a[0] - centre[0]) * (b[1] - centre[1]) -
                           (b[0] - centre[0]) * (a[1] - centre[1]));
        }
      }
      else
      {
        for (const auto& t : cellsOf(out->GetPolys()))
        {
          Point p[3];
          for (int k = 0; k < 3; ++k)
          {
            p[k] = pointOf(out, t[static_cast<std::size_t>(k)]);
            for (int a = 0; a < 3; ++a)
            {
              p[k][a] -= centre[a];
            }
          }
          size += triangleArea(p[0], p[1], p[2]);
          volume += (p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                     p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                     p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0])) /
                    6;
        }
      }
      const double exactSize = dimension == 2 ? 2 * pi * r : 4 * pi * r * r;
      const double exactVolume = dimension == 2 ? pi * r * r : 4 * pi * r * r * r / 3;
      sizeErrors.push_back(std::abs(size - exactSize) / exactSize);
      // Segments run with higher values on their left, normals point to lower
      // values: the circle is clockwise, the sphere's normals point inwards.
      volumeErrors.push_back(std::abs(-volume - exactVolume) / exactVolume);
      std::cout << dimension << "D, " << levels << " levels: " << out->GetNumberOfCells()
                << " cells, relative error of the " << (dimension == 2 ? "length " : "area ")
                << sizeErrors.back() << ", of the " << (dimension == 2 ? "area " : "volume ")
                << volumeErrors.back() << "\n";
    }
    for (const auto* errors : {&sizeErrors, &volumeErrors})
    {
      // Order over the last two refinements (each halves the cells).
      const std::size_t n = errors->size();
      const double order = std::log2((*errors)[n - 2] / (*errors)[n - 1]);
      std::cout << dimension << "D observed order " << order << "\n";
      EXPECT_GT(order, 1.5) << dimension << "D";
      EXPECT_LT(errors->back(), dimension == 2 ? 1e-3 : 1e-2) << dimension << "D";
    }
  }
}

// ---- Errors -----------------------------------------------------------------

TEST(ContourErrors, EachProblemNamedAndAnEmptyOutput)
{
  GridSpec spec = randomSpec(2, 2, 3);
  TestGrid grid = makeGrid(spec, wavy);
  auto expectError = [](vtkCanopyContour* filter, const std::string& words)
  {
    const auto errors = errorsOfUpdate(filter);
    ASSERT_EQ(errors.size(), 1u) << words;
    EXPECT_NE(errors[0].find(words), std::string::npos) << errors[0];
    EXPECT_EQ(filter->GetOutput()->GetNumberOfPoints(), 0) << words;
  };
  vtkNew<vtkCanopyContour> filter;
  filter->SetInputData(grid.htg);
  filter->SetValue(0, 0.1);
  filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "nothing");
  expectError(filter, "no cell field to contour");
  filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
  filter->SetArrayComponent(1);
  expectError(filter, "component 1 of f");
  filter->SetArrayComponent(0);
  filter->AddInterpolatedField("missing");
  expectError(filter, "no cell field missing");
  filter->ClearInterpolatedFields();
  EXPECT_TRUE(errorsOfUpdate(filter).empty());
  EXPECT_GT(filter->GetOutput()->GetNumberOfCells(), 0);
  // No values: nothing to draw, no error.
  filter->SetNumberOfContours(0);
  EXPECT_TRUE(errorsOfUpdate(filter).empty());
  EXPECT_EQ(filter->GetOutput()->GetNumberOfCells(), 0);

  // A 1D grid has no contour lines to draw: said so.
  RandomForestOptions line;
  line.dimension = 1;
  line.rootCells = {{4, 1, 1}};
  RandomForest forest(line);
  TestGrid lineGrid;
  lineGrid.htg = buildHyperTreeGrid(forest.description());
  describe(lineGrid, wavy);
  vtkNew<vtkCanopyContour> onLine;
  onLine->SetInputData(lineGrid.htg);
  onLine->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
  onLine->SetValue(0, 0.1);
  expectError(onLine, "2D or 3D grid");
}

// ---- Split grids -------------------------------------------------------------

TEST(ContourSplit, EachRankDrawsItsOwnPartNoOverlap)
{
  // A forest split between ranks (other ranks' parts absent): each rank's
  // contour is part of the whole forest's (the same triangles, point for point,
  // away from the domain's boundary, where a boundary vertex's gradient may
  // miss another rank's leaves) and no triangle is drawn by two ranks: a dual
  // cell touching another rank's part is left out: without a controller a part
  // is contoured alone (the exchange between real ranks: SplitContour.* in
  // tests/mpi/SplitContourTest.cxx).
  for (int dimension : {2, 3})
  {
    RandomForestOptions o;
    o.dimension = dimension;
    o.rootCells = dimension == 2 ? std::array<std::size_t, 3>{{4, 3, 1}}
                                 : std::array<std::size_t, 3>{{2, 2, 2}};
    o.maxLevels = dimension == 2 ? 6 : 4;
    o.refineProbability = 0.55;
    o.seed = 11;
    RandomForest whole(o);
    auto cellsAsPoints = [](vtkPolyData* out)
    {
      std::vector<std::vector<Point>> cells;
      for (auto ids : cellsOf(drawnCells(out)))
      {
        std::vector<Point> c;
        for (vtkIdType id : ids)
        {
          c.push_back(pointOf(out, id));
        }
        std::sort(c.begin(), c.end());
        cells.push_back(c);
      }
      return cells;
    };
    auto contourOf = [](vtkHyperTreeGrid* htg)
    {
      vtkNew<vtkCanopyContour> filter;
      filter->SetInputData(htg);
      filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "hash");
      filter->SetValue(0, 0.5);
      filter->Update();
      return vtkSmartPointer<vtkPolyData>(filter->GetOutput());
    };
    RankPart all(whole.description(), 0, 1, false);
    TestGrid reference;
    reference.htg = buildHyperTreeGrid(all.description);
    describe(reference, wavy); // the leaves' boxes (adds f and g, not contoured)
    const auto wholeCells = cellsAsPoints(contourOf(reference.htg));
    std::map<std::vector<Point>, int> drawn;
    std::size_t eligible = 0; // the whole forest's cells away from the boundary
    for (const auto& c : wholeCells)
    {
      drawn[c] = 0;
      eligible += std::all_of(c.begin(), c.end(),
                              [&](const Point& x) { return awayFromBoundary(reference, x); });
    }
    ASSERT_GT(drawn.size(), 100u);
    for (int ranks : {2, 3})
    {
      for (auto& entry : drawn)
      {
        entry.second = 0;
      }
      std::size_t compared = 0;
      for (int rank = 0; rank < ranks; ++rank)
      {
        RankPart part(whole.description(), rank, ranks, rank % 2 == 1);
        auto htg = buildHyperTreeGrid(part.description);
        for (const auto& c : cellsAsPoints(contourOf(htg)))
        {
          if (!std::all_of(c.begin(), c.end(),
                           [&](const Point& x) { return awayFromBoundary(reference, x); }))
          {
            continue;
          }
          ++compared;
          const auto found = drawn.find(c);
          ASSERT_NE(found, drawn.end()) << dimension << "D, " << ranks << " ranks: rank " << rank
                                        << " drew a cell the whole forest does not have";
          EXPECT_EQ(++found->second, 1) << dimension << "D: a cell drawn by two ranks";
        }
      }
      std::cout << dimension << "D, " << ranks << " ranks: " << compared << " of the " << eligible
                << " cells away from the boundary drawn\n";
      // What the ranks leave out: the cells along their parts' borders.
      EXPECT_GT(compared, eligible / 2) << dimension << "D, " << ranks << " ranks";
      EXPECT_LT(compared, eligible) << dimension << "D, " << ranks << " ranks";
    }
  }
}

TEST(ContourPruning, RangesInReverseEqualTheWalkFromTheRoot)
{
  // NodeRanges' pass over each tree's nodes from the last to the first (then
  // along the domain's boundary) against its walk from the root, node by
  // node, on every node the contour can reach: 2D and 3D, binary and ternary,
  // masks and missing trees, a field whose contours reach the boundary.
  std::size_t compared = 0;
  std::size_t widened = 0;
  for (int dimension : {2, 3})
  {
    for (int branch : {2, 3})
    {
      for (std::uint64_t seed = 1; seed <= 3; ++seed)
      {
        GridSpec spec = randomSpec(dimension, branch, seed);
        spec.mask = [seed](int level, const Box& b)
        { return level > 0 && coin(seed + 7, level, b) < 0.08; };
        spec.missingTrees = {static_cast<vtkIdType>(seed % 4)};
        TestGrid grid = makeGrid(spec, wavy3);
        const std::string what = std::to_string(dimension) + "D, branch factor " +
                                 std::to_string(branch) + ", seed " + std::to_string(seed);
        canopy::HyperTreeAccess access(grid.htg, true, false);
        // Some coarse values NaN (a leaves-only field's average over a NaN
        // leaf): the children's ranges hold whatever the node's own value.
        vtkDataArray* f = grid.htg->GetCellData()->GetArray("f");
        for (const canopy::TreeAccess& tree : access.trees())
        {
          for (vtkIdType node = 0; node < tree.numberOfVertices; node += 5)
          {
            if (!tree.isLeaf(node))
            {
              f->SetComponent(tree.globalIndex(node), 0, std::nan(""));
            }
          }
        }
        const canopy::DualTraversal dual(access);
        const canopy::ContourField field(grid.htg->GetCellData()->GetArray("f"), 0);
        const canopy::NodeRanges reverse(access, dual, field, {});
        const canopy::NodeRanges walk(access, dual, field, {}, false);
        for (std::size_t t = 0; t < access.trees().size(); ++t)
        {
          const canopy::TreeAccess& tree = access.trees()[t];
          std::vector<vtkIdType> stack{0};
          while (!stack.empty())
          {
            const vtkIdType node = stack.back();
            stack.pop_back();
            const vtkIdType global = tree.globalIndex(node);
            if (access.isMasked(global) || access.isAbsent(global))
            {
              continue;
            }
            const canopy::ValueRange& a = reverse.at(t, node);
            const canopy::ValueRange& b = walk.at(t, node);
            ASSERT_EQ(a.low, b.low) << what << ", tree " << t << ", node " << node;
            ASSERT_EQ(a.high, b.high) << what << ", tree " << t << ", node " << node;
            ASSERT_FALSE(std::isnan(a.low) || std::isnan(a.high)) << what << ", node " << node;
            ++compared;
            const double own = field(global);
            widened += tree.isLeaf(node) && (a.low < own || a.high > own) ? 1 : 0;
            for (int c = 0; !tree.isLeaf(node) && c < access.childrenPerNode(); ++c)
            {
              stack.push_back(tree.firstChild(node) + c);
            }
          }
        }
      }
    }
  }
  std::cout << compared << " nodes compared, " << widened << " boundary leaves widened\n";
  EXPECT_GT(compared, 20000u);
  EXPECT_GT(widened, 500u);
}

TEST(ContourPruning, RangesKeptWhileTopologyAndFieldHold)
{
  // New contour values on the same grid and field: the ranges of the execution
  // before are pruned with (no pass over the nodes), and the output equals a
  // new filter's. A field modified, or another component: computed again.
  GridSpec spec = gradedSpec(3, 2, 2);
  TestGrid grid = makeGrid(spec, wavy3);
  vtkNew<vtkCanopyContour> kept;
  kept->SetInputData(grid.htg);
  kept->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
  kept->SetValue(0, 0.1);
  kept->Update();
  EXPECT_FALSE(kept->GetLastRangesKept());
  for (double value : {-0.4, 0.3})
  {
    kept->SetValue(0, value);
    kept->Update();
    EXPECT_TRUE(kept->GetLastRangesKept()) << value;
    vtkSmartPointer<vtkPolyData> fresh = contour(grid.htg, {value});
    expectSameOutput(kept->GetOutput(), fresh, "value " + std::to_string(value));
  }
  // The field's values changed (and said so): new ranges, the new contour.
  vtkDataArray* f = grid.htg->GetCellData()->GetArray("f");
  for (vtkIdType c = 0; c < f->GetNumberOfTuples(); ++c)
  {
    f->SetComponent(c, 0, f->GetComponent(c, 0) + 0.25);
  }
  f->Modified();
  grid.htg->Modified();
  kept->Update();
  EXPECT_FALSE(kept->GetLastRangesKept());
  expectSameOutput(kept->GetOutput(), contour(grid.htg, {0.3}), "after the field changed");
}

TEST(ContourThreads, SameOutputOnAnyBackend)
{
  // Parts of the grid run on threads in fixed chunks, merged in chunk order:
  // the output does not depend on the backend or the number of threads.
  TestGrid grid = makeGrid(randomSpec(3, 2, 4), wavy3);
  vtkSMPTools::SetBackend("Sequential");
  vtkSmartPointer<vtkPolyData> sequential = contour(grid.htg, {-0.5, 0.0, 0.45}, {"g"});
  vtkSMPTools::SetBackend("STDThread");
  vtkSMPTools::Initialize(4);
  vtkSmartPointer<vtkPolyData> threaded = contour(grid.htg, {-0.5, 0.0, 0.45}, {"g"});
  vtkSMPTools::SetBackend("Sequential");
  EXPECT_GT(sequential->GetNumberOfCells(), 1000);
  expectSameOutput(sequential, threaded, "Sequential against 4 STDThread threads");
}

TEST(Contour2D, GridsInEveryPlane)
{
  // 2D grids in the XY, XZ and YZ planes, offset: a linear field of the two
  // active coordinates gives isolines on their lines, in the grid's plane,
  // watertight, of the line's length inside the domain.
  for (int flat : {2, 1, 0})
  {
    RandomForestOptions o;
    o.dimension = 2;
    o.flatAxis = flat;
    o.rootCells = {{3, 3, 3}};
    o.maxLevels = 6;
    o.refineProbability = 0.5;
    o.seed = 7 + static_cast<std::uint64_t>(flat);
    o.origin = {{-3.5, 2.25, 10.0}};
    RandomForest forest(o);
    const int u = flat == 0 ? 1 : 0;
    const int v = flat == 2 ? 1 : 2;
    auto linear = [&](const Point& x) { return 0.6 * x[u] - 0.45 * x[v]; };
    TestGrid grid;
    grid.htg = buildHyperTreeGrid(forest.description());
    describe(grid, linear);
    const std::string what = "flat axis " + std::to_string(flat);
    const double c = 0.6 * (0.5 * (grid.domain.lo[u] + grid.domain.hi[u])) -
                     0.45 * (0.5 * (grid.domain.lo[v] + grid.domain.hi[v]));
    auto out = contour(grid.htg, {c});
    expectWatertight2D(out, grid, what);
    double total = 0;
    for (const auto& seg : cellsOf(out->GetLines()))
    {
      const Point p = pointOf(out, seg[0]);
      const Point q = pointOf(out, seg[1]);
      EXPECT_NEAR(linear(p), c, 1e-12) << what;
      EXPECT_EQ(p[flat], grid.domain.lo[flat]) << what << ": in the grid's plane";
      total += length(p, q);
    }
    // The line's length in the domain's rectangle, in (u, v) coordinates.
    Box box;
    box.lo = {{grid.domain.lo[u], grid.domain.lo[v], 0}};
    box.hi = {{grid.domain.hi[u], grid.domain.hi[v], 0}};
    const double expected = lineLengthInBox({{0.6, -0.45}}, c, box);
    EXPECT_NEAR(total, expected, 1e-11 * (1 + expected)) << what;
    EXPECT_GT(total, 0.5) << what;
  }
}

TEST(ContourThreads, WatertightAcrossChunks)
{
  // Many trees: the traversal runs in many chunks (16 root tasks each), whose
  // points along their borders are merged by key, the others not looked up:
  // still watertight (a point left unmerged would end its cells' edges once).
  for (int dimension : {2, 3})
  {
    for (int branch : {2, 3})
    {
      GridSpec spec = randomSpec(dimension, branch, 9);
      spec.roots = dimension == 2 ? std::array<int, 3>{{9, 7, 1}} : std::array<int, 3>{{4, 4, 3}};
      spec.maxLevel = branch == 2 ? (dimension == 2 ? 5 : 3) : 2;
      const std::string what =
          std::to_string(dimension) + "D, branch factor " + std::to_string(branch);
      TestGrid grid = makeGrid(spec, dimension == 2 ? wavy : wavy3);
      auto out = contour(grid.htg, {-0.3, 0.2});
      const std::size_t cells = dimension == 2 ? expectWatertight2D(out, grid, what)
                                               : expectWatertight3D(out, grid, what);
      EXPECT_GT(cells, 200u) << what;
    }
  }
}

TEST(Contour3D, LinearFieldAcrossChosenLevelJumps)
{
  // Trees of two depths side by side (LevelJumpForest: each tree uniform,
  // neighbours differing by one to three levels): the plane's area exactly
  // (1e-10) with dyadic roots, and with irregular ones up to jumps of two;
  // irregular roots with jumps of three fold a little (within 1%; measured
  // 3.7e-4).
  const Point a{{0.37, -0.81, 0.52}};
  auto linear = [&](const Point& x) { return a[0] * x[0] + a[1] * x[1] + a[2] * x[2]; };
  for (bool dyadic : {true, false})
  {
    for (int jump : {1, 2, 3})
    {
      LevelJumpForest forest({{3, 2, 2}}, 1, 1 + jump, dyadic);
      TestGrid grid;
      grid.htg = buildHyperTreeGrid(forest.description());
      describe(grid, linear);
      const double c = linear(middleOf(grid));
      auto out = contour(grid.htg, {c});
      const std::string what =
          "jump " + std::to_string(jump) + (dyadic ? ", dyadic roots" : ", irregular roots");
      expectWatertight3D(out, grid, what);
      double area = 0;
      for (const auto& t : cellsOf(out->GetPolys()))
      {
        area += triangleArea(pointOf(out, t[0]), pointOf(out, t[1]), pointOf(out, t[2]));
      }
      const double expected = planeAreaInBox(a, c, grid.domain);
      std::cout << what << ": area " << area << ", plane " << expected << ", relative error "
                << std::abs(area - expected) / expected << "\n";
      EXPECT_NEAR(area, expected, (dyadic || jump < 3 ? 1e-10 : 1e-2) * expected) << what;
    }
  }
}

// ---- Maximum level --------------------------------------------------------------

TEST(ContourMaximumLevel, CoarserForestsCrackFreeAlike)
{
  // Nodes at the maximum level hold their own values (here, the field at their
  // centre): the coarser forest's contour is watertight and, for a linear
  // field, exact; at or below the deepest level it is the full contour, bit
  // for bit.
  const Point a{{0.37, -0.81, 0.52}};
  auto linear = [&](const Point& x) { return a[0] * x[0] + a[1] * x[1] + a[2] * x[2]; };
  for (int dimension : {2, 3})
  {
    for (int branch : {2, 3})
    {
      GridSpec spec = dimension == 2 ? randomSpec(2, branch, 5) : gradedSpec(3, branch, 5);
      TestGrid grid = makeGrid(spec, linear);
      const double c = linear(middleOf(grid));
      auto contourAt = [&](int level)
      {
        vtkNew<vtkCanopyContour> filter;
        filter->SetInputData(grid.htg);
        filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
        filter->SetValue(0, c);
        filter->SetMaximumLevel(level);
        filter->Update();
        return vtkSmartPointer<vtkPolyData>(filter->GetOutput());
      };
      const auto full = contourAt(-1);
      expectSameOutput(full, contourAt(grid.deepest), "at the deepest level");
      vtkIdType previous = 0;
      for (int level = 0; level < grid.deepest; ++level)
      {
        const std::string what = std::to_string(dimension) + "D, branch factor " +
                                 std::to_string(branch) + ", maximum level " +
                                 std::to_string(level);
        const auto out = contourAt(level);
        // Watertight: nothing in this grid is hidden.
        const std::size_t cells = dimension == 2 ? expectWatertight2D(out, grid, what)
                                                 : expectWatertight3D(out, grid, what);
        double size = 0;
        for (const auto& cell : cellsOf(drawnCells(out)))
        {
          size += dimension == 2 ? length(pointOf(out, cell[0]), pointOf(out, cell[1]))
                                 : triangleArea(pointOf(out, cell[0]), pointOf(out, cell[1]),
                                                pointOf(out, cell[2]));
          for (vtkIdType id : cell)
          {
            ASSERT_NEAR(linear(pointOf(out, id)), c, 1e-12) << what;
          }
        }
        // 2D: the grid's plane z = z0, where the line is a.x + a.y = c - a_z z0.
        const double expected =
            dimension == 2
                ? lineLengthInBox({{a[0], a[1]}}, c - a[2] * grid.domain.lo[2], grid.domain)
                : planeAreaInBox(a, c, grid.domain);
        EXPECT_NEAR(size, expected, 1e-10 * (1 + expected)) << what;
        EXPECT_GE(static_cast<vtkIdType>(cells), previous) << what << ": finer, more cells";
        previous = static_cast<vtkIdType>(cells);
      }
      EXPECT_GE(full->GetNumberOfCells(), previous);
    }
  }
}

// ---- The view -------------------------------------------------------------------

TEST(ContourView, LevelOfDetailCrackFreeAndExact)
{
  // Nodes spanning at most a pixel are leaves holding their own values (here,
  // the field at their centre): on a small viewport the contour is coarser,
  // still watertight, and exact for a linear field.
  const Point a{{0.37, -0.81, 0.52}};
  auto linear = [&](const Point& x) { return a[0] * x[0] + a[1] * x[1] + a[2] * x[2]; };
  for (int dimension : {2, 3})
  {
    TestGrid grid = makeGrid(belowPixelSpec(dimension), linear);
    const Point mid = middleOf(grid);
    const double c = linear(mid);
    vtkNew<vtkCanopyContour> filter;
    filter->SetInputData(grid.htg);
    filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
    filter->SetValue(0, c);
    filter->Update();
    const vtkIdType fullCells = filter->GetOutput()->GetNumberOfCells();
    // The whole domain in a small viewport, parallel, along -z (2D) or obliquely.
    filter->ViewDependentOn();
    filter->ViewCullingOff();
    filter->LevelOfDetailOn();
    filter->SetCameraFocalPoint(mid[0], mid[1], mid[2]);
    filter->SetCameraPosition(mid[0] + (dimension == 3 ? 6 : 0), mid[1] - (dimension == 3 ? 5 : 0),
                              mid[2] + 10);
    filter->SetCameraViewUp(0, 1, 0);
    filter->ParallelProjectionOn();
    filter->SetParallelScale(3);
    filter->SetViewportSize(dimension == 3 ? 16 : 48, dimension == 3 ? 12 : 40);
    filter->Update();
    vtkPolyData* out = filter->GetOutput();
    const std::string what = std::to_string(dimension) + "D, level of detail";
    const std::size_t cells =
        dimension == 2 ? expectWatertight2D(out, grid, what) : expectWatertight3D(out, grid, what);
    double size = 0;
    for (const auto& cell : cellsOf(drawnCells(out)))
    {
      size += dimension == 2 ? length(pointOf(out, cell[0]), pointOf(out, cell[1]))
                             : triangleArea(pointOf(out, cell[0]), pointOf(out, cell[1]),
                                            pointOf(out, cell[2]));
      for (vtkIdType id : cell)
      {
        ASSERT_NEAR(linear(pointOf(out, id)), c, 1e-12) << what;
      }
    }
    const double expected =
        dimension == 2 ? lineLengthInBox({{a[0], a[1]}}, c - a[2] * grid.domain.lo[2], grid.domain)
                       : planeAreaInBox(a, c, grid.domain);
    EXPECT_NEAR(size, expected, 1e-10 * (1 + expected)) << what;
    std::cout << what << ": " << cells << " cells, " << fullCells << " at full resolution\n";
    EXPECT_LT(static_cast<vtkIdType>(cells), fullCells / 2) << what;
    EXPECT_GT(cells, 0u) << what;
  }
}

TEST(ContourView, RangesKeptAcrossCamerasSameOutputAsUnpruned)
{
  // The value ranges are the forest's, without the view: one pass, then kept
  // while the camera moves. Under level of detail, pruning with them must
  // still give the unpruned contour of the view's coarser forest, bit for bit,
  // along the domain's boundary too, where a coarse leaf extrapolates its
  // boundary vertices with its own gradient (a curved field, contour values
  // that reach every side).
  for (int dimension : {2, 3})
  {
    TestGrid grid = makeGrid(belowPixelSpec(dimension), wavy3);
    const Point mid = middleOf(grid);
    const std::vector<double> values{-0.5, 0.0, 0.45};
    auto configure = [&](vtkCanopyContour* f, bool prune)
    {
      f->SetInputData(grid.htg);
      f->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
      for (std::size_t i = 0; i < values.size(); ++i)
      {
        f->SetValue(static_cast<int>(i), values[i]);
      }
      f->SetPruning(prune);
      f->ViewDependentOn();
      f->LevelOfDetailOn();
      f->SetCameraViewUp(0, 1, 0);
    };
    vtkNew<vtkCanopyContour> kept;
    configure(kept, true);
    vtkIdType coarsest = std::numeric_limits<vtkIdType>::max();
    for (int camera = 0; camera < 5; ++camera)
    {
      // Parallel and perspective, whole domain and close up, square and wide.
      auto place = [&](vtkCanopyContour* f)
      {
        const double dx = dimension == 3 ? 4.0 - 2.0 * camera : 0.3 * camera;
        const double dy = dimension == 3 ? -3.0 + camera : -0.2 * camera;
        f->SetCameraFocalPoint(mid[0] + 0.2 * camera, mid[1] - 0.1 * camera, mid[2]);
        f->SetCameraPosition(mid[0] + dx, mid[1] + dy, mid[2] + 8 - camera);
        f->SetParallelProjection(camera % 2 == 0);
        f->SetParallelScale(3.0 - 0.5 * camera);
        f->SetViewportSize(dimension == 3 ? 12 + 6 * camera : 30 + 10 * camera,
                           dimension == 3 ? 10 + 4 * camera : 24 + 8 * camera);
        f->SetViewCulling(camera >= 3);
      };
      place(kept);
      kept->Update();
      const std::string what = std::to_string(dimension) + "D, camera " + std::to_string(camera);
      EXPECT_EQ(kept->GetLastRangesKept(), camera > 0) << what;
      EXPECT_GT(kept->GetLastPruned(), 0) << what;
      vtkNew<vtkCanopyContour> unpruned;
      configure(unpruned, false);
      place(unpruned);
      unpruned->Update();
      EXPECT_GT(kept->GetOutput()->GetNumberOfCells(), 20) << what;
      expectSameOutput(kept->GetOutput(), unpruned->GetOutput(), what);
      std::cout << what << ": " << kept->GetOutput()->GetNumberOfCells() << " cells\n";
      coarsest = std::min(coarsest, kept->GetOutput()->GetNumberOfCells());
    }
    // Level of detail is at work: views coarser than the forest.
    EXPECT_LT(2 * coarsest, contour(grid.htg, values)->GetNumberOfCells()) << dimension << "D";
  }
}

TEST(ContourView, CullingKeepsWhatTheViewSees)
{
  // A 2D view on part of the domain, level of detail off: the contour's
  // segments are full-resolution ones (point for point), and every segment
  // of the full contour inside the view is there; far fewer groups descended.
  TestGrid grid = makeGrid(randomSpec(2, 2, 7), wavy);
  vtkNew<vtkCanopyContour> filter;
  filter->SetInputData(grid.htg);
  filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "f");
  filter->SetValue(0, 0.0);
  filter->SetValue(1, 0.35);
  filter->Update();
  vtkSmartPointer<vtkPolyData> full = vtkSmartPointer<vtkPolyData>::New();
  full->DeepCopy(filter->GetOutput());
  const vtkIdType fullVisited = filter->GetLastVisited();
  const double z = grid.domain.lo[2];
  const Point focus{{-0.2, 1.1, z}};
  const double scale = 0.3; // half the view's height; 4:3 viewport
  filter->ViewDependentOn();
  filter->LevelOfDetailOff();
  filter->ViewCullingOn();
  filter->SetCameraFocalPoint(focus[0], focus[1], z);
  filter->SetCameraPosition(focus[0], focus[1], z + 10);
  filter->SetCameraViewUp(0, 1, 0);
  filter->ParallelProjectionOn();
  filter->SetParallelScale(scale);
  filter->SetViewportSize(400, 300);
  filter->Update();
  vtkPolyData* culled = filter->GetOutput();
  auto segments = [](vtkPolyData* out)
  {
    std::set<std::pair<Point, Point>> found;
    for (const auto& s : cellsOf(out->GetLines()))
    {
      const Point p = pointOf(out, s[0]);
      const Point q = pointOf(out, s[1]);
      found.insert({std::min(p, q), std::max(p, q)});
    }
    return found;
  };
  const auto all = segments(full);
  const auto kept = segments(culled);
  for (const auto& s : kept)
  {
    ASSERT_TRUE(all.count(s)) << "a culled contour's segment is a full contour's";
  }
  const Box view{{{focus[0] - scale * 4 / 3, focus[1] - scale, z}},
                 {{focus[0] + scale * 4 / 3, focus[1] + scale, z}}};
  std::size_t inside = 0;
  for (const auto& s : all)
  {
    if (strictlyInside(view, s.first) && strictlyInside(view, s.second))
    {
      ++inside;
      ASSERT_TRUE(kept.count(s)) << "a segment inside the view was culled";
    }
  }
  std::cout << "culled: " << kept.size() << " of " << all.size() << " segments (" << inside
            << " inside the view), groups descended " << filter->GetLastVisited() << " of "
            << fullVisited << "\n";
  EXPECT_GT(inside, 10u);
  EXPECT_LT(kept.size(), all.size());
  EXPECT_GT(filter->GetLastCulled(), 0);
  EXPECT_LT(filter->GetLastVisited(), fullVisited);
}

} // namespace
} // namespace canopy::testing
