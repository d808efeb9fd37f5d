// A forest whose average colours are known in closed form: one root, uniformly
// refined, leaves in a checkerboard of 0 and 1. Any square of whole leaf pairs
// (and any pixel much larger than a leaf) averages the two mapped colours.
#pragma once

#include <canopy/ForestDescription.h>

#include <array>
#include <cstdint>
#include <vector>

namespace canopy::testing
{

/// A uniformly refined single-root forest (2D or 3D, binary) with every node's
/// value: leaves in a checkerboard of 0 and 1 (by the sum of their integer
/// position), coarse nodes the average (0.5), as a simulation's restriction gives.
struct CheckerboardForest
{
  std::vector<std::uint8_t> refinement;
  std::vector<double> values;
  std::vector<double> unitAxis{0.0, 1.0};
  std::vector<double> flat{0.0};
  ForestDescription forest;

  CheckerboardForest(const CheckerboardForest&) = delete; // the description points inside
  CheckerboardForest& operator=(const CheckerboardForest&) = delete;

  /// `levels` refinements of the unit square (cube): 2^levels leaves per axis.
  CheckerboardForest(int dimension, int levels)
  {
    forest.dimension = dimension;
    forest.branchFactor = 2;
    forest.maxLevels = levels + 1;
    forest.rootGrid = {unitAxis.data(),
                       unitAxis.data(),
                       dimension == 3 ? unitAxis.data() : flat.data(),
                       2,
                       2,
                       static_cast<std::size_t>(dimension == 3 ? 2 : 1)};
    // Breadth-first: level by level, children in VTK's order (x fastest).
    std::vector<std::array<long, 3>> level{{{0, 0, 0}}};
    const int children = 1 << dimension;
    for (int l = 0; l <= levels; ++l)
    {
      std::vector<std::array<long, 3>> next;
      for (const auto& ijk : level)
      {
        refinement.push_back(l < levels ? 1 : 0);
        values.push_back(l < levels ? 0.5 : static_cast<double>((ijk[0] + ijk[1] + ijk[2]) % 2));
        for (int c = 0; l < levels && c < children; ++c)
        {
          next.push_back({{2 * ijk[0] + (c & 1), 2 * ijk[1] + ((c >> 1) & 1),
                           dimension == 3 ? 2 * ijk[2] + ((c >> 2) & 1) : 0}});
        }
      }
      level = next;
    }
    forest.trees.push_back({0, refinement.data(), refinement.size()});
    forest.fields.push_back(FieldDescription::aos("value", values.data(), values.size()));
  }
};

} // namespace canopy::testing
