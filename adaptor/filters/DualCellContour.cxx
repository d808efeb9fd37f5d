#include "DualCellContour.h"

#include "Vec3.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace canopy
{

DualCellContour::DualCellContour(const HyperTreeAccess& grid, const DualTraversal& dual,
                                 const ContourField& field, const std::vector<double>& values,
                                 ContourPiece& out, const NodeRanges* ranges, bool cull)
    : Grid(grid), Dual(dual), Field(field), Values(values), Out(out), Gradient(grid, dual, field),
      Ranges(ranges), Cull(cull)
{
}

bool DualCellContour::enter(const DualGroup& group, unsigned axes)
{
  if (Cull)
  {
    // Every cell below lies within the box around the group's nodes: none of
    // it is seen when that box is outside the view.
    Vec3 lo{{1e300, 1e300, 1e300}};
    Vec3 hi{{-1e300, -1e300, -1e300}};
    bool any = false;
    for (unsigned s = 0; s < (1u << Dual.dimension()); ++s)
    {
      if ((s & ~axes) != 0)
      {
        continue; // not a slot of this group (no node)
      }
      const DualNode& n = *group[s];
      if (n.kind != DualNode::Inner && n.kind != DualNode::Leaf)
      {
        continue;
      }
      std::array<double, 3> a;
      std::array<double, 3> b;
      Grid.nodeBounds(*n.tree, n.level, n.ijk, a, b);
      for (std::size_t k = 0; k < 3; ++k)
      {
        lo[k] = std::min(lo[k], a[k]);
        hi[k] = std::max(hi[k], b[k]);
      }
      any = true;
    }
    if (any && Dual.view()->classifyBox(lo, hi) != ViewVolume::BoxSide::Inside &&
        !Dual.view()->overlapsBox(lo, hi))
    {
      ++Culled;
      return false;
    }
  }
  if (Ranges)
  {
    // Outside slots add nothing: their boundary vertices' values are in their
    // mirrored leaves' ranges (NodeRanges.h).
    const unsigned corners = 1u << Dual.dimension();
    ValueRange range;
    for (unsigned s = 0; s < corners; ++s)
    {
      if ((s & ~axes) != 0)
      {
        continue; // not a slot of this group (no node)
      }
      const DualNode& n = *group[s];
      if (n.kind == DualNode::Inner || n.kind == DualNode::Leaf)
      {
        if (n.remote || (Dual.ghosts() && n.tree->hasAbsentDescendant(n.node)))
        {
          // Another rank's (a ghost), or a node with other ranks' parts below
          // (its range covers this rank's leaves only): descended.
          range.add(
              {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()});
          continue;
        }
        if (Dual.levelOfDetail() && Dual.touchesDomainBoundary(*n.tree, n.level, n.ijk))
        {
          // The ranges are the forest's without the view (NodeRanges.h). A
          // coarse leaf of the view holds its own value, which they cover,
          // but its boundary vertices extrapolate with its own gradient, and
          // a leaf's gradient changes with its neighbours' level of detail:
          // descended, to the view's leaves at most.
          range.add(
              {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()});
          continue;
        }
        range.add(Ranges->at(static_cast<std::size_t>(n.tree - Grid.trees().data()), n.node));
      }
    }
    if (std::none_of(Values.begin(), Values.end(),
                     [&](double value) { return value > range.low && value <= range.high; }))
    {
      ++Pruned;
      return false;
    }
  }
  ++Visited;
  return true;
}

bool DualCellContour::insideItsTree(const DualNode& leaf) const
{
  const std::int64_t last = Grid.cellsPerRootAt(leaf.level) - 1;
  for (int i = 0; i < Dual.dimension(); ++i)
  {
    const std::int64_t at = leaf.ijk[static_cast<std::size_t>(Dual.axis(i))];
    if (at == 0 || at == last)
    {
      return false;
    }
  }
  return true;
}

bool DualCellContour::vertex(const DualGroup& group, unsigned s, DualVertex& v)
{
  const DualNode* n = group[s];
  unsigned char sides = 0;
  if (n->kind == DualNode::Outside)
  {
    // The leaf this slot mirrors across the boundary: flip the outside axes.
    sides = n->outside;
    unsigned mirror = s;
    for (int i = 0; i < Dual.dimension(); ++i)
    {
      if (sides & (3u << (2 * i)))
      {
        mirror ^= 1u << i;
      }
    }
    n = group[mirror];
  }
  if (n->kind != DualNode::Leaf)
  {
    return false;
  }
  v.leaf = Dual.leafId(*n);
  v.key = static_cast<std::uint64_t>(v.leaf) * 64 + sides;
  v.value = Field(v.leaf);
  if (sides == 0)
  {
    v.x = nodeCentre(Grid, *n);
    v.own = !n->remote && insideItsTree(*n);
    return true;
  }
  std::array<double, 3> lo;
  std::array<double, 3> hi;
  Grid.nodeBounds(*n->tree, n->level, n->ijk, lo, hi);
  const std::array<double, 3> centre{
      {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])}};
  v.x = centre;
  for (int i = 0; i < Dual.dimension(); ++i)
  {
    const std::size_t a = static_cast<std::size_t>(Dual.axis(i));
    if (sides & (1u << (2 * i)))
    {
      v.x[a] = lo[a];
    }
    else if (sides & (2u << (2 * i)))
    {
      v.x[a] = hi[a];
    }
  }
  auto found = Gradients.find(v.leaf);
  if (found == Gradients.end())
  {
    found = Gradients.emplace(v.leaf, Gradient.at(*n)).first;
  }
  v.value += dot(found->second, sub(v.x, centre));
  return true;
}

