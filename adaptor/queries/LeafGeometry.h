// Where a forest's leaves are and how large, from the root grid alone: the volume
// of a leaf at a level of a tree, a child's integer position from its parent's,
// and a leaf's centre. What queries need without building a grid.
#pragma once

#include <canopy/ForestDescription.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace canopy
{

class LeafGeometry
{
public:
  /// Reads `forest`'s root grid and trees' roots now; keeps no pointer into it.
  explicit LeafGeometry(const ForestDescription& forest);

  std::size_t children() const { return Children; }

  /// Volume (area in 2D, length in 1D) of a leaf at `level` of the t-th tree.
  double volume(std::size_t tree, int level) const
  {
    return RootVolume[tree] * LevelScale[static_cast<std::size_t>(level)];
  }

  /// Position along x, y, z of child `child` (x fastest over the forest's axes that
  /// are not flat) of the node at `parent`, one level down.
  std::array<std::int64_t, 3> childIndex(const std::array<std::int64_t, 3>& parent,
                                         std::size_t child) const
  {
    const std::array<std::int64_t, 3>& digit = ChildDigits[child];
    return {{parent[0] * Scale[0] + digit[0], parent[1] * Scale[1] + digit[1],
             parent[2] * Scale[2] + digit[2]}};
  }

  /// Centre of the leaf at `level`, position `index`, in the root cell `rootIndex`.
  std::array<double, 3> centre(std::int64_t rootIndex, int level,
                               const std::array<std::int64_t, 3>& index) const;

private:
  std::array<const double*, 3> Coordinates{{nullptr, nullptr, nullptr}};
  std::array<std::int64_t, 3> RootCells{{1, 1, 1}};
  std::array<bool, 3> Flat{{true, true, true}};
  std::array<int, 3> Axis{{0, 1, 2}}; ///< the axes that are not flat, in order
  int ActiveAxes = 0;
  std::int64_t Branch = 2;
  std::size_t Children = 1;
  std::vector<std::array<std::int64_t, 3>> ChildDigits; ///< per child: its digit per axis
  std::array<std::int64_t, 3> Scale{{1, 1, 1}};         ///< branchFactor, 1 on flat axes
  std::vector<double> RootVolume;                       ///< per tree of the description
  std::vector<double> LevelScale;                       ///< children^-level
};

} // namespace canopy
