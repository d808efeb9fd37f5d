#include "FullSurfaceWalk.h"

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
    if (Tree.isLeaf(0))
    {
      emit(rootCell, 0, lo[U], hi[U], V >= 0 ? lo[V] : 0.0, V >= 0 ? hi[V] : 0.0);
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
        emit(cell, level + 1, ub[du], ub[du + 1], vb[dv], vb[dv + 1]);
      }
      else
      {
        refined(child, level + 1, i * F + du, j * F + dv);
      }
    }
  }

  /// Corner order as the shared walk's: 2D (lo, +u, +u+v, +v), 1D (lo, +u).
  void emit(vtkIdType cell, int level, double ulo, double uhi, double vlo, double vhi)
  {
    if (Next < Limit && NextPoint + Corners <= PointLimit)
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
      Arrays.offsets[Next] = static_cast<vtkIdType>(PointBase + NextPoint);
      Arrays.cellIds[Next] = cell;
      Arrays.levels[Next] = static_cast<unsigned char>(level);
    }
    ++Next;
    NextPoint += Corners;
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
