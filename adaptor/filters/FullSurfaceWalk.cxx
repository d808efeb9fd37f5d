#include "FullSurfaceWalk.h"

#include "EdgeVertices.h"

#include <array>
#include <stdexcept>
#include <vector>

namespace canopy
{

namespace
{

/// A node's neighbour at its own level across one of its edges (2D): in this
/// tree or the next one, or none (nothing there at that level: a coarser leaf, a
/// masked node, the grid's border, a tree elsewhere).
struct Neighbour
{
  const TreeAccess* tree = nullptr;
  vtkIdType node = 0;
};

/// F: the branch factor; U, V: the active axes (V = -1 in 1D); W: an axis
/// whose coordinate is the tree's origin (2D: the flat one; 1D: both others).
template <int F, int U, int V>
class FullWalk
{
public:
  static constexpr int Corners = V >= 0 ? 4 : 2;
  /// In 2D, the neighbours across a node's edges, in polygonAround's order:
  /// across V below and above, across U below and above.
  using Neighbours = std::array<Neighbour, 4>;

  FullWalk(const HyperTreeAccess& grid, const TreeAccess& tree, const SurfaceArrays& arrays,
           std::size_t limit, std::size_t pointLimit, std::size_t pointBase)
      : Grid(grid), Tree(tree), Arrays(arrays), Limit(limit), PointLimit(pointLimit),
        PointBase(pointBase), Masked(grid.hasMask())
  {
  }

  FullSurfaceCount run()
  {
    const vtkIdType rootCell = Tree.globalIndex(0);
    if (hidden(rootCell))
    {
      return {};
    }
    Vec3 lo;
    Vec3 hi;
    Grid.nodeBounds(Tree, 0, {{0, 0, 0}}, lo, hi);
    for (int a = 0; a < 3; ++a)
    {
      Base[a] = lo[a];
    }
    // The roots around this one.
    Neighbours around;
    if constexpr (V >= 0)
    {
      const std::array<long, 3> root{{static_cast<long>(Tree.rootIJK[0]),
                                      static_cast<long>(Tree.rootIJK[1]),
                                      static_cast<long>(Tree.rootIJK[2])}};
      for (int e = 0; e < 4; ++e)
      {
        std::array<int, 3> offset{{0, 0, 0}};
        offset[e < 2 ? V : U] = e % 2 ? 1 : -1;
        Index3 at;
        std::array<long, 3> atRoot;
        bool elsewhere = false;
        const TreeAccess* other =
            treeOfCell(Grid, root, 0, {{0, 0, 0}}, offset, at, atRoot, elsewhere);
        if (other)
        {
          around[static_cast<std::size_t>(e)] = {other, 0};
        }
      }
    }
    if (Tree.isLeaf(0))
    {
      emit(rootCell, 0, 0, 0, lo[U], hi[U], V >= 0 ? lo[V] : 0.0, V >= 0 ? hi[V] : 0.0, around);
    }
    else
    {
      refined(0, 0, 0, 0, around);
    }
    return {Next, NextPoint};
  }

private:
  bool hidden(vtkIdType cell) const { return Masked && Grid.isMasked(cell); }

  /// Lower bounds of positions first .. first + F - 1 at `level` along `axis`,
  /// and the upper bound of the last (the row's end is exact, as in nodeBounds).
  void boundaries(int level, int axis, std::int64_t first, double (&b)[F + 1]) const
  {
    const std::int64_t cells = Grid.cellsPerRootAt(level);
    const double count = static_cast<double>(cells);
    const double origin = Tree.origin[axis];
    const double size = Tree.size[axis];
    for (int k = 0; k <= F; ++k)
    {
      b[k] = first + k == cells ? origin + size
                                : origin + size * (static_cast<double>(first + k) / count);
    }
  }

  /// The child at digits (du, dv) of neighbour n, if n is refined and visible.
  Neighbour childOf(const Neighbour& n, int du, int dv) const
  {
    if (!n.tree || n.tree->isLeaf(n.node) || (Masked && Grid.isMasked(n.tree->globalIndex(n.node))))
    {
      return {};
    }
    return {n.tree, n.tree->firstChild(n.node) + du + F * dv};
  }

