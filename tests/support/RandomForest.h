// A reproducible random forest that owns its arrays: the shape of an AMR
// simulation's data, for tests and benchmarks.
#pragma once

#include <canopy/ForestDescription.h>

#include <array>
#include <cstdint>
#include <vector>

namespace canopy::testing
{

/// How the simulation stores its nodes.
enum class StorageOrder
{
  BreadthFirst, ///< Canopy's default: trees back to back, each breadth-first (no slot map)
  DepthFirst    ///< pre-order within each tree, trees back to back (slot map given)
};

struct RandomForestOptions
{
  int dimension = 3;
  int branchFactor = 2;
  std::array<std::size_t, 3> rootCells{{2, 2, 2}}; ///< flat axes (2D, 1D) are ignored
  int flatAxis = 2;                                ///< 2D only: the axis with a single point
  int activeAxis = 0; ///< 1D only: the axis of the line (the two others have a single point)
  int maxLevels = 4;
  double refineProbability = 0.5;
  double maskProbability = 0.0; ///< 0: no mask arrays at all
  std::uint64_t seed = 1;
  StorageOrder order = StorageOrder::BreadthFirst;
  std::array<double, 3> origin{{0, 0, 0}};
  bool skipEveryOtherRoot = false; ///< leave holes in the root grid (trees not given)
};

/// A forest with root coordinates that are deliberately non-uniform.
class RandomForest
{
public:
  explicit RandomForest(const RandomForestOptions& options);
  RandomForest(const RandomForest&) = delete;
  RandomForest& operator=(const RandomForest&) = delete;

  /// The description (no fields yet; tests add their own).
  ForestDescription& description() { return Description; }
  const ForestDescription& description() const { return Description; }

  std::size_t numberOfNodes() const { return TotalNodes; }
  std::size_t numberOfLeaves() const { return TotalLeaves; }
  std::size_t childrenPerNode() const { return Children; }

  /// Per tree, per breadth-first node: storage slot, level, parent (-1 for root),
  /// child position within the parent.
  struct Node
  {
    std::int64_t slot;
    int level;
    std::int64_t parent;
    int childIndex;
  };
  const std::vector<std::vector<Node>>& nodes() const { return Nodes; }
  /// The node's cell in a grid Canopy builds: breadth-first, tree by tree (docs/api.md).
  std::int64_t cellOf(std::size_t tree, std::size_t node) const
  {
    return FirstCell[tree] + static_cast<std::int64_t>(node);
  }
  const std::vector<std::vector<std::uint8_t>>& refinement() const { return Refinement; }
  const std::vector<std::vector<std::uint8_t>>& masked() const { return Masked; }
  const std::array<std::vector<double>, 3>& coordinates() const { return Coordinates; }

private:
  std::array<std::vector<double>, 3> Coordinates;
  std::vector<std::vector<std::uint8_t>> Refinement;
  std::vector<std::vector<std::uint8_t>> Masked;
  std::vector<std::vector<std::int64_t>> Slots;
  std::vector<std::vector<Node>> Nodes;
  std::vector<std::int64_t> FirstCell;
  std::size_t TotalNodes = 0;
  std::size_t TotalLeaves = 0;
  std::size_t Children = 0;
  ForestDescription Description;
};

/// FNV-1a over raw bytes: proves a buffer was not written.
std::uint64_t checksum(const void* data, std::size_t bytes);

} // namespace canopy::testing
