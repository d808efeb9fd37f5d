#include "LeafGradient.h"

#include <cmath>

namespace canopy
{

DualNode LeafGradient::across(const DualNode& leaf, int i, bool upper, bool farCorner) const
{
  DualNode none{};
  none.kind = DualNode::Outside;
  const int a = Dual.axis(i);
  const std::size_t ua = static_cast<std::size_t>(a);
  const std::int64_t cells = Grid.cellsPerRootAt(leaf.level);
  std::array<std::int64_t, 3> target = leaf.ijk;
  std::array<long, 3> rootIJK{{static_cast<long>(leaf.tree->rootIJK[0]),
                               static_cast<long>(leaf.tree->rootIJK[1]),
                               static_cast<long>(leaf.tree->rootIJK[2])}};
  target[ua] += upper ? 1 : -1;
  if (target[ua] < 0 || target[ua] >= cells)
  {
    // In the next tree along the axis, at the matching position.
    rootIJK[ua] += upper ? 1 : -1;
    target[ua] = upper ? 0 : cells - 1;
    const auto& roots = Grid.rootCells();
    if (rootIJK[ua] < 0 || rootIJK[ua] >= static_cast<long>(roots[ua]))
    {
      return none; // the domain's boundary
    }
  }
  // Down from the root, as the traversal classifies nodes: other ranks' parts
  // through their ghosts (ContourGhosts.h), so every rank finds the same leaves.
  DualNode n = Dual.rootNode(rootIJK);
  while (n.kind == DualNode::Inner)
  {
    int c = 0;
    if (n.level < leaf.level)
    {
      c = Grid.childToward(n.level, leaf.level, target);
    }
    else
    {
      // Finer than the leaf: the child against the shared face, at the
      // face's lowest or highest corner.
      const int last = Grid.branchFactor() - 1;
      int weight = 1;
      for (int j = 0; j < Dual.dimension(); ++j)
      {
        c += (j == i ? (upper ? 0 : last) : (farCorner ? last : 0)) * weight;
        weight *= Grid.branchFactor();
      }
    }
    DualNode child;
    Dual.childNode(child, n, c);
    n = child;
  }
  if (n.kind != DualNode::Leaf)
  {
    none.kind = DualNode::Hidden;
    return none;
  }
  return n;
}

std::array<double, 3> LeafGradient::at(const DualNode& leaf) const
{
  const int d = Dual.dimension();
  const std::array<double, 3> c = nodeCentre(Grid, leaf);
  const double f = Field(Dual.leafId(leaf));
  // Normal equations in the active axes: A g = b.
  double A[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  double b[3] = {0, 0, 0};
  for (int i = 0; i < d; ++i)
  {
    for (int side = 0; side < 4; ++side)
    {
      // Each face's leaf at the face's lowest corner, and, where finer leaves
      // meet the face, the one at its highest corner too (finer leaves alone
      // can lie in one plane with the coarser ones: ternary trees do).
      const bool upper = side & 1;
      const bool farCorner = side & 2;
      const DualNode n = across(leaf, i, upper, farCorner);
      if (n.kind != DualNode::Leaf || (farCorner && n.level <= leaf.level))
      {
        continue;
      }
      const std::array<double, 3> cn = nodeCentre(Grid, n);
      const double df = Field(Dual.leafId(n)) - f;
      double off[3];
      for (int j = 0; j < d; ++j)
      {
        off[j] =
            cn[static_cast<std::size_t>(Dual.axis(j))] - c[static_cast<std::size_t>(Dual.axis(j))];
      }
      for (int j = 0; j < d; ++j)
      {
        b[j] += off[j] * df;
        for (int k = 0; k < d; ++k)
        {
          A[j][k] += off[j] * off[k];
        }
      }
    }
  }
  double g[3] = {0, 0, 0};
  // Cramer's rule; a (nearly) singular system: the neighbours do not span the
  // dimension, constant extrapolation.
  if (d == 2)
  {
    const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
    if (std::abs(det) > 1e-12 * A[0][0] * A[1][1] && det != 0)
    {
      g[0] = (b[0] * A[1][1] - A[0][1] * b[1]) / det;
      g[1] = (A[0][0] * b[1] - b[0] * A[1][0]) / det;
    }
  }
  else
  {
    auto det3 = [](const double m[3][3])
    {
      return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
             m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
             m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    const double det = det3(A);
    if (std::abs(det) > 1e-12 * A[0][0] * A[1][1] * A[2][2] && det != 0)
    {
      for (int j = 0; j < 3; ++j)
      {
        double m[3][3];
        for (int r = 0; r < 3; ++r)
        {
          for (int k = 0; k < 3; ++k)
          {
            m[r][k] = k == j ? b[r] : A[r][k];
          }
        }
        g[j] = det3(m) / det;
      }
    }
  }
  std::array<double, 3> gradient{{0, 0, 0}};
  for (int j = 0; j < d; ++j)
  {
    gradient[static_cast<std::size_t>(Dual.axis(j))] = g[j];
  }
  return gradient;
}

} // namespace canopy
