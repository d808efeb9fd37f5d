#include "SolidNeighbours.h"

namespace canopy
{

SolidNeighbours::Neighbour SolidNeighbours::rootAt(const HyperTreeAccess& grid, long i, long j,
                                                   long k)
{
  if (const TreeAccess* tree = grid.treeAt(i, j, k))
  {
    return nodeAt(grid, *tree, 0);
  }
  return {grid.treeElsewhere(i, j, k) ? Neighbour::Kind::Elsewhere : Neighbour::Kind::Border,
          nullptr, 0};
}

SolidNeighbours::SolidNeighbours(const HyperTreeAccess& grid, const TreeAccess& tree)
    : Grid(grid), Tree(tree), Levels(static_cast<std::size_t>(deepestLevel(grid, tree)) + 1)
{
  vtkIdType weight = 1;
  for (int a : grid.activeAxes())
  {
    Weight[static_cast<std::size_t>(a)] = weight;
    weight *= grid.branchFactor();
  }
}

void SolidNeighbours::enter(const WalkNode& n)
{
  if (static_cast<std::size_t>(n.level) >= Levels.size())
  {
    Levels.resize(static_cast<std::size_t>(n.level) + 1); // deeper than its tree said
  }
  Level& here = Levels[static_cast<std::size_t>(n.level)];
  here.node = n.node;
  here.ijk = n.ijk;
  const int f = Grid.branchFactor();
  for (std::size_t a = 0; a < 3; ++a)
  {
    here.digit[a] = static_cast<int>(f == 2 ? n.ijk[a] & 1 : n.ijk[a] % f);
  }
  here.known = 0;
  here.coverKnown = 0;
  here.covered = 0;
}

Index3 SolidNeighbours::positionAt(int level, const Direction& d) const
{
  const Level& here = Levels[static_cast<std::size_t>(level)];
  const std::int64_t cells = Grid.cellsPerRootAt(level);
  Index3 p;
  for (std::size_t a = 0; a < 3; ++a)
  {
    // Across the root's bounds, the next root's first or last cell.
    p[a] = here.ijk[a] + d[a];
    p[a] = p[a] < 0 ? cells - 1 : p[a] >= cells ? 0 : p[a];
  }
  return p;
}

const SolidNeighbours::Neighbour& SolidNeighbours::find(Level& here, int level, const Direction& d,
                                                        int k)
{
  Neighbour& out = here.around[static_cast<std::size_t>(k)];
  here.known |= 1u << k;
  if (level == 0)
  {
    out = rootAt(Grid, static_cast<long>(Tree.rootIJK[0]) + d[0],
                 static_cast<long>(Tree.rootIJK[1]) + d[1],
                 static_cast<long>(Tree.rootIJK[2]) + d[2]);
    return out;
  }
  // Per axis: where the step leaves the parent (up), and the child digit there.
  const int f = Grid.branchFactor();
  Direction up{{0, 0, 0}};
  vtkIdType child = 0;
  bool sibling = true;
  for (std::size_t a = 0; a < 3; ++a)
  {
    int digit = here.digit[a] + d[a];
    if (digit < 0 || digit >= f)
    {
      up[a] = d[a];
      digit -= d[a] * f;
      sibling = false;
    }
    child += digit * Weight[a];
  }
  if (sibling)
  {
    out = nodeAt(Grid, Tree,
                 Tree.firstChild(Levels[static_cast<std::size_t>(level) - 1].node) + child);
    return out;
  }
  out = childOf(Grid, at(level - 1, up), static_cast<int>(child));
  return out;
}

} // namespace canopy
