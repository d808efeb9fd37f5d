// The vertices that finer neighbours put on a drawn flat piece's edges.
//
// Where a coarse piece (a slice's cut, a 2D grid's quad, a 3D node's face) meets
// finer ones along an edge (a T-junction), the finer pieces' corners lie inside
// its edge. A rasterizer fills the seam between two triangles without a gap only
// when both have the same edge; the coarse piece's one long edge next to the
// fine pieces' short ones leaves pixels that neither covers (single background
// pixels in slices and surfaces). So a drawn piece is a polygon that carries
// those corners, in order along each edge: neighbours' edges then coincide
// exactly, point for point, whatever the rasterizer (docs/filters.md, "Flat
// pieces meet edge to edge").
//
// The corners come from the trees, not from the output: from the cell at the
// piece's level on the other side of the edge (an integer position, in this
// tree or the next), the nodes below it that touch the edge, down to where the
// walk that draws them stops. The caller gives that walk's rule (classify) and
// which children touch the edge (a digit per axis), so that the two agree by
// construction. Their bounds along the edge, strictly inside it, are the
// vertices. On the way down to the piece's level only the topology is asked
// (a masked node, a leaf): were level of detail to stop there, it would stop at
// the cell at the piece's level too (a node's footprint is at most its
// parent's), which has no corner inside the edge either way. The walks carry
// each node's neighbours down the tree rather than looking for them from a
// common ancestor: across its edges in a plane (2D, slices: PlaneNeighbours),
// across its faces and edges in 3D (SolidNeighbours.h, FaceEdgeVertices.h).
//
// Another rank's part met on the way (an absent node, a tree elsewhere) is
// reported: the caller then asks the other ranks (EdgeVertexExchange.h).
#pragma once

#include "HyperTreeAccess.h"
#include "TreeTraversal.h"
#include "Vec3.h"

#include <array>
#include <cstdint>
#include <vector>

