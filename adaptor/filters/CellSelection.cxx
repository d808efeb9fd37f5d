#include "CellSelection.h"

#include "ClippedPolytope.h"
#include "GridSection.h"
#include "TreeTraversal.h"

#include <vtkAOSDataArrayTemplate.h>
#include <vtkDataArray.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
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
  return unselectable(Grid, tree, node, AllowMasked);
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

/// Cells already selected: a bit per cell when that is small next to the
/// points (a hash set costs more per insertion), else a hash set.
class SeenCells
{
public:
  SeenCells(vtkIdType cells, std::size_t points)
  {
    const auto words = static_cast<std::size_t>(cells / 64 + 1);
    if (words <= 64 * points + 65536)
    {
      Bits.assign(words, 0);
    }
  }
  /// False when already there.
  bool insert(vtkIdType global)
  {
    if (Bits.empty())
    {
      return Set.insert(global).second;
    }
    std::uint64_t& word = Bits[static_cast<std::size_t>(global) / 64];
    const std::uint64_t bit = std::uint64_t(1) << (global % 64);
    const bool fresh = (word & bit) == 0;
    word |= bit;
    return fresh;
  }

private:
  std::vector<std::uint64_t> Bits;
  std::unordered_set<vtkIdType> Set;
};

} // namespace

std::vector<SelectedNode> CellSelection::byLocation(const std::vector<Vec3>& points,
                                                    SelectionReport& report) const
{
  std::vector<SelectedNode> selected;
  SeenCells seen(Grid.numberOfCells(), points.size());
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
          if (Grid.nodeLower(*tree, n.level + 1, a, n.ijk[a] * f + d) <= p[a])
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
    if (!seen.insert(n.global))
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
  // One traversal of all trees for all ids; output in tree order. The walk's
  // inherited bit says that an ancestor is hidden.
  std::size_t found = 0;
  const auto& trees = Grid.trees();
  forEachTreeInOrder(Progress, static_cast<vtkIdType>(trees.size()),
                     [&](vtkIdType t)
                     {
                       const TreeAccess& tree = trees[static_cast<std::size_t>(t)];
                       // False (the loop ends) once every id is found.
                       return walkTree(
                           Grid, tree,
                           [&](WalkNode& n)
                           {
                             if (found >= wanted.size())
                             {
                               return WalkStep::Stop;
                             }
                             const vtkIdType global = tree.globalIndex(n.node);
                             n.inherited = n.inherited || hidden(tree, n.node);
                             if (wanted.count(global))
                             {
                               ++found;
                               if (n.inherited)
                               {
                                 ++report.masked;
                               }
                               else
                               {
                                 selected.push_back({&tree, n.node, global, n.level, n.ijk});
                               }
                             }
                             return WalkStep::Descend;
                           });
                     });
  return selected;
}

namespace
{

/// The value a range selection compares: a component, or the magnitude when
/// component < 0. Typed for contiguous arrays (a virtual call per leaf costs
/// more than the rest of the walk); other arrays through GetComponent.
template <typename Array>
double valueAt(Array* values, vtkIdType tuple, int component, int components)
{
  if (component >= 0)
  {
    return static_cast<double>(values->GetComponent(tuple, component));
  }
  double sum = 0;
  for (int c = 0; c < components; ++c)
  {
    const double x = static_cast<double>(values->GetComponent(tuple, c));
    sum += x * x;
  }
  return std::sqrt(sum);
}

/// Runs walk(tree, out) for every tree in parallel, each into its own list,
/// and joins the lists in tree order (the same for any number of threads).
template <typename Walk>
std::vector<SelectedNode> perTree(const HyperTreeAccess& grid, const ProgressShare& progress,
                                  const Walk& walk)
{
  const auto& trees = grid.trees();
  std::vector<std::vector<SelectedNode>> found(trees.size());
  forEachTree(progress, static_cast<vtkIdType>(trees.size()),
              [&](vtkIdType t)
              { walk(trees[static_cast<std::size_t>(t)], found[static_cast<std::size_t>(t)]); });
  std::size_t total = 0;
  for (const auto& list : found)
  {
    total += list.size();
  }
  std::vector<SelectedNode> selected;
  selected.reserve(total);
  for (const auto& list : found)
  {
    selected.insert(selected.end(), list.begin(), list.end());
  }
  return selected;
}

} // namespace

std::function<bool(vtkIdType)> CellSelection::valueInRange(vtkDataArray* values, int component,
                                                           double low, double high)
{
  const int nc = values->GetNumberOfComponents();
  auto test = [=](auto* typed) -> std::function<bool(vtkIdType)>
  {
    return [=](vtkIdType global)
    {
      const double v = valueAt(typed, global, component, nc);
      return v >= low && v <= high; // false for NaN
    };
  };
  if (auto* doubles = vtkAOSDataArrayTemplate<double>::FastDownCast(values))
  {
    return test(doubles);
  }
  if (auto* floats = vtkAOSDataArrayTemplate<float>::FastDownCast(values))
  {
    return test(floats);
  }
  return test(values);
}