void DualCellContour::cell(const DualGroup& group)
{
  ++DualCells;
  Cached = 0;
  const unsigned corners = 1u << Dual.dimension();
  // Where ranks meet, every rank that sees the cell (one of its leaves here,
  // the others as ghosts) sees it alike: it is drawn by the owner of its lowest
  // slot's leaf (an Outside slot has none), by no other (ContourGhosts.h).
  for (unsigned s = 0; s < corners; ++s)
  {
    if (group[s]->kind != DualNode::Outside)
    {
      // 3D: a cell another rank draws is still contoured here when it can be
      // (its triangles kept for the points' normals only: a point on the
      // border then averages the same triangles on both ranks).
      Foreign = group[s]->remote != 0;
      if (Foreign && Dual.dimension() == 2)
      {
        return;
      }
      break;
    }
  }
  std::array<DualVertex, 8> v;
  // Values first: most cells met are not crossed, and a leaf's centre costs
  // more than its value. Boundary vertices are made whole (their value needs
  // their position).
  for (unsigned s = 0; s < corners; ++s)
  {
    const DualNode& n = *group[s];
    if (n.kind == DualNode::Leaf)
    {
      v[s].leaf = Dual.leafId(n);
      v[s].key = static_cast<std::uint64_t>(v[s].leaf) * 64;
      v[s].value = Field(v[s].leaf);
      v[s].own = !n.remote && insideItsTree(n);
    }
    else if (!vertex(group, s, v[s]))
    {
      return;
    }
  }
  double low = v[0].value;
  double high = v[0].value;
  for (unsigned s = 1; s < corners; ++s)
  {
    low = std::min(low, v[s].value);
    high = std::max(high, v[s].value);
  }
  if (std::none_of(Values.begin(), Values.end(),
                   [&](double value) { return value > low && value <= high; }))
  {
    return; // no contour crosses the cell
  }
  for (unsigned s = 0; s < corners; ++s)
  {
    if (group[s]->kind == DualNode::Leaf)
    {
      v[s].x = nodeCentre(Grid, *group[s]);
    }
  }
  if (Dual.dimension() == 2)
  {
    // Leaves of trees with other aspect ratios can make the quad non-convex
    // (only one of its diagonals inside it): take the diagonal 0-3 unless a
    // triangle it makes is inverted. In 2D no other cell shares a diagonal.
    const std::size_t x = static_cast<std::size_t>(Dual.axis(0));
    const std::size_t y = static_cast<std::size_t>(Dual.axis(1));
    auto area = [&](const DualVertex& a, const DualVertex& b, const DualVertex& c)
    { return (b.x[x] - a.x[x]) * (c.x[y] - a.x[y]) - (b.x[y] - a.x[y]) * (c.x[x] - a.x[x]); };
    if (area(v[0], v[1], v[3]) < 0 || area(v[0], v[3], v[2]) < 0)
    {
      triangle(v[0], v[1], v[2]);
      triangle(v[1], v[3], v[2]);
      return;
    }
    triangle(v[0], v[1], v[3]);
    triangle(v[0], v[3], v[2]);
    return;
  }
  // Kuhn: one tetrahedron per order of the axes, along the path 0 -> 7; the
  // sign its volume has in a cube (odd orders are negative).
  static const unsigned paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  static const double signs[6] = {1, -1, -1, 1, 1, -1};
  bool folded = false;
  for (std::size_t k = 0; k < 6 && !folded; ++k)
  {
    const DualVertex& a = v[0];
    const DualVertex& b = v[paths[k][0]];
    const DualVertex& c = v[paths[k][1]];
    const DualVertex& d = v[7];
    if (a.key == b.key || a.key == c.key || a.key == d.key || b.key == c.key || b.key == d.key ||
        c.key == d.key)
    {
      continue; // no volume: dropped
    }
    folded = signs[k] * dot(sub(b.x, a.x), cross(sub(c.x, a.x), sub(d.x, a.x))) < 0;
  }
  if (!folded || !centroidFan(v))
  {
    for (const auto& path : paths)
    {
      const DualVertex* t[4] = {&v[0], &v[path[0]], &v[path[1]], &v[7]};
      tetrahedron(t);
    }
  }
}