  /// A refined, visible node at integer position (i, j) (along U, V) and `level`,
  /// with its neighbours at its level (2D).
  void refined(vtkIdType node, int level, std::int64_t i, std::int64_t j, const Neighbours& around)
  {
    double ub[F + 1];
    double vb[F + 1] = {};
    boundaries(level + 1, U, i * F, ub);
    if constexpr (V >= 0)
    {
      boundaries(level + 1, V, j * F, vb);
    }
    const vtkIdType first = Tree.firstChild(node);
    constexpr int Children = V >= 0 ? F * F : F;
    for (int c = 0; c < Children; ++c)
    {
      const vtkIdType child = first + c;
      const vtkIdType cell = Tree.globalIndex(child);
      if (hidden(cell))
      {
        continue; // a masked node hides its subtree
      }
      const int du = c % F;
      const int dv = c / F; // 0 in 1D
      // The child's neighbours: its siblings inside the node, else the children
      // of the node's neighbours facing it.
      Neighbours next;
      if constexpr (V >= 0)
      {
        next[0] = dv > 0 ? Neighbour{&Tree, child - F} : childOf(around[0], du, F - 1);
        next[1] = dv < F - 1 ? Neighbour{&Tree, child + F} : childOf(around[1], du, 0);
        next[2] = du > 0 ? Neighbour{&Tree, child - 1} : childOf(around[2], F - 1, dv);
        next[3] = du < F - 1 ? Neighbour{&Tree, child + 1} : childOf(around[3], 0, dv);
      }
      if (Tree.isLeaf(child))
      {
        emit(cell, level + 1, i * F + du, j * F + dv, ub[du], ub[du + 1], vb[dv], vb[dv + 1], next);
      }
      else
      {
        refined(child, level + 1, i * F + du, j * F + dv, next);
      }
    }
  }

  /// Corner order as the shared walk's: 2D (lo, +u, +u+v, +v), 1D (lo, +u); in
  /// 2D with the corners of finer neighbours on the edges (EdgeVertices.h),
  /// found below the neighbours at the leaf's level.
  void emit(vtkIdType cell, int level, std::int64_t i, std::int64_t j, double ulo, double uhi,
            double vlo, double vhi, const Neighbours& around)
  {
    std::size_t count = Corners;
    bool polygon = false;
    if constexpr (V >= 0)
    {
      Vec3 lo{{Base[0], Base[1], Base[2]}};
      Vec3 hi = lo;
      lo[U] = ulo;
      hi[U] = uhi;
      lo[V] = vlo;
      hi[V] = vhi;
      for (int e = 0; e < 4; ++e)
      {
        std::vector<double>& out = OnEdge[static_cast<std::size_t>(e)];
        out.clear();
        const Neighbour& n = around[static_cast<std::size_t>(e)];
        // Only a refined neighbour has finer cells along the edge.
        if (!n.tree || n.tree->isLeaf(n.node))
        {
          continue;
        }
        const int across = e < 2 ? V : U;
        const int along = e < 2 ? U : V;
        const std::int64_t cells = Grid.cellsPerRootAt(level);
        Index3 at{{0, 0, 0}};
        at[U] = i;
        at[V] = j;
        at[across] = ((e % 2 ? at[across] + 1 : at[across] - 1) + cells) % cells;
        EdgeCells edge;
        edge.along = along;
        edge.digit[static_cast<std::size_t>(across)] = e % 2 ? 0 : F - 1;
        edgeVertices(
            Grid, *n.tree, WalkNode{n.node, level, at}, level, at, edge, lo[along], hi[along],
            [this](const TreeAccess& t, const WalkNode& m) { return role(t, m); }, false, out,
            Stack);
        count += out.size();
        polygon = polygon || !out.empty();
      }
      if (polygon && Next < Limit && NextPoint + count <= PointLimit)
      {
        polygonAround(rectangleCorners(lo, hi, U, V), U, V, hi,
                      {{&OnEdge[0], &OnEdge[1], &OnEdge[2], &OnEdge[3]}}, Polygon);
        double* p = Arrays.points + 3 * NextPoint;
        for (const Vec3& q : Polygon)
        {
          *p++ = q[0];
          *p++ = q[1];
          *p++ = q[2];
        }
      }
    }
    if (!polygon && Next < Limit && NextPoint + count <= PointLimit)
    {
      double* p = Arrays.points + 3 * NextPoint;
      const double us[4] = {ulo, uhi, uhi, ulo};
      const double vs[4] = {vlo, vlo, vhi, vhi};
      // The other axes' coordinates in locals: stores through p could alias a member.
      const double base[3] = {Base[0], Base[1], Base[2]};
      for (int k = 0; k < Corners; ++k, p += 3)
      {
        for (int a = 0; a < 3; ++a)
        {
          p[a] = a == U ? us[k] : (a == V ? vs[k] : base[a]);
        }
      }
    }
    if (Next < Limit && NextPoint + count <= PointLimit)
    {
      Arrays.offsets[Next] = static_cast<vtkIdType>(PointBase + NextPoint);
      Arrays.cellIds[Next] = cell;
      Arrays.levels[Next] = static_cast<unsigned char>(level);
    }
    ++Next;
    NextPoint += count;
  }

