#include "LeafGeometry.h"

#include <cmath>

namespace canopy
{

LeafGeometry::LeafGeometry(const ForestDescription& forest) : Branch(forest.branchFactor)
{
  const RootGrid& grid = forest.rootGrid;
  Coordinates = {{grid.x, grid.y, grid.z}};
  const std::array<std::size_t, 3> points{{grid.pointsX, grid.pointsY, grid.pointsZ}};
  for (std::size_t a = 0; a < 3; ++a)
  {
    RootCells[a] = points[a] > 1 ? static_cast<std::int64_t>(points[a] - 1) : 1;
    Flat[a] = points[a] <= 1;
    if (points[a] > 1)
    {
      Axis[static_cast<std::size_t>(ActiveAxes++)] = static_cast<int>(a);
    }
  }
  for (int d = 0; d < ActiveAxes; ++d)
  {
    Children *= static_cast<std::size_t>(Branch);
    Scale[static_cast<std::size_t>(Axis[static_cast<std::size_t>(d)])] = Branch;
  }
  // Child c's digit along the a-th axis that is not flat: (c / Branch^a) % Branch.
  for (std::size_t c = 0; c < Children; ++c)
  {
    std::array<std::int64_t, 3> digits{{0, 0, 0}};
    std::size_t rest = c;
    for (int a = 0; a < ActiveAxes; ++a)
    {
      digits[static_cast<std::size_t>(Axis[static_cast<std::size_t>(a)])] =
          static_cast<std::int64_t>(rest % static_cast<std::size_t>(Branch));
      rest /= static_cast<std::size_t>(Branch);
    }
    ChildDigits.push_back(digits);
  }
  const int levels = forest.maxLevels > 0 ? forest.maxLevels : 1;
  LevelScale.resize(static_cast<std::size_t>(levels) + 1);
  for (std::size_t level = 0; level < LevelScale.size(); ++level)
  {
    LevelScale[level] = std::pow(static_cast<double>(Children), -static_cast<double>(level));
  }
  RootVolume.reserve(forest.trees.size());
  for (const TreeDescription& tree : forest.trees)
  {
    const std::int64_t root = tree.rootIndex;
    const std::array<std::int64_t, 3> at{{root % RootCells[0], (root / RootCells[0]) % RootCells[1],
                                          root / (RootCells[0] * RootCells[1])}};
    double volume = 1.0;
    for (int a = 0; a < ActiveAxes; ++a)
    {
      const auto axis = static_cast<std::size_t>(Axis[static_cast<std::size_t>(a)]);
      const double* x = Coordinates[axis];
      volume *= x[at[axis] + 1] - x[at[axis]];
    }
    RootVolume.push_back(volume);
  }
}

std::array<double, 3> LeafGeometry::centre(std::int64_t rootIndex, int level,
                                           const std::array<std::int64_t, 3>& index) const
{
  const std::array<std::int64_t, 3> at{{rootIndex % RootCells[0],
                                        (rootIndex / RootCells[0]) % RootCells[1],
                                        rootIndex / (RootCells[0] * RootCells[1])}};
  std::array<double, 3> centre{{0.0, 0.0, 0.0}};
  const double cellsPerAxis = std::pow(static_cast<double>(Branch), level); // rare: extremes
  for (std::size_t axis = 0; axis < 3; ++axis)
  {
    const double* x = Coordinates[axis];
    const double lower = x[at[axis]];
    if (Flat[axis])
    {
      centre[axis] = lower; // the plane's or the line's single coordinate
      continue;
    }
    const double width = x[at[axis] + 1] - lower;
    centre[axis] = lower + (static_cast<double>(index[axis]) + 0.5) * width / cellsPerAxis;
  }
  return centre;
}

} // namespace canopy
