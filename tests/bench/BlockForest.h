// A block forest as Athena++/Parthenon keep theirs, for the block-forest
// benchmark: a 3D root grid of trees (octrees), refined around a spherical front
// until a target number of blocks, each leaf a block of n^3 cells allocated on its
// own, [var][k][j][i] (variables outermost, i fastest), with ghost cells around
// the interior (filled with a sentinel Canopy must never read), doubles.
#pragma once

#include <canopy/ForestDescription.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <queue>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace canopy::bench
{

struct BlockForestOptions
{
  int rootsPerAxis = 4;  ///< root grid over [0, 1]^3
  int cellsPerSide = 16; ///< n: blocks of n^3 cells
  int ghostCells = 2;
  std::size_t targetBlocks = 244; ///< refined while that brings the block count nearer
  int maxLevel = 2;               ///< deepest block level (roots are level 0)
  /// The front: the sphere of this radius around the domain's centre. Nodes it
  /// crosses are refined first (coarsest first), then the nearest to it relative
  /// to their size.
  double frontRadius = 0.2;
};

class BlockForest
{
public:
  static constexpr int Variables = 2;
  /// Ghost cells hold this: a value read from one would show in every range.
  static constexpr double GhostSentinel = 1e30;

  struct Block
  {
    std::size_t tree = 0;
    int level = 0;
    std::array<double, 3> lo{{0, 0, 0}};
    double size = 0; ///< edge length (blocks are cubes)
  };

  explicit BlockForest(const BlockForestOptions& options) : Options(options)
  {
    const int r = options.rootsPerAxis;
    for (int i = 0; i <= r; ++i)
    {
      Coordinates.push_back(static_cast<double>(i) / r);
    }
    refine();
    allocate();
  }

  static const char* variableName(int v) { return v == 0 ? "density" : "energy"; }

  /// The forest for Canopy; with `cutaway`, every block inside the octant
  /// x, y, z > 0.5 is masked (the octant towards the benchmark's camera).
  canopy::ForestDescription description(bool cutaway = false) const
  {
    canopy::ForestDescription d;
    d.dimension = 3;
    d.branchFactor = 2;
    d.blockCellsPerSide = Options.cellsPerSide;
    const auto points = Coordinates.size();
    d.rootGrid = {
        Coordinates.data(), Coordinates.data(), Coordinates.data(), points, points, points};
    for (const Tree& tree : Trees)
    {
      canopy::TreeDescription t;
      t.rootIndex = tree.root;
      t.refinement = tree.refinement.data();
      t.numberOfNodes = tree.refinement.size();
      t.masked = cutaway ? tree.cutaway.data() : nullptr;
      d.trees.push_back(t);
    }
    const auto strides = canopy::BlockStrides::variableOutermost<double>(3, Options.cellsPerSide,
                                                                         Options.ghostCells);
    for (int v = 0; v < Variables; ++v)
    {
      d.fields.push_back(canopy::FieldDescription::blocks<double>(
          variableName(v), Tables[static_cast<std::size_t>(v)].data(), Blocks.size(), strides));
    }
    return d;
  }

  const std::vector<Block>& blocks() const { return Blocks; }
  int cellsPerSide() const { return Options.cellsPerSide; }
  int ghostCells() const { return Options.ghostCells; }
  int paddedSide() const { return Options.cellsPerSide + 2 * Options.ghostCells; }
  /// Interior cells of every block: what the simulation computes.
  std::size_t leafCells() const
  {
    const auto n = static_cast<std::size_t>(Options.cellsPerSide);
    return Blocks.size() * n * n * n;
  }
  /// Described nodes of every tree (refined nodes and blocks' roots).
  std::size_t describedNodes() const
  {
    std::size_t nodes = 0;
    for (const Tree& tree : Trees)
      nodes += tree.refinement.size();
    return nodes;
  }
  /// Blocks per level, coarsest first.
  std::vector<std::size_t> blocksPerLevel() const
  {
    std::vector<std::size_t> count(static_cast<std::size_t>(Options.maxLevel) + 1, 0);
    for (const Block& b : Blocks)
      ++count[static_cast<std::size_t>(b.level)];
    return count;
  }
  /// Variable v of block b: its (n + 2g)^3 array, ghosts included.
  const double* variable(std::size_t block, int v) const
  {
    return Tables[static_cast<std::size_t>(v)][block];
  }
  /// Interior cell (i, j, k) of variable v of block b.
  double interior(std::size_t block, int v, int i, int j, int k) const
  {
    const int p = paddedSide();
    const int g = Options.ghostCells;
    return variable(block, v)[(i + g) + static_cast<std::size_t>(p) *
                                            ((j + g) + static_cast<std::size_t>(p) * (k + g))];
  }
  /// Bytes the simulation allocated for its blocks.
  std::size_t blockBytes() const
  {
    const auto p = static_cast<std::size_t>(paddedSide());
    return Blocks.size() * Variables * p * p * p * sizeof(double);
  }
  const BlockForestOptions& options() const { return Options; }

private:
  struct Node
  {
    int level = 0;
    std::array<std::int64_t, 3> ijk{{0, 0, 0}}; ///< position among the tree's nodes of its level
    std::int64_t firstChild = -1;
  };
  struct Tree
  {
    std::int64_t root = 0;
    std::array<int, 3> rootIJK{{0, 0, 0}};
    std::vector<Node> nodes;              ///< creation order
    std::vector<std::uint8_t> refinement; ///< breadth-first
    std::vector<std::uint8_t> cutaway;    ///< breadth-first: blocks in the cut-away octant
  };

  double rootSize() const { return 1.0 / Options.rootsPerAxis; }

  void nodeBox(const Tree& tree, const Node& node, std::array<double, 3>& lo, double& size) const
  {
    size = rootSize() / static_cast<double>(std::int64_t(1) << node.level);
    for (int a = 0; a < 3; ++a)
    {
      lo[static_cast<std::size_t>(a)] =
          Coordinates[static_cast<std::size_t>(tree.rootIJK[static_cast<std::size_t>(a)])] +
          static_cast<double>(node.ijk[static_cast<std::size_t>(a)]) * size;
    }
  }

  /// Distance from a box to the front (0 when the front crosses it).
  double gapToFront(const std::array<double, 3>& lo, double size) const
  {
    double nearest = 0;
    double farthest = 0;
    for (int a = 0; a < 3; ++a)
    {
      const double l = lo[static_cast<std::size_t>(a)] - 0.5;
      const double h = l + size;
      const double n = l > 0 ? l : (h < 0 ? -h : 0.0);
      const double f = std::max(std::abs(l), std::abs(h));
      nearest += n * n;
      farthest += f * f;
    }
    nearest = std::sqrt(nearest);
    farthest = std::sqrt(farthest);
    const double r = Options.frontRadius;
    return r < nearest ? nearest - r : (r > farthest ? r - farthest : 0.0);
  }

  void refine()
  {
    const int r = Options.rootsPerAxis;
    for (int k = 0; k < r; ++k)
      for (int j = 0; j < r; ++j)
        for (int i = 0; i < r; ++i)
        {
          Tree tree;
          tree.root = i + static_cast<std::int64_t>(r) * (j + static_cast<std::int64_t>(r) * k);
          tree.rootIJK = {{i, j, k}};
          tree.nodes.push_back(Node{});
          Trees.push_back(std::move(tree));
        }
    // Greedy: (normalized gap, level, tree, node), smallest first.
    using Key = std::tuple<double, int, std::size_t, std::size_t>;
    std::priority_queue<Key, std::vector<Key>, std::greater<Key>> candidates;
    auto consider = [&](std::size_t t, std::size_t n)
    {
      const Node& node = Trees[t].nodes[n];
      if (node.level >= Options.maxLevel)
        return;
      std::array<double, 3> lo;
      double size = 0;
      nodeBox(Trees[t], node, lo, size);
      candidates.emplace(gapToFront(lo, size) / size, node.level, t, n);
    };
    for (std::size_t t = 0; t < Trees.size(); ++t)
      consider(t, 0);
    std::size_t leaves = Trees.size();
    auto off = [&](std::size_t count)
    {
      return count > Options.targetBlocks ? count - Options.targetBlocks
                                          : Options.targetBlocks - count;
    };
    while (!candidates.empty() && off(leaves + 7) < off(leaves))
    {
      const auto [gap, level, t, n] = candidates.top();
      candidates.pop();
      Tree& tree = Trees[t];
      tree.nodes[n].firstChild = static_cast<std::int64_t>(tree.nodes.size());
      const Node parent = tree.nodes[n];
      for (int c = 0; c < 8; ++c)
      {
        Node child;
        child.level = parent.level + 1;
        for (int a = 0; a < 3; ++a)
          child.ijk[static_cast<std::size_t>(a)] =
              2 * parent.ijk[static_cast<std::size_t>(a)] + ((c >> a) & 1);
        tree.nodes.push_back(child);
      }
      for (int c = 0; c < 8; ++c)
        consider(t,
                 static_cast<std::size_t>(tree.nodes[n].firstChild) + static_cast<std::size_t>(c));
      leaves += 7;
    }
    // Breadth-first descriptions; blocks are the leaves breadth-first, tree by tree
    // (Canopy's default block order).
    for (std::size_t t = 0; t < Trees.size(); ++t)
    {
      Tree& tree = Trees[t];
      std::deque<std::size_t> queue{0};
      while (!queue.empty())
      {
        const Node& node = tree.nodes[queue.front()];
        queue.pop_front();
        const bool refined = node.firstChild >= 0;
        tree.refinement.push_back(refined ? 1 : 0);
        std::array<double, 3> lo;
        double size = 0;
        nodeBox(tree, node, lo, size);
        const bool inOctant = lo[0] >= 0.5 && lo[1] >= 0.5 && lo[2] >= 0.5;
        tree.cutaway.push_back(!refined && inOctant ? 1 : 0);
        if (refined)
        {
          for (int c = 0; c < 8; ++c)
            queue.push_back(static_cast<std::size_t>(node.firstChild) +
                            static_cast<std::size_t>(c));
          continue;
        }
        Blocks.push_back(Block{t, node.level, lo, size});
      }
    }
  }

  /// Density: 1 away from the front, up to 4 on it; energy: 2.5 density + x.
  double value(int v, double x, double y, double z) const
  {
    const double d =
        std::sqrt((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) + (z - 0.5) * (z - 0.5));
    const double w = (d - Options.frontRadius) / 0.03;
    const double density = 1.0 + 3.0 * std::exp(-w * w);
    return v == 0 ? density : 2.5 * density + x;
  }

  void allocate()
  {
    const int n = Options.cellsPerSide;
    const int g = Options.ghostCells;
    const int p = paddedSide();
    const std::size_t perVariable = static_cast<std::size_t>(p) * p * p;
    for (auto& table : Tables)
      table.reserve(Blocks.size());
    for (const Block& b : Blocks)
    {
      // One allocation per block (as Athena++'s MeshBlock), variables outermost.
      Memory.emplace_back(new double[Variables * perVariable]);
      double* data = Memory.back().get();
      const double h = b.size / n;
      for (int v = 0; v < Variables; ++v)
      {
        double* var = data + v * perVariable;
        Tables[static_cast<std::size_t>(v)].push_back(var);
        for (int k = 0; k < p; ++k)
          for (int j = 0; j < p; ++j)
            for (int i = 0; i < p; ++i)
            {
              const bool ghost = i < g || j < g || k < g || i >= n + g || j >= n + g || k >= n + g;
              var[i + static_cast<std::size_t>(p) * (j + static_cast<std::size_t>(p) * k)] =
                  ghost ? GhostSentinel
                        : value(v, b.lo[0] + (i - g + 0.5) * h, b.lo[1] + (j - g + 0.5) * h,
                                b.lo[2] + (k - g + 0.5) * h);
            }
      }
    }
  }

  BlockForestOptions Options;
  std::vector<double> Coordinates;
  std::vector<Tree> Trees;
  std::vector<Block> Blocks;
  std::vector<std::unique_ptr<double[]>> Memory;
  std::array<std::vector<const double*>, Variables> Tables;
};

} // namespace canopy::bench
