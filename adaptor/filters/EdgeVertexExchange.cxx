#include "EdgeVertexExchange.h"

#include "AdaptiveSurfaceBuilder.h"
#include "GatherFromAll.h"

#include <vtkMultiProcessController.h>

#include <algorithm>

namespace canopy
{

namespace
{

/// The line key of axis `along` through p: its coordinates on the two other axes.
std::tuple<int, double, double> lineThrough(int along, const Vec3& p)
{
  const int first = along == 0 ? 1 : 0;
  const int second = along == 2 ? 1 : 2;
  return {along, p[static_cast<std::size_t>(first)], p[static_cast<std::size_t>(second)]};
}

} // namespace

SharedEdge sharedEdgeOf(int edge, int u, int v, const Vec3& lo, const Vec3& hi)
{
  const int along = edge < 2 ? u : v;
  const int across = edge < 2 ? v : u;
  Vec3 p = lo;
  p[static_cast<std::size_t>(across)] =
      edge % 2 ? hi[static_cast<std::size_t>(across)] : lo[static_cast<std::size_t>(across)];
  const auto line = lineThrough(along, p);
  return {along,
          {{std::get<1>(line), std::get<2>(line)}},
          lo[static_cast<std::size_t>(along)],
          hi[static_cast<std::size_t>(along)]};
}

SharedVertices::SharedVertices(const std::vector<SharedEdge>& edges)
{
  for (const SharedEdge& e : edges)
  {
    auto& ends = Lines[{e.along, e.at[0], e.at[1]}];
    ends.push_back(e.lo);
    ends.push_back(e.hi);
  }
  for (auto& line : Lines)
  {
    std::sort(line.second.begin(), line.second.end());
    line.second.erase(std::unique(line.second.begin(), line.second.end()), line.second.end());
  }
}

void SharedVertices::between(int along, const Vec3& p, double a, double b,
                             std::vector<double>& out) const
{
  const auto line = Lines.find(lineThrough(along, p));
  if (line == Lines.end())
  {
    return;
  }
  const auto& ends = line->second;
  for (auto x = std::upper_bound(ends.begin(), ends.end(), std::min(a, b));
       x != ends.end() && *x < std::max(a, b); ++x)
  {
    out.push_back(*x);
  }
}

std::vector<SharedEdge> gatherSharedEdges(vtkMultiProcessController* controller,
                                          const std::vector<SharedEdge>& mine)
{
  std::vector<double> values;
  values.reserve(SharedEdge::Values * mine.size());
  for (const SharedEdge& e : mine)
  {
    values.insert(values.end(), {static_cast<double>(e.along), e.at[0], e.at[1], e.lo, e.hi});
  }
  std::vector<vtkIdType> counts;
  const std::vector<double> all = gatherFromAll(controller, values, counts);
  std::vector<SharedEdge> edges;
  for (std::size_t i = 0; i + SharedEdge::Values <= all.size(); i += SharedEdge::Values)
  {
    const int along = static_cast<int>(all[i]);
    if (along >= 0 && along <= 2)
    {
      edges.push_back({along, {{all[i + 1], all[i + 2]}}, all[i + 3], all[i + 4]});
    }
  }
  return edges;
}

void insertSharedVertices(TreeCells& cells, const std::vector<std::uint32_t>& listed,
                          const SharedVertices& shared)
{
  if (listed.empty() || shared.empty())
  {
    return;
  }
  std::vector<double> points;
  points.reserve(cells.points.size());
  std::vector<double> found;
  std::size_t first = 0; // the cell's first point in cells.points
  auto next = listed.begin();
  for (std::size_t c = 0; c < cells.sizes.size(); ++c)
  {
    const std::size_t size = cells.sizes[c];
    const double* p = cells.points.data() + 3 * first;
    first += size;
    if (next == listed.end() || *next != c)
    {
      points.insert(points.end(), p, p + 3 * size);
      continue;
    }
    ++next;
    std::size_t count = 0;
    for (std::size_t k = 0; k < size; ++k)
    {
      const Vec3 a{{p[3 * k], p[3 * k + 1], p[3 * k + 2]}};
      const std::size_t l = (k + 1) % size;
      const Vec3 b{{p[3 * l], p[3 * l + 1], p[3 * l + 2]}};
      points.insert(points.end(), a.begin(), a.end());
      ++count;
      int along = 0;
      while (along < 2 && a[static_cast<std::size_t>(along)] == b[static_cast<std::size_t>(along)])
      {
        ++along;
      }
      found.clear();
      shared.between(along, a, a[static_cast<std::size_t>(along)],
                     b[static_cast<std::size_t>(along)], found);
      // From a towards b.
      const bool up = b[static_cast<std::size_t>(along)] > a[static_cast<std::size_t>(along)];
      for (std::size_t i = 0; i < found.size(); ++i)
      {
        Vec3 q = a;
        q[static_cast<std::size_t>(along)] = up ? found[i] : found[found.size() - 1 - i];
        points.insert(points.end(), q.begin(), q.end());
        ++count;
      }
    }
    cells.sizes[c] = static_cast<std::uint32_t>(count);
  }
  cells.points.swap(points);
}

} // namespace canopy
