// The vertices that smaller pieces put on the edges of a 3D surface's face
// pieces (EdgeVertices.h says why a flat piece carries them). A face's edge is
// where four cells meet: the piece's own, the hole across the face, and the two
// others, beside the piece's cell and diagonally across, where the pieces
// meeting the edge come from (their drawn nodes' and their holes' bounds, a
// masked node bounding the faces it exposes).
#pragma once

#include "EdgeVertices.h"
#include "HyperTreeAccess.h"
#include "TreeTraversal.h"
#include "Vec3.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <vector>

namespace canopy
{

/// The deepest common ancestor of the cells at `from` and `to` (same level,
/// same tree), given `from`'s ancestors (path[l]: its ancestor at level l).
inline WalkNode commonAncestor(const HyperTreeAccess& grid, const vtkIdType* path, int level,
                               const Index3& from, const Index3& to)
{
  if (grid.branchFactor() == 2)
  {
    // The positions agree above their highest differing bit.
    std::uint64_t differing = 0;
    for (int a = 0; a < 3; ++a)
    {
      differing |= static_cast<std::uint64_t>(from[a] ^ to[a]);
    }
    int up = 0;
    for (; differing; differing >>= 1)
    {
      ++up;
    }
    if (up > level)
    {
      return {0, 0, {{0, 0, 0}}};
    }
    return {path[level - up], level - up, {{from[0] >> up, from[1] >> up, from[2] >> up}}};
  }
  for (int up = 1; up <= level; ++up)
  {
    const std::int64_t scale = grid.cellsPerRootAt(up);
    bool same = true;
    for (int a = 0; a < 3 && same; ++a)
    {
      same = from[a] / scale == to[a] / scale;
    }
    if (same)
    {
      return {path[level - up], level - up, {{from[0] / scale, from[1] / scale, from[2] / scale}}};
    }
  }
  return {0, 0, {{0, 0, 0}}};
}

/// The vertices on the four edges of a 3D face piece, found around each edge.
/// The piece is the face normal to `axis`, on side `side` (1: the upper one), of
/// the cell at `level`, `ijk` on the solid's side (in `tree`): the drawn node
/// at `nodeLevel`, `nodeIJK` itself, or a finer cell inside it facing a finer
/// hole. It spans lo to hi on the other axes u = axis + 1 and v = axis + 2
/// (mod 3); onEdge as rectangleEdgeVertices gives it. Four cells meet along an
/// edge: the piece's own (inside the drawn node), the hole across the face,
/// and the two others, beside the piece's cell and diagonally across, where the
/// pieces meeting it come from: their drawn nodes' and holes' bounds (a masked
/// node bounds the faces it exposes). `path`: the drawn node's ancestors, or
/// nullptr (descents then start at the roots). Returns the edges (bit e for
/// onEdge[e]) around which another rank's part was met.
template <typename Classify>
unsigned faceEdgeVertices(const HyperTreeAccess& grid, const TreeAccess& tree,
                          const vtkIdType* path, int nodeLevel, const Index3& nodeIJK, int level,
                          const Index3& ijk, int axis, int side, const Vec3& lo, const Vec3& hi,
                          Classify&& classify, std::array<std::vector<double>, 4>& onEdge,
                          EdgeScratch& scratch)
{
  const int f = grid.branchFactor();
  const int u = (axis + 1) % 3;
  const int v = (axis + 2) % 3;
  const std::array<long, 3> root{{static_cast<long>(tree.rootIJK[0]),
                                  static_cast<long>(tree.rootIJK[1]),
                                  static_cast<long>(tree.rootIJK[2])}};
  const std::int64_t scale = grid.cellsPerRootAt(level - nodeLevel);
  const std::int64_t perRoot = grid.cellsPerRootAt(level);
  std::vector<double>& found = scratch.found;
  std::vector<double>& merged = scratch.merged;
  unsigned remote = 0;
  for (int e = 0; e < 4; ++e)
  {
    const int across = e < 2 ? v : u; // the axis the edge is crossed along, in the face
    const int along = e < 2 ? u : v;
    const int edgeSide = e % 2;
    std::vector<double>& out = onEdge[static_cast<std::size_t>(e)];
    out.clear();
    for (const bool diagonal : {false, true})
    {
      std::array<int, 3> offset{{0, 0, 0}};
      offset[static_cast<std::size_t>(across)] = edgeSide ? 1 : -1;
      EdgeCells cells;
      cells.along = along;
      cells.digit[static_cast<std::size_t>(across)] = edgeSide ? 0 : f - 1;
      // The children touching the face's plane: on the face's side of a cell
      // beside the piece's, on the opposite side of one across the plane.
      cells.digit[static_cast<std::size_t>(axis)] = (side == 1) != diagonal ? f - 1 : 0;
      if (diagonal)
      {
        offset[static_cast<std::size_t>(axis)] = side ? 1 : -1;
      }
      Index3 at = ijk;
      const TreeAccess* other = &tree;
      bool inside = true; // in this tree
      for (int a = 0; a < 3; ++a)
      {
        at[a] += offset[static_cast<std::size_t>(a)];
        inside = inside && at[a] >= 0 && at[a] < perRoot;
      }
      if (!inside)
      {
        std::array<long, 3> atRoot;
        bool elsewhere = false;
        other = treeOfCell(grid, root, level, ijk, offset, at, atRoot, elsewhere);
        if (!other)
        {
          remote |= elsewhere ? 1u << e : 0u;
          continue;
        }
      }
      else if (level > nodeLevel && at[0] / scale == nodeIJK[0] && at[1] / scale == nodeIJK[1] &&
               at[2] / scale == nodeIJK[2])
      {
        continue; // inside the drawn node: drawn whole, no corner inside the edge
      }
      const WalkNode from =
          other == &tree && path ? commonAncestor(grid, path, level, ijk, at) : WalkNode{};
      found.clear();
      if (!edgeVertices(grid, *other, from, level, at, cells, lo[static_cast<std::size_t>(along)],
                        hi[static_cast<std::size_t>(along)], classify, true, found, scratch.stack))
      {
        remote |= 1u << e;
      }
      // Both cells' bounds, merged in order.
      if (out.empty())
      {
        out.swap(found);
      }
      else if (!found.empty())
      {
        merged.clear();
        std::merge(out.begin(), out.end(), found.begin(), found.end(), std::back_inserter(merged));
        merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
        out.swap(merged);
      }
    }
  }
  return remote;
}

} // namespace canopy