template <typename Skip, typename Keep>
std::vector<SelectedNode> CellSelection::visibleLeaves(const Skip& skip, const Keep& keep) const
{
  return perTree(Grid, Progress,
                 [&](const TreeAccess& tree, std::vector<SelectedNode>& out)
                 {
                   walkTree(Grid, tree,
                            [&](WalkNode& n)
                            {
                              if (hidden(tree, n.node))
                              {
                                return WalkStep::Skip;
                              }
                              const vtkIdType global = tree.globalIndex(n.node);
                              if (skip(global))
                              {
                                return WalkStep::Skip;
                              }
                              if (!tree.isLeaf(n.node))
                              {
                                return WalkStep::Descend;
                              }
                              if (keep(global))
                              {
                                out.push_back({&tree, n.node, global, n.level, n.ijk});
                              }
                              return WalkStep::Skip;
                            });
                 });
}

std::vector<SelectedNode> CellSelection::byValue(vtkDataArray* values, int component, double low,
                                                 double high) const
{
  return visibleLeaves([](vtkIdType) { return false; }, valueInRange(values, component, low, high));
}

std::vector<SelectedNode> CellSelection::complement(const std::vector<SelectedNode>& selected) const
{
  std::vector<unsigned char> chosen(static_cast<std::size_t>(Grid.numberOfCells()), 0);
  for (const SelectedNode& n : selected)
  {
    chosen[static_cast<std::size_t>(n.global)] = 1;
  }
  // A selected node's subtree is left out whole.
  return visibleLeaves([&](vtkIdType global) { return chosen[static_cast<std::size_t>(global)]; },
                       [](vtkIdType) { return true; });
}

std::vector<SelectedNode> CellSelection::byRegion(const SelectionRegion& region,
                                                  SelectionReport& report) const
{
  std::vector<SelectedNode> selected;
  if (region.empty)
  {
    return selected;
  }
  Vec3 lo;
  Vec3 hi;
  const auto& trees = Grid.trees();
  forEachTreeInOrder(
      Progress, static_cast<vtkIdType>(trees.size()),
      [&](vtkIdType t)
      {
        const TreeAccess& tree = trees[static_cast<std::size_t>(t)];
        walkTree(Grid, tree,
                 [&](WalkNode& n)
                 {
                   ++report.visited;
                   if (hidden(tree, n.node))
                   {
                     return WalkStep::Skip;
                   }
                   Grid.nodeBounds(tree, n.level, n.ijk, lo, hi);
                   if (!region.overlaps(lo, hi))
                   {
                     return WalkStep::Skip; // nothing below can overlap: children lie inside
                   }
                   if (tree.isLeaf(n.node))
                   {
                     selected.push_back({&tree, n.node, tree.globalIndex(n.node), n.level, n.ijk});
                   }
                   return WalkStep::Descend;
                 });
        return true;
      });
  return selected;
}

SelectionRegion CellSelection::boxRegion(const std::array<double, 6>& box) const
{
  // Exact comparisons of the cells' own bounds: touching is not overlapping.
  const std::vector<int> axes = Grid.activeAxes();
  SelectionRegion region;
  region.overlaps = [axes, box](const Vec3& lo, const Vec3& hi)
  {
    for (int a : axes)
    {
      if (!(std::max(lo[a], box[2 * a]) < std::min(hi[a], box[2 * a + 1])))
      {
        return false;
      }
    }
    return true;
  };
  region.contains = [axes, box](const Vec3& lo, const Vec3& hi)
  {
    for (int a : axes)
    {
      if (!(box[2 * a] <= lo[a] && lo[a] < hi[a] && hi[a] <= box[2 * a + 1]))
      {
        return false;
      }
    }
    return true;
  };
  return region;
}

SelectionRegion CellSelection::frustumRegion(const Frustum& frustum) const
{
  // Relative to the grid's centre: planes far from the origin keep their precision.
  const auto& b = Grid.bounds();
  const Vec3 anchor{{0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])}};
  const std::vector<HalfSpace> halfSpaces = frustum.halfSpaces(anchor);
  SelectionRegion region;
  region.contains = [](const Vec3&, const Vec3&) { return false; };
  if (Grid.dimension() == 3)
  {
    auto polytope = std::make_shared<const ClippedPolytope>(
        halfSpaces, anchor, Vec3{{b[0], b[2], b[4]}}, Vec3{{b[1], b[3], b[5]}});
    region.empty = polytope->empty();
    region.overlaps = [polytope](const Vec3& lo, const Vec3& hi)
    { return polytope->overlaps(lo, hi); };
    return region;
  }
  auto section = std::make_shared<const GridSection>(Grid, halfSpaces, anchor);
  region.empty = section->empty();
  region.overlaps = [section](const Vec3& lo, const Vec3& hi) { return section->overlaps(lo, hi); };
  return region;
}

} // namespace canopy
