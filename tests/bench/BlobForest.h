// A blob for the contour benchmarks: the unit cube, 16^3 roots, the field a
// smoothed indicator of a ball, f = (1 + tanh((R - r) / w)) / 2 at each node's
// centre (every node, coarse ones too), r the distance to the cube's centre,
// R = 0.15, w a multiple of the band's node edge h. Nodes within a few w (plus
// their half diagonal) of the sphere r = R are refined to the band level: the
// blob's surface, at one resolution. Every other node is refined to the
// background level (at most the band's), where f is within 4e-4 of 0 or 1, so
// the contour at 0.5 does not depend on the background.
//
// The simulation's side: refinement bytes per tree and one double per node,
// breadth-first, trees back to back (no slot map), read in place.
#pragma once

#include <canopy/ForestDescription.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace canopy::bench
{

struct BlobForestOptions
{
  int bandLevel = 5;
  int backgroundLevel = 2;
  double widthInBandEdges = 1.25; ///< w / h
  double bandHalfWidthInWidths = 4.0;
};

class BlobForest
{
public:
  static constexpr int Roots = 16;
  static constexpr double Radius = 0.15;
  static constexpr double RootEdge = 1.0 / Roots;

  explicit BlobForest(const BlobForestOptions& options)
      : Options(options),
        Width(options.widthInBandEdges * RootEdge / static_cast<double>(1 << options.bandLevel))
  {
    for (int i = 0; i <= Roots; ++i)
    {
      Axis.push_back(i * RootEdge);
    }
    Description.dimension = 3;
    Description.branchFactor = 2;
    Description.maxLevels = options.bandLevel + 1;
    Description.rootGrid = {Axis.data(), Axis.data(), Axis.data(),
                            Axis.size(), Axis.size(), Axis.size()};
    Refinement.resize(static_cast<std::size_t>(Roots * Roots * Roots));
    for (int root = 0; root < Roots * Roots * Roots; ++root)
    {
      describeTree(root);
    }
    for (std::size_t root = 0; root < Refinement.size(); ++root)
    {
      TreeDescription tree;
      tree.rootIndex = static_cast<std::int64_t>(root);
      tree.refinement = Refinement[root].data();
      tree.numberOfNodes = Refinement[root].size();
      Description.trees.push_back(tree);
    }
    Description.fields.push_back(FieldDescription::aos("f", Values.data(), Values.size()));
  }
  BlobForest(const BlobForest&) = delete;
  BlobForest& operator=(const BlobForest&) = delete;

  const ForestDescription& description() const { return Description; }
  std::size_t leaves() const { return Leaves; }
  double field(double x, double y, double z) const
  {
    return 0.5 * (1.0 + std::tanh((Radius - distance(x, y, z)) / Width));
  }

private:
  struct Node
  {
    int level;
    std::array<std::int64_t, 3> index; ///< at its level, within the whole domain
  };

  static double distance(double x, double y, double z)
  {
    return std::sqrt((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) + (z - 0.5) * (z - 0.5));
  }

  void describeTree(int root)
  {
    std::vector<std::uint8_t>& refinement = Refinement[static_cast<std::size_t>(root)];
    std::vector<Node> level{{0, {root % Roots, (root / Roots) % Roots, root / (Roots * Roots)}}};
    std::vector<Node> next;
    const double bandHalfWidth = Options.bandHalfWidthInWidths * Width;
    const int background = std::min(Options.backgroundLevel, Options.bandLevel);
    while (!level.empty())
    {
      next.clear();
      for (const Node& node : level)
      {
        const double edge = RootEdge / static_cast<double>(std::int64_t{1} << node.level);
        const double c[3] = {(node.index[0] + 0.5) * edge, (node.index[1] + 0.5) * edge,
                             (node.index[2] + 0.5) * edge};
        Values.push_back(field(c[0], c[1], c[2]));
        const bool inBand = std::abs(distance(c[0], c[1], c[2]) - Radius) <=
                            bandHalfWidth + 0.5 * std::sqrt(3.0) * edge;
        const bool refine = node.level < (inBand ? Options.bandLevel : background);
        refinement.push_back(refine ? 1 : 0);
        if (!refine)
        {
          ++Leaves;
          continue;
        }
        for (int k = 0; k < 2; ++k)
          for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i)
              next.push_back(
                  {node.level + 1,
                   {2 * node.index[0] + i, 2 * node.index[1] + j, 2 * node.index[2] + k}});
      }
      level.swap(next);
    }
  }

  BlobForestOptions Options;
  double Width;
  std::vector<double> Axis;
  std::vector<std::vector<std::uint8_t>> Refinement;
  std::vector<double> Values;
  std::size_t Leaves = 0;
  ForestDescription Description;
};

} // namespace canopy::bench