bool DualCellContour::centroidFan(const std::array<DualVertex, 8>& v)
{
  // The cell's boundary: each face's triangles (split by Kuhn's diagonal, as
  // the neighbouring cell splits the face) without the degenerate ones; a
  // triangle met twice (two faces folded onto each other where leaves repeat)
  // is inside the cell and both copies go.
  std::array<std::array<const DualVertex*, 3>, 12> faces;
  // +1: wound outwards (an upper face), -1: inwards (a lower face).
  std::array<double, 12> winding{};
  double adding = 1;
  std::size_t count = 0;
  auto add = [&](const DualVertex* a, const DualVertex* b, const DualVertex* c)
  {
    if (a->key == b->key || b->key == c->key || a->key == c->key)
    {
      return;
    }
    std::array<std::uint64_t, 3> keys{{a->key, b->key, c->key}};
    std::sort(keys.begin(), keys.end());
    for (std::size_t f = 0; f < count; ++f)
    {
      std::array<std::uint64_t, 3> other{{faces[f][0]->key, faces[f][1]->key, faces[f][2]->key}};
      std::sort(other.begin(), other.end());
      if (other == keys)
      {
        winding[f] = winding[count - 1];
        faces[f] = faces[--count];
        return;
      }
    }
    winding[count] = adding;
    faces[count++] = {{a, b, c}};
  };
  for (int i = 0; i < 3; ++i)
  {
    const unsigned u = 1u << ((i + 1) % 3);
    const unsigned w = 1u << ((i + 2) % 3);
    for (unsigned side : {0u, 1u << i})
    {
      adding = side ? 1 : -1;
      add(&v[side], &v[side | u], &v[side | u | w]);
      add(&v[side], &v[side | u | w], &v[side | w]);
    }
  }
  if (count == 0)
  {
    return true; // no volume
  }
  // How many triangles use each triangle's edges.
  auto uses = [&](std::uint64_t p, std::uint64_t q, const std::size_t* among, std::size_t n)
  {
    int found = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
      const auto& g = faces[among ? among[i] : i];
      for (std::size_t h = 0; h < 3; ++h)
      {
        const std::uint64_t r = g[h]->key;
        const std::uint64_t t = g[(h + 1) % 3]->key;
        found += (r == p && t == q) || (r == q && t == p);
      }
    }
    return found;
  };
  // Where leaves repeat the boundary can pinch: two wedges sharing an edge
  // (used by four triangles). Triangles joined across edges used exactly twice
  // are one part; each part must be closed (its edges used twice within it)
  // and gets its own fan, else nothing is done here.
  std::array<std::size_t, 12> part;
  for (std::size_t f = 0; f < count; ++f)
  {
    part[f] = f;
  }
  auto root = [&](std::size_t f)
  {
    while (part[f] != f)
    {
      f = part[f];
    }
    return f;
  };
  for (std::size_t f = 0; f < count; ++f)
  {
    for (std::size_t e = 0; e < 3; ++e)
    {
      const std::uint64_t p = faces[f][e]->key;
      const std::uint64_t q = faces[f][(e + 1) % 3]->key;
      if (uses(p, q, nullptr, count) != 2)
      {
        continue;
      }
      for (std::size_t g = 0; g < count; ++g)
      {
        if (g != f && uses(p, q, &g, 1) == 1)
        {
          part[root(g)] = root(f);
        }
      }
    }
  }
  std::array<std::array<std::size_t, 12>, 12> members;
  std::array<std::size_t, 12> sizes{};
  for (std::size_t f = 0; f < count; ++f)
  {
    const std::size_t r = root(f);
    members[r][sizes[r]++] = f;
  }
  for (std::size_t r = 0; r < count; ++r)
  {
    for (std::size_t i = 0; i < sizes[r]; ++i)
    {
      const auto& f = faces[members[r][i]];
      for (std::size_t e = 0; e < 3; ++e)
      {
        if (uses(f[e]->key, f[(e + 1) % 3]->key, members[r].data(), sizes[r]) != 2)
        {
          return false;
        }
      }
    }
  }
  for (std::size_t r = 0; r < count; ++r)
  {
    if (sizes[r] == 0)
    {
      continue;
    }
    // The part's distinct vertices, and how many slots each fills.
    std::array<const DualVertex*, 8> corners;
    std::array<double, 8> slots{};
    std::size_t n = 0;
    for (std::size_t i = 0; i < sizes[r]; ++i)
    {
      for (const DualVertex* x : faces[members[r][i]])
      {
        bool seen = false;
        for (std::size_t j = 0; j < n && !seen; ++j)
        {
          seen = corners[j]->key == x->key;
        }
        if (!seen && n < corners.size())
        {
          corners[n++] = x;
        }
      }
    }
    for (std::size_t j = 0; j < n; ++j)
    {
      for (const DualVertex& x : v)
      {
        slots[j] += x.key == corners[j]->key ? 1 : 0;
      }
    }
    // The fan's apex: a point inside the part from which every triangle is
    // seen from inside (no folded tetrahedron). Candidates, each a convex
    // combination of the part's vertices, its value the same combination of
    // theirs (exact for a linear field): their mean, their mean weighted by
    // the slots they fill, and each vertex itself (a fan from a vertex skips
    // the triangles it is on). The first without a fold, else the one folding
    // the least volume.
    auto folds = [&](const std::array<double, 3>& apex, const DualVertex* skip)
    {
      double folded = 0;
      for (std::size_t i = 0; i < sizes[r]; ++i)
      {
        const std::size_t f = members[r][i];
        const auto& t = faces[f];
        if (skip && (t[0] == skip || t[1] == skip || t[2] == skip))
        {
          continue;
        }
        const double volume =
            winding[f] * dot(sub(t[0]->x, apex), cross(sub(t[1]->x, apex), sub(t[2]->x, apex)));
        folded += volume < 0 ? -volume : 0;
      }
      return folded;
    };
    auto mean = [&](bool weighted)
    {
      std::array<double, 3> x{{0, 0, 0}};
      double total = 0;
      for (std::size_t j = 0; j < n; ++j)
      {
        total += weighted ? slots[j] : 1;
      }
      for (std::size_t j = 0; j < n; ++j)
      {
        const double w = (weighted ? slots[j] : 1) / total;
        for (std::size_t a = 0; a < 3; ++a)
        {
          x[a] += w * corners[j]->x[a];
        }
      }
      return x;
    };
    int best = 0; // 0, 1: the means; 2 + j: vertex j
    double least = folds(mean(false), nullptr);
    for (int candidate = 1; candidate < 2 + static_cast<int>(n) && least > 0; ++candidate)
    {
      const double folded = candidate == 1
                                ? folds(mean(true), nullptr)
                                : folds(corners[static_cast<std::size_t>(candidate - 2)]->x,
                                        corners[static_cast<std::size_t>(candidate - 2)]);
      if (folded < least)
      {
        least = folded;
        best = candidate;
      }
    }
    if (best >= 2)
    {
      const DualVertex* apex = corners[static_cast<std::size_t>(best - 2)];
      for (std::size_t i = 0; i < sizes[r]; ++i)
      {
        const auto& f = faces[members[r][i]];
        const DualVertex* t[4] = {apex, f[0], f[1], f[2]};
        tetrahedron(t); // the triangles on the apex: dropped there
      }
      continue;
    }
    DualVertex centroid;
    centroid.key = Out.centroidKey();
    centroid.own = true;
    centroid.leaf = -static_cast<vtkIdType>(Out.centroids.size()) - 1;
    centroid.x = mean(best == 1);
    ContourPiece::Centroid record;
    record.count = static_cast<int>(n);
    double total = 0;
    for (std::size_t j = 0; j < n; ++j)
    {
      total += best == 1 ? slots[j] : 1;
    }
    for (std::size_t j = 0; j < n; ++j)
    {
      const double w = (best == 1 ? slots[j] : 1) / total;
      centroid.value += w * corners[j]->value;
      record.leaves[j] = corners[j]->leaf;
      record.weights[j] = w;
    }
    Out.centroids.push_back(record);
    for (std::size_t i = 0; i < sizes[r]; ++i)
    {
      const auto& f = faces[members[r][i]];
      const DualVertex* t[4] = {&centroid, f[0], f[1], f[2]};
      tetrahedron(t);
    }
  }
  return true;
}

