// A 3D forest whose neighbouring root cells are refined to different depths, so
// that coarse cells meet finer ones (T-junctions) with a chosen level jump: the
// root cells alternate, like a checkerboard, between trees refined uniformly to
// `coarse` and to `fine` levels. Irregular root coordinates (not dyadic) also
// exercise where trees meet. Owns everything its description borrows.
#pragma once

#include <canopy/ForestDescription.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace canopy::testing
{

class LevelJumpForest
{
public:
  /// `roots`: root cells per axis; `coarse`, `fine`: the depth of alternate
  /// trees (levels below the root); `dyadic`: root cells of side 1 at integer
  /// coordinates, else sides between 0.7 and 1.3 that no binary fraction gives.
  LevelJumpForest(std::array<int, 3> roots, int coarse, int fine, bool dyadic)
  {
    for (int a = 0; a < 3; ++a)
    {
      double x = 0;
      Coordinates[a].push_back(x);
      for (int i = 0; i < roots[a]; ++i)
      {
        x += dyadic ? 1.0 : 0.7 + 0.6 * ((i * 7 + a * 3) % 10) / 9.0 + 1e-3 / 3.0;
        Coordinates[a].push_back(x);
      }
    }
    Description.dimension = 3;
    Description.branchFactor = 2;
    Description.maxLevels = std::max(coarse, fine) + 1;
    Description.rootGrid = {Coordinates[0].data(), Coordinates[1].data(), Coordinates[2].data(),
                            Coordinates[0].size(), Coordinates[1].size(), Coordinates[2].size()};
    for (int k = 0; k < roots[2]; ++k)
      for (int j = 0; j < roots[1]; ++j)
        for (int i = 0; i < roots[0]; ++i)
        {
          const int depth = (i + j + k) % 2 ? fine : coarse;
          std::vector<std::uint8_t> bits;
          std::size_t atLevel = 1;
          for (int level = 0; level <= depth; ++level)
          {
            bits.insert(bits.end(), atLevel, level < depth ? 1 : 0);
            atLevel *= 8;
          }
          Refinement.push_back(std::move(bits));
          TreeDescription tree;
          tree.rootIndex = i + roots[0] * (j + roots[1] * k);
          Description.trees.push_back(tree);
        }
    for (std::size_t t = 0; t < Description.trees.size(); ++t)
    {
      Description.trees[t].refinement = Refinement[t].data();
      Description.trees[t].numberOfNodes = Refinement[t].size();
    }
  }
  LevelJumpForest(const LevelJumpForest&) = delete;
  LevelJumpForest& operator=(const LevelJumpForest&) = delete;

  const ForestDescription& description() const { return Description; }
  /// The domain's bounds: xmin, xmax, ymin, ymax, zmin, zmax.
  std::array<double, 6> bounds() const
  {
    return {{Coordinates[0].front(), Coordinates[0].back(), Coordinates[1].front(),
             Coordinates[1].back(), Coordinates[2].front(), Coordinates[2].back()}};
  }

private:
  std::array<std::vector<double>, 3> Coordinates;
  std::vector<std::vector<std::uint8_t>> Refinement;
  ForestDescription Description;
};

} // namespace canopy::testing
