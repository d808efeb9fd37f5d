#include "DualCellContour.h"

#include <algorithm>
#include <utility>

namespace canopy
{

namespace
{

std::array<double, 3> minus(const std::array<double, 3>& a, const std::array<double, 3>& b)
{
  return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
}

std::array<double, 3> cross(const std::array<double, 3>& a, const std::array<double, 3>& b)
{
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}

double dot(const std::array<double, 3>& a, const std::array<double, 3>& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

} // namespace

DualCellContour::DualCellContour(const HyperTreeAccess& grid, const DualTraversal& dual,
                                 const ContourField& field, const std::vector<double>& values,
                                 ContourPiece& out)
    : Grid(grid), Dual(dual), Field(field), Values(values), Out(out), Gradient(grid, dual, field)
{
}

bool DualCellContour::vertex(const DualGroup& group, unsigned s, DualVertex& v)
{
  const DualNode* n = &group[s];
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
    n = &group[mirror];
  }
  if (n->kind != DualNode::Leaf)
  {
    return false;
  }
  v.leaf = n->tree->globalIndex(n->node);
  v.key = static_cast<std::uint64_t>(v.leaf) * 64 + sides;
  v.value = Field(v.leaf);
  if (sides == 0)
  {
    v.x = nodeCentre(Grid, *n);
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
  v.value += dot(found->second, minus(v.x, centre));
  return true;
}

void DualCellContour::cell(const DualGroup& group)
{
  ++DualCells;
  const unsigned corners = 1u << Dual.dimension();
  std::array<DualVertex, 8> v;
  for (unsigned s = 0; s < corners; ++s)
  {
    if (!vertex(group, s, v[s]))
    {
      return;
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
  // Kuhn: one tetrahedron per order of the axes, along the path 0 -> 7.
  static const unsigned paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  for (const auto& path : paths)
  {
    const DualVertex* t[4] = {&v[0], &v[path[0]], &v[path[1]], &v[7]};
    tetrahedron(t);
  }
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
    vtkIdType from = Out.point(p, q, contour, value);
    vtkIdType to = Out.point(p, r, contour, value);
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
    // Normals towards lower values: away from an above vertex.
    const DualVertex& reference = *up[0];
    auto emit = [&](vtkIdType p0, vtkIdType p1, vtkIdType p2)
    {
      const auto& x0 = Out.points[static_cast<std::size_t>(p0)];
      const auto normal = cross(minus(Out.points[static_cast<std::size_t>(p1)], x0),
                                minus(Out.points[static_cast<std::size_t>(p2)], x0));
      if (dot(normal, minus(reference.x, x0)) > 0)
      {
        std::swap(p1, p2);
      }
      Out.cells.push_back(p0);
      Out.cells.push_back(p1);
      Out.cells.push_back(p2);
    };
    if (ups == 1 || downs == 1)
    {
      const DualVertex* lone = ups == 1 ? up[0] : down[0];
      const DualVertex* const* others = ups == 1 ? down : up;
      emit(Out.point(*lone, *others[0], contour, value),
           Out.point(*lone, *others[1], contour, value),
           Out.point(*lone, *others[2], contour, value));
    }
    else
    {
      // Two and two: the quad a0-b0, a0-b1, a1-b1, a1-b0, as two triangles.
      const vtkIdType p00 = Out.point(*up[0], *down[0], contour, value);
      const vtkIdType p01 = Out.point(*up[0], *down[1], contour, value);
      const vtkIdType p11 = Out.point(*up[1], *down[1], contour, value);
      const vtkIdType p10 = Out.point(*up[1], *down[0], contour, value);
      emit(p00, p01, p11);
      emit(p00, p11, p10);
    }
  }
}

} // namespace canopy