void DualCellContour::triangle(const DualVertex& a, const DualVertex& b, const DualVertex& c)
{
  if (a.key == b.key || b.key == c.key || a.key == c.key)
  {
    return; // a leaf filling two slots: no area
  }
  const DualVertex* v[3] = {&a, &b, &c};
  const double low = std::min({a.value, b.value, c.value});
  const double high = std::max({a.value, b.value, c.value});
  for (std::size_t k = 0; k < Values.size(); ++k)
  {
    const double value = Values[k];
    if (!(value > low && value <= high))
    {
      continue; // all on one side (a vertex at the value counts as above)
    }
    // The vertex alone on its side, and the two others.
    const bool above[3] = {a.value >= value, b.value >= value, c.value >= value};
    const int lone = above[0] == above[1] ? 2 : (above[0] == above[2] ? 1 : 0);
    const DualVertex& p = *v[lone];
    const DualVertex& q = *v[(lone + 1) % 3];
    const DualVertex& r = *v[(lone + 2) % 3];
    const std::uint32_t contour = static_cast<std::uint32_t>(k);
    vtkIdType from = point(p, q, contour, value);
    vtkIdType to = point(p, r, contour, value);
    // Higher values on the left: the side of an above vertex, in the grid's plane.
    const DualVertex& high = above[lone] ? p : q;
    const std::size_t u = static_cast<std::size_t>(Dual.axis(0));
    const std::size_t w = static_cast<std::size_t>(Dual.axis(1));
    const auto& x0 = Out.points[static_cast<std::size_t>(from)];
    const auto& x1 = Out.points[static_cast<std::size_t>(to)];
    const double side =
        (x1[u] - x0[u]) * (high.x[w] - x0[w]) - (x1[w] - x0[w]) * (high.x[u] - x0[u]);
    if (side < 0)
    {
      std::swap(from, to);
    }
    Out.cells.push_back(from);
    Out.cells.push_back(to);
  }
}

