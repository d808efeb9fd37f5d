// A forest whose trees a test changes one by one, as an AMR code does between
// steps: a tree re-refined at random, a mask bit toggled; described anew with
// fresh field memory each time (a node field "value" and a leaves-only
// "leafValue"), with a slot map that is not breadth-first when asked.
#pragma once

#include <canopy/ForestDescription.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

namespace canopy::testing
{

/// A forest whose trees the test changes one by one, as an AMR code does.
class ChangingForest
{
public:
  /// `trees` trees on the first root cells of the smallest square or cube of
  /// root cells that holds them (side 0.5, offset 0.1 per axis).
  ChangingForest(int dimension, int trees, bool slots, std::uint64_t seed)
      : Dimension(dimension), Random(seed), UseSlots(slots)
  {
    Children = dimension == 3 ? 8 : 4;
    int side = 1;
    while (std::pow(side, dimension) < trees)
    {
      ++side;
    }
    for (int a = 0; a < 3; ++a)
    {
      const int points = a < dimension ? side + 1 : 1;
      for (int i = 0; i < points; ++i)
        Coordinates[a].push_back(0.5 * i + 0.1 * a);
    }
    Trees.resize(static_cast<std::size_t>(trees));
    for (std::size_t t = 0; t < Trees.size(); ++t)
    {
      Trees[t].root = static_cast<std::int64_t>(t);
      refine(t);
    }
  }

  /// New random refinement (and mask) for tree t.
  void refine(std::size_t t)
  {
    std::uniform_real_distribution<double> unit(0, 1);
    Tree& tree = Trees[t];
    tree.refinement.assign(1, 0);
    std::vector<int> level{0};
    for (std::size_t n = 0; n < tree.refinement.size(); ++n)
    {
      if (level[n] < 3 && unit(Random) < 0.5)
      {
        tree.refinement[n] = 1;
        for (int c = 0; c < Children; ++c)
        {
          tree.refinement.push_back(0);
          level.push_back(level[n] + 1);
        }
      }
    }
    tree.masked.assign(tree.refinement.size(), 0);
    for (std::size_t n = 1; n < tree.masked.size(); ++n)
      tree.masked[n] = unit(Random) < 0.1;
  }

  /// Moves every root coordinate by `d` (a mesh that moves, same topology).
  void shiftCoordinates(double d)
  {
    for (auto& axis : Coordinates)
      for (double& x : axis)
        x += d;
  }

  void toggleMask(std::size_t t)
  {
    auto& masked = Trees[t].masked;
    masked[masked.size() / 2] ^= 1;
  }

  /// The description, slots depth-first per tree when asked, values fresh in new memory.
  ForestDescription describe(double valueOffset)
  {
    ForestDescription d;
    d.dimension = Dimension;
    d.maxLevels = 4;
    d.rootGrid = {Coordinates[0].data(), Coordinates[1].data(), Coordinates[2].data(),
                  Coordinates[0].size(), Coordinates[1].size(), Coordinates[2].size()};
    std::size_t total = 0;
    std::size_t leaves = 0;
    for (auto& tree : Trees)
    {
      tree.slots.resize(tree.refinement.size());
      for (std::size_t n = 0; n < tree.slots.size(); ++n)
      {
        // Reversed within the tree: a slot map that is not breadth-first.
        tree.slots[n] = static_cast<std::int64_t>(total + tree.slots.size() - 1 - n);
      }
      total += tree.refinement.size();
      for (auto r : tree.refinement)
        leaves += r == 0;
      d.trees.push_back({tree.root, tree.refinement.data(), tree.refinement.size(),
                         tree.masked.data(), UseSlots ? tree.slots.data() : nullptr, nullptr});
    }
    // New memory each time: the builder must wrap the fields anew.
    Values = std::make_unique<std::vector<double>>(total);
    LeafValues = std::make_unique<std::vector<double>>(leaves);
    for (std::size_t i = 0; i < total; ++i)
      (*Values)[i] = valueOffset + 0.5 * static_cast<double>(i);
    for (std::size_t i = 0; i < leaves; ++i)
      (*LeafValues)[i] = valueOffset - static_cast<double>(i);
    d.fields.push_back(FieldDescription::aos("value", Values->data(), total));
    d.fields.push_back(
        FieldDescription::aos("leafValue", LeafValues->data(), leaves, 1, Centering::LeavesOnly));
    return d;
  }

  std::size_t size() const { return Trees.size(); }
  std::size_t numberOfNodes(std::size_t t) const { return Trees[t].refinement.size(); }

private:
  struct Tree
  {
    std::int64_t root;
    std::vector<std::uint8_t> refinement;
    std::vector<std::uint8_t> masked;
    std::vector<std::int64_t> slots;
  };
  int Dimension;
  int Children;
  std::mt19937_64 Random;
  bool UseSlots;
  std::array<std::vector<double>, 3> Coordinates;
  std::vector<Tree> Trees;
  std::unique_ptr<std::vector<double>> Values;
  std::unique_ptr<std::vector<double>> LeafValues;
};

} // namespace canopy::testing
