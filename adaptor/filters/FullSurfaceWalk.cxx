#include "FullSurfaceWalk.h"

#include "EdgeVertices.h"

#include <stdexcept>

namespace canopy
{

namespace
{

/// F: the branch factor; U, V: the active axes (V = -1 in 1D); W: an axis
/// whose coordinate is the tree's origin (2D: the flat one; 1D: both others).
template <int F, int U, int V>
class FullWalk
{
public:
  static constexpr int Corners = V >= 0 ? 4 : 2;

  FullWalk(const HyperTreeAccess& grid, const TreeAccess& tree, const SurfaceArrays& arrays,
           std::size_t limit, std::size_t pointLimit, std::size_t pointBase)
      : Grid(grid), Tree(tree), Arrays(arrays), Limit(limit), PointLimit(pointLimit),
        PointBase(pointBase), Masked(grid.hasMask()),
        Path(static_cast<std::size_t>(grid.maxLevel()) + 1, 0)
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
    if (Tree.isLeaf(0))
    {
      emit(0, rootCell, 0, 0, 0, lo[U], hi[U], V >= 0 ? lo[V] : 0.0, V >= 0 ? hi[V] : 0.0);
    }
    else
    {
      refined(0, 0, 0, 0);
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

  /// A refined, visible node at integer position (i, j) (along U, V) and `level`.
  void refined(vtkIdType node, int level, std::int64_t i, std::int64_t j)
  {
    Path[static_cast<std::size_t>(level)] = node;
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
      if (Tree.isLeaf(child))
      {
        emit(child, cell, level + 1, i * F + du, j * F + dv, ub[du], ub[du + 1], vb[dv],
             vb[dv + 1]);
      }
      else
      {
        refined(child, level + 1, i * F + du, j * F + dv);
      }
    }
  }

  /// Corner order as the shared walk's: 2D (lo, +u, +u+v, +v), 1D (lo, +u); in
  /// 2D with the corners of finer neighbours on the edges (EdgeVertices.h).
  void emit(vtkIdType node, vtkIdType cell, int level, std::int64_t i, std::int64_t j, double ulo,
            double uhi, double vlo, double vhi)
  {
    std::size_t count = Corners;
    if constexpr (V >= 0)
    {
      Vec3 lo{{Base[0], Base[1], Base[2]}};
      Vec3 hi = lo;
      lo[U] = ulo;
      hi[U] = uhi;
      lo[V] = vlo;
      hi[V] = vhi;
      Index3 ijk{{0, 0, 0}};
      ijk[U] = i;
      ijk[V] = j;
      rectangleEdgeVertices(
          Grid, Tree, Path.data(), WalkNode{node, level, ijk}, U, V, lo, hi, -1, nullptr,
          [this](const TreeAccess& t, const WalkNode& m) { return role(t, m); }, OnEdge);
      count += OnEdge[0].size() + OnEdge[1].size() + OnEdge[2].size() + OnEdge[3].size();
      if (Next < Limit && NextPoint + count <= PointLimit)
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
    else if (Next < Limit && NextPoint + count <= PointLimit)
    {
      double* p = Arrays.points + 3 * NextPoint;
      const double us[2] = {ulo, uhi};
      // The other axes' coordinates in locals: stores through p could alias a member.
      const double base[3] = {Base[0], Base[1], Base[2]};
      for (int k = 0; k < Corners; ++k, p += 3)
      {
        for (int a = 0; a < 3; ++a)
        {
          p[a] = a == U ? us[k] : base[a];
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
  std::vector<vtkIdType> Path;               ///< the refined nodes above the current one
  std::array<std::vector<double>, 4> OnEdge; ///< emit's scratch
  std::vector<Vec3> Polygon;                 ///< the same
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