vtkIdType DualCellContour::point(const DualVertex& a, const DualVertex& b, std::uint32_t contour,
                                 double value)
{
  for (std::size_t i = 0; i < Cached; ++i)
  {
    const CachedPoint& c = Cache[i];
    if (c.contour == contour && ((c.a == a.key && c.b == b.key) || (c.a == b.key && c.b == a.key)))
    {
      return c.id;
    }
  }
  const vtkIdType id = Out.point(a, b, contour, value);
  if (Cached < Cache.size())
  {
    Cache[Cached++] = {a.key, b.key, contour, id};
  }
  return id;
}

void DualCellContour::tetrahedron(const DualVertex* v[4])
{
  for (int i = 0; i < 4; ++i)
  {
    for (int j = i + 1; j < 4; ++j)
    {
      if (v[i]->key == v[j]->key)
      {
        return; // a leaf filling two slots: no volume
      }
    }
  }
  double low = v[0]->value;
  double high = v[0]->value;
  for (int i = 1; i < 4; ++i)
  {
    low = std::min(low, v[i]->value);
    high = std::max(high, v[i]->value);
  }
  // Gradient of the linear interpolant: sum of df_i (e_j x e_k) / volume.
  const auto e1 = sub(v[1]->x, v[0]->x);
  const auto e2 = sub(v[2]->x, v[0]->x);
  const auto e3 = sub(v[3]->x, v[0]->x);
  const auto c23 = cross(e2, e3);
  const auto c31 = cross(e3, e1);
  const auto c12 = cross(e1, e2);
  const double volume = dot(e1, c23);
  const double d1 = v[1]->value - v[0]->value;
  const double d2 = v[2]->value - v[0]->value;
  const double d3 = v[3]->value - v[0]->value;
  std::array<double, 3> against{{0, 0, 0}};
  for (std::size_t a = 0; a < 3; ++a)
  {
    against[a] = -(d1 * c23[a] + d2 * c31[a] + d3 * c12[a]);
  }
  if (volume < 0)
  {
    against = {{-against[0], -against[1], -against[2]}};
  }
  // A flat tetrahedron's gradient means nothing: its triangles (of no area
  // either) get no normal, and their points take their neighbours'.
  double longest = 0;
  for (const auto& e : {e1, e2, e3})
  {
    longest = std::max(longest, dot(e, e));
  }
  if (std::abs(volume) <= 1e-9 * longest * std::sqrt(longest))
  {
    against = {{0, 0, 0}};
  }
  const double size = std::sqrt(dot(against, against));
  const std::array<double, 3> unitAgainst =
      size > 0 ? std::array<double, 3>{{against[0] / size, against[1] / size, against[2] / size}}
               : against;
  for (std::size_t k = 0; k < Values.size(); ++k)
  {
    const double value = Values[k];
    if (!(value > low && value <= high))
    {
      continue;
    }
    const std::uint32_t contour = static_cast<std::uint32_t>(k);
    const DualVertex* up[4];
    const DualVertex* down[4];
    int ups = 0;
    int downs = 0;
    for (int i = 0; i < 4; ++i)
    {
      if (v[i]->value >= value)
      {
        up[ups++] = v[i];
      }
      else
      {
        down[downs++] = v[i];
      }
    }
    // The field's gradient in the tetrahedron (its linear interpolant): the
    // triangles' normals point against it (towards lower values).
    auto emit = [&](vtkIdType p0, vtkIdType p1, vtkIdType p2)
    {
      const auto& x0 = Out.points[static_cast<std::size_t>(p0)];
      const auto normal = cross(sub(Out.points[static_cast<std::size_t>(p1)], x0),
                                sub(Out.points[static_cast<std::size_t>(p2)], x0));
      if (dot(normal, against) < 0)
      {
        std::swap(p1, p2);
      }
      Out.cells.push_back(p0);
      Out.cells.push_back(p1);
      Out.cells.push_back(p2);
      Out.cellNormals.push_back(unitAgainst);
      Out.foreign.push_back(Foreign ? 1 : 0);
    };
    if (ups == 1 || downs == 1)
    {
      const DualVertex* lone = ups == 1 ? up[0] : down[0];
      const DualVertex* const* others = ups == 1 ? down : up;
      emit(point(*lone, *others[0], contour, value), point(*lone, *others[1], contour, value),
           point(*lone, *others[2], contour, value));
    }
    else
    {
      // Two and two: the quad a0-b0, a0-b1, a1-b1, a1-b0, as two triangles.
      const vtkIdType p00 = point(*up[0], *down[0], contour, value);
      const vtkIdType p01 = point(*up[0], *down[1], contour, value);
      const vtkIdType p11 = point(*up[1], *down[1], contour, value);
      const vtkIdType p10 = point(*up[1], *down[0], contour, value);
      emit(p00, p01, p11);
      emit(p00, p11, p10);
    }
  }
}

} // namespace canopy
