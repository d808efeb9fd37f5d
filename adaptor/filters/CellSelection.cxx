#include "CellSelection.h"

#include "ClippedPolytope.h"
#include "GridSection.h"

#include <vtkDataArray.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace canopy
{

CellSelection::CellSelection(const HyperTreeAccess& grid, bool allowMasked)
    : Grid(grid), AllowMasked(allowMasked)
{
}

void CellSelection::bounds(const SelectedNode& n, Vec3& lo, Vec3& hi) const
{
  Grid.nodeBounds(*n.tree, n.level, n.ijk, lo, hi);
}

bool CellSelection::hidden(const TreeAccess& tree, vtkIdType node) const
{
  if (!Grid.hasMask())
  {
    return false;
  }
  // Absent cells (another rank's) are never selectable, even with AllowMasked.
  const vtkIdType global = tree.globalIndex(node);
  return Grid.isAbsent(global) || (!AllowMasked && Grid.isMasked(global));
}

namespace
{

/// Root cell index along an axis for coordinate x under the half-open rule, or
/// -1 outside. The last cell also owns the upper boundary.
long rootCellAlong(const std::vector<double>& c, double x)
{
  if (!(x >= c.front() && x <= c.back()))
  {
    return -1; // outside, or NaN
  }
  const long i = static_cast<long>(std::upper_bound(c.begin(), c.end(), x) - c.begin()) - 1;
  return std::min(i, static_cast<long>(c.size()) - 2);
}

} // namespace

std::vector<SelectedNode> CellSelection::byLocation(const std::vector<Vec3>& points,
                                                    SelectionReport& report) const
{
  std::vector<SelectedNode> selected;
  std::unordered_set<vtkIdType> seen;
  const int f = Grid.branchFactor();
  for (const Vec3& p : points)
  {
    std::array<long, 3> root{{0, 0, 0}};
    bool inside = true;
    for (int a : Grid.activeAxes())
    {
      root[a] = rootCellAlong(Grid.coordinates(a), p[a]);
      inside = inside && root[a] >= 0;
    }
    const TreeAccess* tree = inside ? Grid.treeAt(root[0], root[1], root[2]) : nullptr;
    if (!tree)
    {
      ++report.outside;
      continue;
    }
    SelectedNode n{tree, 0, 0, 0, {{0, 0, 0}}};
    bool masked = false;
    while (true)
    {
      if (hidden(*tree, n.node))
      {
        masked = true;
        break;
      }
      if (tree->isLeaf(n.node))
      {
        break;
      }
      // Child digit per axis: the last child whose lower bound is <= p, with
      // bounds computed exactly as the cells' own (so the rule is consistent).
      std::array<std::int64_t, 3> child = n.ijk;
      int position = 0;
      int weight = 1;
      for (int a : Grid.activeAxes())
      {
        int digit = 0;
        for (int d = 1; d < f; ++d)
        {
          std::array<std::int64_t, 3> probe = n.ijk;
          probe[a] = n.ijk[a] * f + d;
          Vec3 lo;
          Vec3 hi;
          Grid.nodeBounds(*tree, n.level + 1, probe, lo, hi);
          if (lo[a] <= p[a])
          {
            digit = d;
          }
        }
        child[a] = n.ijk[a] * f + digit;
        position += digit * weight;
        weight *= f;
      }
      n = {tree, tree->firstChild(n.node) + position, 0, n.level + 1, child};
    }
    if (masked)
    {
      ++report.masked;
      continue;
    }
    n.global = tree->globalIndex(n.node);
    if (!seen.insert(n.global).second)
    {
      ++report.duplicates;
      continue;
    }
    selected.push_back(n);
  }
  return selected;
}

std::vector<SelectedNode> CellSelection::byId(const std::vector<vtkIdType>& ids,
                                              SelectionReport& report) const
{
  std::unordered_set<vtkIdType> wanted;
  for (vtkIdType id : ids)
  {
    if (id < 0 || id >= Grid.numberOfCells())
    {
      ++report.outOfRange;
    }
    else if (!wanted.insert(id).second)
    {
      ++report.duplicates;
    }
  }
  std::vector<SelectedNode> selected;
  if (wanted.empty())
  {
    return selected;
  }
  // One traversal of all trees for all ids; output in tree order.
  std::size_t found = 0;
  for (const TreeAccess& tree : Grid.trees())
  {
    struct Frame
    {
      vtkIdType node;
      int level;
      std::array<std::int64_t, 3> ijk;
      bool hidden;
    };
    std::vector<Frame> stack{{0, 0, {{0, 0, 0}}, false}};
    while (!stack.empty() && found < wanted.size())
    {
      const Frame n = stack.back();
      stack.pop_back();
      const vtkIdType global = tree.globalIndex(n.node);
      const bool isHidden = n.hidden || hidden(tree, n.node);
      if (wanted.count(global))
      {
        ++found;
        if (isHidden)
        {
          ++report.masked;
        }
        else
        {
          selected.push_back({&tree, n.node, global, n.level, n.ijk});
        }
      }
      if (tree.isLeaf(n.node))
      {
        continue;
      }
      const vtkIdType first = tree.firstChild(n.node);
      for (int c = Grid.childrenPerNode(); c-- > 0;)
      {
        stack.push_back({first + c, n.level + 1, Grid.childPosition(n.ijk, c), isHidden});
      }
    }
  }
  return selected;
}

std::vector<SelectedNode> CellSelection::byValue(vtkDataArray* values, int component, double low,
                                                 double high) const
{
  std::vector<SelectedNode> selected;
  const int nc = values->GetNumberOfComponents();
  for (const TreeAccess& tree : Grid.trees())
  {
    struct Frame
    {
      vtkIdType node;
      int level;
      std::array<std::int64_t, 3> ijk;
    };
    std::vector<Frame> stack{{0, 0, {{0, 0, 0}}}};
    while (!stack.empty())
    {
      const Frame n = stack.back();
      stack.pop_back();
      if (hidden(tree, n.node))
      {
        continue;
      }
      if (tree.isLeaf(n.node))
      {
        const vtkIdType global = tree.globalIndex(n.node);
        double v = 0;
        if (component >= 0)
        {
          v = values->GetComponent(global, component);
        }
        else
        {
          for (int c = 0; c < nc; ++c)
          {
            const double x = values->GetComponent(global, c);
            v += x * x;
          }
          v = std::sqrt(v);
        }
        if (v >= low && v <= high) // false for NaN
        {
          selected.push_back({&tree, n.node, global, n.level, n.ijk});
        }
        continue;
      }
      const vtkIdType first = tree.firstChild(n.node);
      for (int c = Grid.childrenPerNode(); c-- > 0;)
      {
        stack.push_back({first + c, n.level + 1, Grid.childPosition(n.ijk, c)});
      }
    }
  }
  return selected;
}

template <typename Overlaps>
std::vector<SelectedNode> CellSelection::byRegion(const Overlaps& overlaps,
                                                  SelectionReport& report) const
{
  std::vector<SelectedNode> selected;
  Vec3 lo;
  Vec3 hi;
  for (const TreeAccess& tree : Grid.trees())
  {
    struct Frame
    {
      vtkIdType node;
      int level;
      std::array<std::int64_t, 3> ijk;
    };
    std::vector<Frame> stack{{0, 0, {{0, 0, 0}}}};
    while (!stack.empty())
    {
      const Frame n = stack.back();
      stack.pop_back();
      ++report.visited;
      if (hidden(tree, n.node))
      {
        continue;
      }
      Grid.nodeBounds(tree, n.level, n.ijk, lo, hi);
      if (!overlaps(lo, hi))
      {
        continue; // nothing below can overlap: children lie inside their parent
      }
      if (tree.isLeaf(n.node))
      {
        selected.push_back({&tree, n.node, tree.globalIndex(n.node), n.level, n.ijk});
        continue;
      }
      const vtkIdType first = tree.firstChild(n.node);
      for (int c = Grid.childrenPerNode(); c-- > 0;)
      {
        stack.push_back({first + c, n.level + 1, Grid.childPosition(n.ijk, c)});
      }
    }
  }
  return selected;
}

std::vector<SelectedNode> CellSelection::byBox(const std::array<double, 6>& box,
                                               SelectionReport& report) const
{
  // Exact comparisons of the cells' own bounds: touching is not overlapping.
  const std::vector<int>& axes = Grid.activeAxes();
  return byRegion(
      [&](const Vec3& lo, const Vec3& hi)
      {
        for (int a : axes)
        {
          if (!(std::max(lo[a], box[2 * a]) < std::min(hi[a], box[2 * a + 1])))
          {
            return false;
          }
        }
        return true;
      },
      report);
}

std::vector<SelectedNode> CellSelection::byFrustum(const Frustum& frustum,
                                                   SelectionReport& report) const
{
  // Relative to the grid's centre: planes far from the origin keep their precision.
  const auto& b = Grid.bounds();
  const Vec3 anchor{{0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])}};
  const std::vector<HalfSpace> halfSpaces = frustum.halfSpaces(anchor);
  if (Grid.dimension() == 3)
  {
    const ClippedPolytope region(halfSpaces, anchor, {{b[0], b[2], b[4]}}, {{b[1], b[3], b[5]}});
    if (region.empty())
    {
      return {};
    }
    return byRegion([&](const Vec3& lo, const Vec3& hi) { return region.overlaps(lo, hi); },
                    report);
  }
  const GridSection section(Grid, halfSpaces, anchor);
  if (section.empty())
  {
    return {};
  }
  return byRegion([&](const Vec3& lo, const Vec3& hi) { return section.overlaps(lo, hi); }, report);
}

} // namespace canopy