namespace canopy
{

using Index3 = std::array<std::int64_t, 3>;

/// What the walk that draws a grid does at a node it reaches.
enum class EdgeRole
{
  Descend, ///< enters its children
  Drawn,   ///< stops and draws it (a leaf, or a node level of detail draws whole)
  Hidden,  ///< a masked node: not drawn, nor anything below it
  Remote   ///< another rank's part: what is drawn there, that rank knows
};

/// Which descendants of a cell touch one of its edges: the edge runs along
/// `along`; on every other axis `digit` gives the child digit on the edge's side
/// (0 or f - 1), or Any on an axis the grid does not have (2D), or Cut on a
/// slice's axis, whose digit at each level `cutDigits` gives (indexed by the
/// child's level).
struct EdgeCells
{
  static constexpr int Any = -1;
  static constexpr int Cut = -2;
  int along = 0;
  std::array<int, 3> digit{{Any, Any, Any}};
  const std::vector<int>* cutDigits = nullptr;
};

/// Memory the searches reuse, one per walk (not per call: they are many).
struct EdgeScratch
{
  std::vector<WalkNode> stack;
  std::vector<double> found;
  std::vector<double> merged;
};

/// The tree holding the cell at `ijk` + `offset` (each -1, 0 or +1) at `level`
/// below root cell `root`, and that cell's position in it (`at`, `atRoot`).
/// nullptr when there is no tree here; `elsewhere` then says whether the root
/// cell's tree is on another rank (rather than outside the grid, or a hole).
inline const TreeAccess* treeOfCell(const HyperTreeAccess& grid, const std::array<long, 3>& root,
                                    int level, const Index3& ijk, const std::array<int, 3>& offset,
                                    Index3& at, std::array<long, 3>& atRoot, bool& elsewhere)
{
  const std::int64_t cells = grid.cellsPerRootAt(level);
  at = ijk;
  atRoot = root;
  for (int a = 0; a < 3; ++a)
  {
    if (offset[a] == 0)
    {
      continue;
    }
    at[a] += offset[a];
    if (at[a] < 0)
    {
      at[a] = cells - 1;
      atRoot[a] -= 1;
    }
    else if (at[a] >= cells)
    {
      at[a] = 0;
      atRoot[a] += 1;
    }
  }
  const TreeAccess* tree = grid.treeAt(atRoot[0], atRoot[1], atRoot[2]);
  elsewhere = !tree && grid.treeElsewhere(atRoot[0], atRoot[1], atRoot[2]);
  return tree;
}

/// Appends to `out`, ascending and without repeats, the bounds along
/// `cells.along` strictly inside (lo, hi) of the nodes where the drawing walk
/// stops (Drawn, and Hidden when `hiddenBound`: in 3D a masked node bounds the
/// faces it exposes) among the descendants of the cell at `level`, `target`
/// that touch the edge `cells` describes; the descent to that cell starts at
/// `start` (one of its ancestors in `tree`, or itself). `classify(tree, node)`
/// is the drawing walk's rule. Returns false when another rank's part was met
/// on the way (what lies there, only that rank knows).
template <typename Classify>
bool edgeVertices(const HyperTreeAccess& grid, const TreeAccess& tree, WalkNode start, int level,
                  const Index3& target, const EdgeCells& cells, double lo, double hi,
                  Classify&& classify, bool hiddenBound, std::vector<double>& out,
                  std::vector<WalkNode>& stack)
{
  // Down to the cell: a masked node or a leaf above it holds the whole edge.
  WalkNode m = start;
  while (m.level < level)
  {
    const vtkIdType global = tree.globalIndex(m.node);
    if (grid.hasMask() && grid.isMasked(global))
    {
      return !grid.isAbsent(global);
    }
    if (tree.isLeaf(m.node))
    {
      return true;
    }
    const int child = grid.childToward(m.level, level, target);
    m = {tree.firstChild(m.node) + child, m.level + 1, grid.childPosition(m.ijk, child)};
  }
  // The cell itself first: most often it is drawn whole (no corner inside the
  // edge), and a walk below it costs a stack.
  switch (classify(tree, m))
  {
  case EdgeRole::Remote:
    return false;
  case EdgeRole::Descend:
    break;
  default:
    return true;
  }
  bool local = true;
  const std::size_t first = out.size();
  auto add = [&](double x)
  {
    if (x > lo && x < hi && (out.size() == first || out.back() != x))
    {
      out.push_back(x);
    }
  };
  // Depth first, children in order: the bounds come ascending along the edge.
  walkSubtree(
      grid, tree, m,
      [&](WalkNode& n)
      {
        switch (n.level == level ? EdgeRole::Descend : classify(tree, n))
        {
        case EdgeRole::Remote:
          local = false;
          return WalkStep::Skip;
        case EdgeRole::Hidden:
          if (!hiddenBound)
          {
            return WalkStep::Skip;
          }
          [[fallthrough]];
        case EdgeRole::Drawn:
          if (n.level > level)
          {
            add(grid.nodeLower(tree, n.level, cells.along, n.ijk[cells.along]));
            add(grid.nodeLower(tree, n.level, cells.along, n.ijk[cells.along] + 1));
          }
          return WalkStep::Skip;
        default:
          return WalkStep::Descend;
        }
      },
      [&](const WalkNode& parent, int c)
      {
        const auto& digits = grid.childDigits(c);
        for (int a = 0; a < 3; ++a)
        {
          const int want = cells.digit[a];
          if (a == cells.along || want == EdgeCells::Any || digits[a] < 0)
          {
            continue;
          }
          const int need = want == EdgeCells::Cut
                               ? (*cells.cutDigits)[static_cast<std::size_t>(parent.level) + 1]
                               : want;
          if (digits[a] != need)
          {
            return false;
          }
        }
        return true;
      },
      stack);
  return local;
}

/// The neighbours at a node's own level across its four edges in a plane (the
/// axes u and v of a 2D grid, or of a slice's cut through a 3D grid), kept per
/// level during a depth-first walk that enters each node after its parent: a
/// node's are its siblings or the children of its parent's, so finding them
/// costs a few steps per node, not a descent per edge. Edges are numbered as
/// polygonAround numbers them: across v below and above, across u below and
/// above.
class PlaneNeighbours
{
public:
  /// A neighbour: a node of `tree`, or none at this level (the grid's border, a
  /// coarser leaf, a masked node); `remote`: none because another rank has
  /// that part (a tree elsewhere, an absent node).
  struct Neighbour
  {
    const TreeAccess* tree = nullptr;
    vtkIdType node = 0;
    bool remote = false;
  };
  using Around = std::array<Neighbour, 4>;