  /// What this walk does at a node (EdgeVertices.h): leaves drawn, masked nodes hidden.
  EdgeRole role(const TreeAccess& t, const WalkNode& m) const
  {
    const vtkIdType global = t.globalIndex(m.node);
    if (Masked && Grid.isMasked(global))
    {
      return Grid.isAbsent(global) ? EdgeRole::Remote : EdgeRole::Hidden;
    }
    return t.isLeaf(m.node) ? EdgeRole::Drawn : EdgeRole::Descend;
  }

  const HyperTreeAccess& Grid;
  const TreeAccess& Tree;
  const SurfaceArrays& Arrays;
  const std::size_t Limit;
  const std::size_t PointLimit;
  const std::size_t PointBase;
  const bool Masked;
  double Base[3] = {0, 0, 0}; ///< the root's lower corner: the other axes' coordinates
  std::size_t Next = 0;
  std::size_t NextPoint = 0;
  std::array<std::vector<double>, 4> OnEdge; ///< emit's scratch
  std::vector<Vec3> Polygon;                 ///< the same
  std::vector<WalkNode> Stack;               ///< the same
};

template <int F>
FullSurfaceCount writeWith(const HyperTreeAccess& grid, const TreeAccess& tree,
                           const SurfaceArrays& arrays, std::size_t limit, std::size_t pointLimit,
                           std::size_t pointBase)
{
  const auto& axes = grid.activeAxes();
  if (grid.dimension() == 1)
  {
    switch (axes[0])
    {
    case 0:
      return FullWalk<F, 0, -1>(grid, tree, arrays, limit, pointLimit, pointBase).run();
    case 1:
      return FullWalk<F, 1, -1>(grid, tree, arrays, limit, pointLimit, pointBase).run();
    default:
      return FullWalk<F, 2, -1>(grid, tree, arrays, limit, pointLimit, pointBase).run();
    }
  }
  if (axes[0] == 0 && axes[1] == 1)
  {
    return FullWalk<F, 0, 1>(grid, tree, arrays, limit, pointLimit, pointBase).run();
  }
  if (axes[0] == 0)
  {
    return FullWalk<F, 0, 2>(grid, tree, arrays, limit, pointLimit, pointBase).run();
  }
  return FullWalk<F, 1, 2>(grid, tree, arrays, limit, pointLimit, pointBase).run();
}

} // namespace

FullSurfaceCount writeFullSurface(const HyperTreeAccess& grid, const TreeAccess& tree,
                                  const SurfaceArrays& arrays, std::size_t limit,
                                  std::size_t pointLimit, std::size_t pointBase)
{
  if (grid.dimension() < 1 || grid.dimension() > 2)
  {
    throw std::logic_error("writeFullSurface: 1D and 2D grids only");
  }
  switch (grid.branchFactor())
  {
  case 2:
    return writeWith<2>(grid, tree, arrays, limit, pointLimit, pointBase);
  case 3:
    return writeWith<3>(grid, tree, arrays, limit, pointLimit, pointBase);
  default:
    throw std::logic_error("writeFullSurface: branch factor 2 or 3 only");
  }
}

} // namespace canopy
