// Validation of a ForestDescription, and the per-tree layout it establishes.
//
// Everything a build needs to know about the shape of the forest is computed
// here once, so the builder never re-walks the refinement bytes to find sizes,
// and nothing is built from a description that is wrong anywhere.
#pragma once

#include <canopy/ForestDescription.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace canopy
{

/// Thrown when a ForestDescription is malformed. what() lists every problem
/// found, one per line, each naming the tree or field concerned.
class InvalidForest : public std::invalid_argument
{
public:
  explicit InvalidForest(std::vector<std::string> problems);
  const std::vector<std::string>& problems() const { return Problems; }

private:
  std::vector<std::string> Problems;
};

/// What a valid description holds, for sizing the simulation's arrays and for
/// information. (The builder's own per-tree layout is internal: ForestLayout.h.)
struct ForestCounts
{
  std::size_t totalNodes = 0;         ///< every described node
  std::size_t totalCells = 0;         ///< cells of the grid: totalNodes, or with blocks' cells
  std::size_t numberOfBlocks = 0;     ///< block forests: present leaves, each a block
  std::size_t totalLeaves = 0;        ///< every described leaf, absent ones included
  std::size_t totalPresentNodes = 0;  ///< tuples an every-node field holds
  std::size_t totalPresentLeaves = 0; ///< tuples a leaves-only field holds
  std::size_t numberOfRootCells = 0;  ///< root cells of the root grid
  bool anyMask = false;               ///< some tree has a mask
  bool anyAbsent = false;             ///< some node is absent (another rank's part)
};

/// Validates the whole description; throws InvalidForest listing the problems.
/// Checks run in stages (forest parameters, root grid, trees, fields); every
/// problem of the first failing stage is listed. Cost: one pass over the
/// refinement bytes (and over the slot maps, if given). The description is
/// only read; nothing is kept.
ForestCounts validateForest(const ForestDescription& forest);

/// The deepest trees Canopy builds and its filters walk, as a number of levels (the
/// root level included): integer node positions must fit in 64 bits with room to
/// spare (branchFactor^(levels-1) <= 2^61): 62 levels for binary trees, 39 for
/// ternary ones. validateForest refuses a maxLevels above it.
constexpr int maxSupportedLevels(int branchFactor)
{
  int levels = 1;
  for (long long cells = 1; cells <= (1LL << 61) / branchFactor; cells *= branchFactor)
  {
    ++levels;
  }
  return levels;
}

} // namespace canopy
