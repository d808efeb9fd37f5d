#include "DualTraversal.h"

#include <stdexcept>

namespace canopy
{

DualTraversal::DualTraversal(const HyperTreeAccess& grid, int maximumLevel, const ViewVolume* view,
                             bool levelOfDetail, double pixelThreshold)
    : Grid(grid), MaximumLevel(maximumLevel), View(view), LevelOfDetail(levelOfDetail),
      PixelThreshold(pixelThreshold)
{
  D = static_cast<int>(grid.activeAxes().size());
  F = grid.branchFactor();
  if (D < 2 || D > 3)
  {
    throw std::invalid_argument("contours need a 2D or 3D grid");
  }
  if (F < 2 || F > 3)
  {
    throw std::invalid_argument("contours need a branch factor of 2 or 3");
  }
  Tasks = 1;
  for (int i = 0; i < D; ++i)
  {
    const std::size_t ui = static_cast<std::size_t>(i);
    Axes[ui] = grid.activeAxes()[ui];
    Roots[ui] = static_cast<long>(grid.rootCells()[static_cast<std::size_t>(Axes[ui])]);
    Tasks *= Roots[ui] + 1;
  }
}

DualNode DualTraversal::root(const std::array<long, 3>& p) const
{
  DualNode n{};
  unsigned char outside = 0;
  std::array<long, 3> ijk{{0, 0, 0}};
  for (int i = 0; i < D; ++i)
  {
    const std::size_t ui = static_cast<std::size_t>(i);
    if (p[ui] < 0)
    {
      outside |= static_cast<unsigned char>(1u << (2 * i));
    }
    else if (p[ui] >= Roots[ui])
    {
      outside |= static_cast<unsigned char>(2u << (2 * i));
    }
    ijk[static_cast<std::size_t>(Axes[ui])] = p[ui];
  }
  if (outside != 0)
  {
    n.kind = DualNode::Outside;
    n.outside = outside;
    return n;
  }
  const TreeAccess* tree = Grid.treeAt(ijk[0], ijk[1], ijk[2]);
  if (tree == nullptr)
  {
    n.kind = DualNode::Hidden;
    if (Grid.treeElsewhere(ijk[0], ijk[1], ijk[2]))
    {
      // Another rank's tree: its ghosts, if it sent any.
      n.remote = 1;
      const std::array<unsigned int, 3> at{{static_cast<unsigned int>(ijk[0]),
                                            static_cast<unsigned int>(ijk[1]),
                                            static_cast<unsigned int>(ijk[2])}};
      if (const TreeAccess* stand = Ghosts ? Ghosts->elsewhere(at) : nullptr)
      {
        classifyGhost(n, *stand, 0, {{0, 0, 0}});
      }
    }
    return n;
  }
  classify(n, *tree, 0, 0, {{0, 0, 0}});
  return n;
}

} // namespace canopy
