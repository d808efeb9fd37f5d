// The vertices that smaller pieces put on the edges of a 3D surface's face
// pieces (EdgeVertices.h says why a flat piece carries them). A face's edge is
// where four cells meet: the piece's own, the hole across the face, and the two
// others, beside the piece's cell and diagonally across, where the pieces
// meeting the edge come from (their drawn nodes' and their holes' bounds, a
// masked node bounding the faces it exposes). Both lie in the drawn node's
// neighbours across a face or an edge, which the face walk carries down the
// tree (SolidNeighbours.h): each search starts at the drawn node's level.
#pragma once

#include "EdgeVertices.h"
#include "HyperTreeAccess.h"
#include "SolidNeighbours.h"
#include "TreeTraversal.h"
#include "Vec3.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <vector>

namespace canopy
{

/// The vertices on the four edges of a 3D face piece, found around each edge.
/// The piece is the face normal to `axis`, on side `side` (1: the upper one), of
/// the cell at `level`, `ijk` on the solid's side: the drawn node at
/// `nodeLevel`, `nodeIJK` itself, or a finer cell inside it facing a finer hole.
/// It spans lo to hi on the other axes u = axis + 1 and v = axis + 2 (mod 3);
/// onEdge as rectangleEdgeVertices gives it. `around(d)`: the drawn node's
/// same-level neighbour in direction d (SolidNeighbours::at). Returns the edges
/// (bit e for onEdge[e]) around which another rank's part was met.
template <typename Around, typename Classify>
unsigned faceEdgeVertices(const HyperTreeAccess& grid, int nodeLevel, const Index3& nodeIJK,
                          int level, const Index3& ijk, int axis, int side, const Vec3& lo,
                          const Vec3& hi, Around&& around, Classify&& classify,
                          std::array<std::vector<double>, 4>& onEdge, EdgeScratch& scratch)
{
  using Kind = SolidNeighbours::Neighbour::Kind;
  const int f = grid.branchFactor();
  const int u = (axis + 1) % 3;
  const int v = (axis + 2) % 3;
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
      Index3 at = ijk;
      at[static_cast<std::size_t>(across)] += edgeSide ? 1 : -1;
      if (diagonal)
      {
        at[static_cast<std::size_t>(axis)] += side ? 1 : -1;
      }
      // The drawn node's neighbour holding the cell (a step of -1, 0 or 1 per
      // axis at the node's level), and the cell's position in that one's tree.
      SolidNeighbours::Direction step{{0, 0, 0}};
      for (std::size_t a = 0; a < 3; ++a)
      {
        const std::int64_t outer = at[a] < 0            ? -1
                                   : level == nodeLevel ? at[a]
                                   : f == 2             ? at[a] >> (level - nodeLevel)
                                                        : at[a] / scale;
        step[a] = static_cast<int>(outer - nodeIJK[a]);
        at[a] = at[a] < 0 ? perRoot - 1 : at[a] >= perRoot ? 0 : at[a];
      }
      const SolidNeighbours::Neighbour& holder = around(step);
      if (holder.kind != Kind::Node)
      {
        // Nothing drawn there (a border, a hole, a leaf as large or larger),
        // or another rank's part.
        remote |= holder.kind == Kind::Elsewhere || holder.kind == Kind::Absent ? 1u << e : 0u;
        continue;
      }
      EdgeCells cells;
      cells.along = along;
      cells.digit[static_cast<std::size_t>(across)] = edgeSide ? 0 : f - 1;
      // The children touching the face's plane: on the face's side of a cell
      // beside the piece's, on the opposite side of one across the plane.
      cells.digit[static_cast<std::size_t>(axis)] = (side == 1) != diagonal ? f - 1 : 0;
      found.clear();
      WalkNode start{holder.node, nodeLevel, at};
      for (std::size_t a = 0; level > nodeLevel && a < 3; ++a)
      {
        start.ijk[a] = f == 2 ? at[a] >> (level - nodeLevel) : at[a] / scale;
      }
      if (!edgeVertices(grid, *holder.tree, start, level, at, cells,
                        lo[static_cast<std::size_t>(along)], hi[static_cast<std::size_t>(along)],
                        classify, true, found, scratch.stack))
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
