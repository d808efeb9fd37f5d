#include "BlockForest.h"

#include "PartitionedForest.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>

namespace canopy::testing
{
namespace
{

/// Per tree of `forest`, per breadth-first node: the leaf's place in the forest's
/// Morton order (depth-first, children in order, trees in order), -1 for refined nodes.
std::vector<std::vector<std::int64_t>> mortonLeafIds(const ForestDescription& forest,
                                                     std::size_t children)
{
  std::vector<std::vector<std::int64_t>> ids;
  std::int64_t next = 0;
  for (const TreeDescription& tree : forest.trees)
  {
    std::vector<std::size_t> firstChild(tree.numberOfNodes, 0);
    for (std::size_t n = 0, c = 1; n < tree.numberOfNodes; ++n)
    {
      if (tree.refinement[n])
      {
        firstChild[n] = c;
        c += children;
      }
    }
    std::vector<std::int64_t> id(tree.numberOfNodes, -1);
    std::vector<std::size_t> stack{0};
    while (!stack.empty())
    {
      const std::size_t n = stack.back();
      stack.pop_back();
      if (!tree.refinement[n])
      {
        id[n] = next++;
        continue;
      }
      for (std::size_t c = children; c-- > 0;)
      {
        stack.push_back(firstChild[n] + c);
      }
    }
    ids.push_back(std::move(id));
  }
  return ids;
}

void store(unsigned char* at, double value, bool single)
{
  if (single)
  {
    const auto v = static_cast<float>(value);
    std::memcpy(at, &v, sizeof v);
  }
  else
  {
    std::memcpy(at, &value, sizeof value);
  }
}

} // namespace

double BlockForest::value(std::int64_t id, const std::array<int, 3>& cell, int cellsPerSide,
                          int component)
{
  const int n = cellsPerSide;
  return static_cast<double>(id % 1024) * 16384.0 +
         static_cast<double>(((cell[2] * n + cell[1]) * n + cell[0]) * 4 + component);
}

BlockForest::BlockForest(const BlockForestOptions& options) : Options(options)
{
  Whole = std::make_unique<RandomForest>(options.shape);
  const ForestDescription& whole = Whole->description();
  const std::size_t children = Whole->childrenPerNode();
  const auto ids = mortonLeafIds(whole, children);

  std::vector<std::size_t> wholeTree;
  std::vector<std::vector<std::size_t>> wholeNode;
  if (options.ranks == 1)
  {
    for (std::size_t t = 0; t < whole.trees.size(); ++t)
    {
      const TreeDescription& tree = whole.trees[t];
      Refinement.emplace_back(tree.refinement, tree.refinement + tree.numberOfNodes);
      Masked.push_back(
          tree.masked ? std::vector<std::uint8_t>(tree.masked, tree.masked + tree.numberOfNodes)
                      : std::vector<std::uint8_t>());
      Absent.emplace_back();
      RootIndex.push_back(tree.rootIndex);
      wholeTree.push_back(t);
      std::vector<std::size_t> identity(tree.numberOfNodes);
      std::iota(identity.begin(), identity.end(), 0);
      wholeNode.push_back(std::move(identity));
    }
  }
  else
  {
    for (PartitionedTree& part : partitionForRank(whole, options.rank, options.ranks))
    {
      Refinement.push_back(std::move(part.refinement));
      Absent.push_back(std::move(part.absent));
      Masked.emplace_back();
      RootIndex.push_back(part.rootIndex);
      wholeTree.push_back(part.wholeTree);
      wholeNode.push_back(std::move(part.wholeNode));
    }
  }

  // The present leaves, breadth-first tree by tree; shuffled, blockIndex says where.
  std::vector<Block> leaves;
  for (std::size_t t = 0; t < Refinement.size(); ++t)
  {
    for (std::size_t n = 0; n < Refinement[t].size(); ++n)
    {
      if (!Refinement[t][n] && (Absent[t].empty() || !Absent[t][n]))
      {
        leaves.push_back({t, n, ids[wholeTree[t]][wholeNode[t][n]]});
      }
    }
  }
  std::vector<std::size_t> order(leaves.size());
  std::iota(order.begin(), order.end(), 0);
  if (options.shuffledBlocks)
  {
    std::mt19937_64 random(options.shape.seed + 77);
    std::shuffle(order.begin(), order.end(), random);
    BlockIndex.resize(Refinement.size());
    for (std::size_t t = 0; t < Refinement.size(); ++t)
    {
      BlockIndex[t].assign(Refinement[t].size(), -1);
    }
  }
  Blocks.resize(leaves.size());
  for (std::size_t d = 0; d < leaves.size(); ++d)
  {
    Blocks[order[d]] = leaves[d];
    if (options.shuffledBlocks)
    {
      BlockIndex[leaves[d].tree][leaves[d].node] = static_cast<std::int64_t>(order[d]);
    }
  }

  const int dimension = whole.dimension;
  const int n = options.cellsPerSide;
  const int g = options.ghostCells;
  for (int a = 0; a < dimension; ++a)
  {
    Extent[static_cast<std::size_t>(a)] = static_cast<std::size_t>(n + 2 * g);
  }
  const bool single = options.singlePrecision;
  ValueSize = single ? sizeof(float) : sizeof(double);
  const auto nc = static_cast<std::size_t>(options.components);
  const std::size_t cells = Extent[0] * Extent[1] * Extent[2];
  const std::size_t blocks = Blocks.size();
  switch (options.storage)
  {
  case BlockStorage::PerBlockVariableOutermost:
  case BlockStorage::PerBlockVariableInnermost:
    Buffers.assign(blocks, std::vector<unsigned char>(cells * nc * ValueSize));
    break;
  case BlockStorage::OneArray:
    Buffers.assign(1, std::vector<unsigned char>(blocks * cells * nc * ValueSize));
    break;
  case BlockStorage::SeparateComponents:
    Buffers.assign(blocks * nc, std::vector<unsigned char>(cells * ValueSize));
    break;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t b = 0; b < blocks; ++b)
  {
    for (int c = 0; c < options.components; ++c)
    {
      std::array<int, 3> p{{0, 0, 0}};
      for (p[2] = 0; p[2] < static_cast<int>(Extent[2]); ++p[2])
        for (p[1] = 0; p[1] < static_cast<int>(Extent[1]); ++p[1])
          for (p[0] = 0; p[0] < static_cast<int>(Extent[0]); ++p[0])
          {
            bool ghost = false;
            std::array<int, 3> interior{{0, 0, 0}};
            for (int a = 0; a < dimension; ++a)
            {
              const auto axis = static_cast<std::size_t>(a);
              interior[axis] = p[axis] - g;
              ghost = ghost || interior[axis] < 0 || interior[axis] >= n;
            }
            unsigned char* at =
                Buffers[bufferOf(b, c)].data() + offsetOf(p, c) +
                (options.storage == BlockStorage::OneArray ? b * cells * nc * ValueSize : 0);
            store(at, ghost ? nan : value(Blocks[b].id, interior, n, c), single);
          }
    }
  }

  Description.dimension = whole.dimension;
  Description.branchFactor = whole.branchFactor;
  Description.maxLevels = whole.maxLevels + 8;
  Description.rootGrid = whole.rootGrid;
  Description.blockCellsPerSide = n;
  Description.missingTreesAreElsewhere = options.ranks > 1;
  for (std::size_t t = 0; t < Refinement.size(); ++t)
  {
    TreeDescription tree;
    tree.rootIndex = RootIndex[t];
    tree.refinement = Refinement[t].data();
    tree.numberOfNodes = Refinement[t].size();
    tree.absent = Absent[t].empty() ? nullptr : Absent[t].data();
    tree.masked = Masked[t].empty() ? nullptr : Masked[t].data();
    tree.blockIndex = BlockIndex.empty() ? nullptr : BlockIndex[t].data();
    Description.trees.push_back(tree);
  }
  const int components = options.components;
  const auto outermost = [&](auto zero)
  {
    using T = decltype(zero);
    return BlockStrides::variableOutermost<T>(dimension, n, g);
  };
  const auto innermost = [&](auto zero)
  {
    using T = decltype(zero);
    return BlockStrides::variableInnermost<T>(dimension, n, g, components);
  };
  FieldDescription field;
  const auto describe = [&](auto zero)
  {
    using T = decltype(zero);
    switch (options.storage)
    {
    case BlockStorage::PerBlockVariableOutermost:
    case BlockStorage::PerBlockVariableInnermost:
      for (auto& buffer : Buffers)
      {
        BlockTable.push_back(buffer.data());
      }
      return FieldDescription::blocks<T>(
          "f", reinterpret_cast<const T* const*>(BlockTable.data()), blocks,
          options.storage == BlockStorage::PerBlockVariableOutermost ? outermost(zero)
                                                                     : innermost(zero),
          components);
    case BlockStorage::OneArray:
      return FieldDescription::blockArray<T>("f", reinterpret_cast<const T*>(Buffers[0].data()),
                                             cells * nc * sizeof(T), blocks, innermost(zero),
                                             components);
    case BlockStorage::SeparateComponents:
    {
      ComponentTables.assign(nc, {});
      std::vector<const T* const*> tables;
      for (std::size_t c = 0; c < nc; ++c)
      {
        for (std::size_t b = 0; b < blocks; ++b)
        {
          ComponentTables[c].push_back(Buffers[b * nc + c].data());
        }
        tables.push_back(reinterpret_cast<const T* const*>(ComponentTables[c].data()));
      }
      return FieldDescription::blockComponents<T>("f", tables, blocks, outermost(zero));
    }
    }
    return FieldDescription();
  };
  field = single ? describe(0.0f) : describe(0.0);
  Description.fields.push_back(field);
}

std::size_t BlockForest::offsetOf(const std::array<int, 3>& p, int component) const
{
  const auto c = static_cast<std::size_t>(component);
  const auto nc = static_cast<std::size_t>(Options.components);
  const std::size_t cell =
      (static_cast<std::size_t>(p[2]) * Extent[1] + static_cast<std::size_t>(p[1])) * Extent[0] +
      static_cast<std::size_t>(p[0]);
  switch (Options.storage)
  {
  case BlockStorage::PerBlockVariableOutermost:
    return (c * Extent[0] * Extent[1] * Extent[2] + cell) * ValueSize;
  case BlockStorage::PerBlockVariableInnermost:
  case BlockStorage::OneArray:
    return (cell * nc + c) * ValueSize;
  case BlockStorage::SeparateComponents:
    return cell * ValueSize;
  }
  return 0;
}

std::size_t BlockForest::bufferOf(std::size_t block, int component) const
{
  switch (Options.storage)
  {
  case BlockStorage::OneArray:
    return 0;
  case BlockStorage::SeparateComponents:
    return block * static_cast<std::size_t>(Options.components) +
           static_cast<std::size_t>(component);
  default:
    return block;
  }
}

void* BlockForest::address(std::size_t block, const std::array<int, 3>& cell, int component)
{
  std::array<int, 3> p = cell;
  for (int a = 0; a < Description.dimension; ++a)
  {
    p[static_cast<std::size_t>(a)] += Options.ghostCells;
  }
  const std::size_t blockOffset = Options.storage == BlockStorage::OneArray
                                      ? block * Extent[0] * Extent[1] * Extent[2] *
                                            static_cast<std::size_t>(Options.components) * ValueSize
                                      : 0;
  return Buffers[bufferOf(block, component)].data() + blockOffset + offsetOf(p, component);
}

double BlockForest::stored(std::size_t block, const std::array<int, 3>& cell, int component) const
{
  const void* at = const_cast<BlockForest*>(this)->address(block, cell, component);
  if (Options.singlePrecision)
  {
    float v;
    std::memcpy(&v, at, sizeof v);
    return v;
  }
  double v;
  std::memcpy(&v, at, sizeof v);
  return v;
}

std::uint64_t BlockForest::checksum() const
{
  std::uint64_t hash = 0;
  for (const auto& buffer : Buffers)
  {
    hash = hash * 31 + canopy::testing::checksum(buffer.data(), buffer.size());
  }
  return hash;
}

} // namespace canopy::testing