  PlaneNeighbours(const HyperTreeAccess& grid, const TreeAccess& tree, int u, int v)
      : Grid(grid), Tree(tree), U(u), V(v),
        Levels(static_cast<std::size_t>(deepestLevel(grid, tree)) + 1)
  {
    int weight = 1;
    for (int a : grid.activeAxes())
    {
      Weight[static_cast<std::size_t>(a)] = weight;
      weight *= grid.branchFactor();
    }
  }

  /// Call on entering node n, a child of the node entered last one level up
  /// (or the root).
  void enter(const WalkNode& n)
  {
    if (static_cast<std::size_t>(n.level) >= Levels.size())
    {
      Levels.resize(static_cast<std::size_t>(n.level) + 1); // deeper than its tree said
    }
    Around& here = Levels[static_cast<std::size_t>(n.level)];
    const int f = Grid.branchFactor();
    for (int e = 0; e < 4; ++e)
    {
      const int across = e < 2 ? V : U;
      const int side = e % 2;
      Neighbour& out = here[static_cast<std::size_t>(e)];
      out = Neighbour{};
      if (n.level == 0)
      {
        const std::array<long, 3> root{{static_cast<long>(Tree.rootIJK[0]),
                                        static_cast<long>(Tree.rootIJK[1]),
                                        static_cast<long>(Tree.rootIJK[2])}};
        std::array<int, 3> offset{{0, 0, 0}};
        offset[static_cast<std::size_t>(across)] = side ? 1 : -1;
        Index3 at;
        std::array<long, 3> atRoot;
        bool elsewhere = false;
        out.tree = treeOfCell(Grid, root, 0, n.ijk, offset, at, atRoot, elsewhere);
        out.remote = !out.tree && elsewhere;
        continue;
      }
      const std::int64_t position = n.ijk[static_cast<std::size_t>(across)];
      const int digit = static_cast<int>(f == 2 ? position & 1 : position % f);
      const vtkIdType step = Weight[static_cast<std::size_t>(across)];
      if (side ? digit < f - 1 : digit > 0)
      {
        out = {&Tree, side ? n.node + step : n.node - step, false}; // a sibling
        continue;
      }
      // The child of the parent's neighbour facing this node.
      const Neighbour& parent =
          Levels[static_cast<std::size_t>(n.level) - 1][static_cast<std::size_t>(e)];
      if (!parent.tree)
      {
        out.remote = parent.remote;
        continue;
      }
      const vtkIdType global = parent.tree->globalIndex(parent.node);
      if (Grid.hasMask() && Grid.isMasked(global))
      {
        out.remote = Grid.isAbsent(global);
        continue;
      }
      if (parent.tree->isLeaf(parent.node))
      {
        continue; // a coarser leaf: nothing of it inside this node's edge
      }
      // This node's child index, with the digit across the edge mirrored.
      vtkIdType child = 0;
      for (int a : Grid.activeAxes())
      {
        const std::int64_t p = n.ijk[static_cast<std::size_t>(a)];
        child += (f == 2 ? p & 1 : p % f) * Weight[static_cast<std::size_t>(a)];
      }
      child += (side ? -digit : f - 1 - digit) * step;
      out = {parent.tree, parent.tree->firstChild(parent.node) + child, false};
    }
  }

  const Around& at(int level) const { return Levels[static_cast<std::size_t>(level)]; }

private:
  const HyperTreeAccess& Grid;
  const TreeAccess& Tree;
  const int U;
  const int V;
  std::array<vtkIdType, 3> Weight{{0, 0, 0}}; ///< a child digit's weight in the child index
  std::vector<Around> Levels;
};

/// The vertices on the four edges of node n's flat piece, a rectangle in the
/// plane of axes u and v spanning lo to hi (a 2D grid's node, or a slice's cut
/// of a 3D node, then with `cutAxis` >= 0 and its digits per level), found
/// below n's neighbours `around` (PlaneNeighbours): onEdge[0], [1] along u at v
/// = lo and hi, [2], [3] along v at u = lo and hi (polygonAround's order), each
/// ascending. Returns the edges (bit e for onEdge[e]) across which another
/// rank's part was met: what lies there, that rank knows.
template <typename Classify>
unsigned rectangleEdgeVertices(const HyperTreeAccess& grid, const WalkNode& n,
                               const PlaneNeighbours::Around& around, int u, int v, const Vec3& lo,
                               const Vec3& hi, int cutAxis, const std::vector<int>* cutDigits,
                               Classify&& classify, std::array<std::vector<double>, 4>& onEdge,
                               EdgeScratch& scratch)
{
  const int f = grid.branchFactor();
  const std::int64_t cells = grid.cellsPerRootAt(n.level);
  unsigned remote = 0;
  for (int e = 0; e < 4; ++e)
  {
    std::vector<double>& out = onEdge[static_cast<std::size_t>(e)];
    out.clear();
    const PlaneNeighbours::Neighbour& next = around[static_cast<std::size_t>(e)];
    if (!next.tree)
    {
      remote |= next.remote ? 1u << e : 0u;
      continue;
    }
    if (next.tree->isLeaf(next.node))
    {
      // No finer cell there; but a leaf may be another rank's part.
      if (grid.hasMask())
      {
        const vtkIdType global = next.tree->globalIndex(next.node);
        remote |= grid.isMasked(global) && grid.isAbsent(global) ? 1u << e : 0u;
      }
      continue;
    }
    const int across = e < 2 ? v : u; // the axis the edge is crossed along
    const int along = e < 2 ? u : v;
    const int side = e % 2; // 1: the edge at the node's upper bound
    EdgeCells edge;
    edge.along = along;
    edge.digit[static_cast<std::size_t>(across)] = side ? 0 : f - 1;
    if (cutAxis >= 0)
    {
      edge.digit[static_cast<std::size_t>(cutAxis)] = EdgeCells::Cut;
      edge.cutDigits = cutDigits;
    }
    Index3 at = n.ijk;
    at[static_cast<std::size_t>(across)] =
        (at[static_cast<std::size_t>(across)] + (side ? 1 : -1) + cells) % cells;
    if (!edgeVertices(grid, *next.tree, WalkNode{next.node, n.level, at}, n.level, at, edge,
                      lo[static_cast<std::size_t>(along)], hi[static_cast<std::size_t>(along)],
                      classify, false, out, scratch.stack))
    {
      remote |= 1u << e;
    }
  }
  return remote;
}

/// The points of a flat piece's polygon: its rectangle's corners in the order
/// given (corner k to corner k + 1 is an edge), each followed by the vertices on
/// the edge it starts. The rectangle lies in the plane of axes u and v and spans
/// lo to hi on them; values[0] and values[1] are the vertices on its edges along
/// u at v = lo and v = hi, values[2] and values[3] along v at u = lo and u = hi,
/// each ascending.
inline void polygonAround(const std::array<Vec3, 4>& corners, int u, int v, const Vec3& hi,
                          const std::array<const std::vector<double>*, 4>& values,
                          std::vector<Vec3>& out)
{
  out.clear();
  for (std::size_t k = 0; k < 4; ++k)
  {
    const Vec3& a = corners[k];
    const Vec3& b = corners[(k + 1) % 4];
    out.push_back(a);
    const int d = a[static_cast<std::size_t>(u)] != b[static_cast<std::size_t>(u)] ? u : v;
    const int w = d == u ? v : u;
    const std::vector<double>& on =
        *values[(d == v ? 2 : 0) +
                (a[static_cast<std::size_t>(w)] == hi[static_cast<std::size_t>(w)] ? 1 : 0)];
    Vec3 p = a;
    if (b[static_cast<std::size_t>(d)] > a[static_cast<std::size_t>(d)])
    {
      for (double x : on)
      {
        p[static_cast<std::size_t>(d)] = x;
        out.push_back(p);
      }
    }
    else
    {
      for (auto x = on.rbegin(); x != on.rend(); ++x)
      {
        p[static_cast<std::size_t>(d)] = *x;
        out.push_back(p);
      }
    }
  }
}

} // namespace canopy
