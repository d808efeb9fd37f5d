// A block forest held as Athena++/Parthenon/FLASH codes hold one: a random
// octree (quadtree) of blocks of n^d cells, each block's field in an array with
// ghost cells around the interior (filled with NaN: a ghost read shows), in one
// of the layouts those codes use. Optionally one rank's part of the forest split
// between ranks at block boundaries (PartitionedForest.h), the other ranks'
// parts absent. Addresses are computed here from the layout's own indexing, not
// from Canopy's BlockStrides, so the two are checked against each other.
#pragma once

#include "RandomForest.h"

#include <canopy/ForestDescription.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace canopy::testing
{

enum class BlockStorage
{
  PerBlockVariableOutermost, ///< one allocation per block, [var][k][j][i] (Athena++, Parthenon)
  PerBlockVariableInnermost, ///< one allocation per block, [k][j][i][var]
  OneArray,                  ///< every block in one array, [block][k][j][i][var] (FLASH's unk)
  SeparateComponents         ///< one allocation per block and component, [k][j][i]
};

struct BlockForestOptions
{
  RandomForestOptions shape; ///< the trees down to the blocks (masks only with ranks == 1)
  int cellsPerSide = 4;
  int ghostCells = 2;
  int components = 2;
  BlockStorage storage = BlockStorage::PerBlockVariableOutermost;
  bool singlePrecision = false;
  bool shuffledBlocks = false; ///< blocks in an order of the simulation's own (blockIndex)
  int rank = 0;
  int ranks = 1;
};

class BlockForest
{
public:
  explicit BlockForest(const BlockForestOptions& options);
  BlockForest(const BlockForest&) = delete;
  BlockForest& operator=(const BlockForest&) = delete;

  /// The rank's description with one field "f" of `components` components.
  const ForestDescription& description() const { return Description; }
  const BlockForestOptions& options() const { return Options; }

  /// The rank's blocks, by their index in the field's block tables.
  struct Block
  {
    std::size_t tree = 0; ///< position in description().trees
    std::size_t node = 0; ///< breadth-first node of that tree description
    std::int64_t id = 0;  ///< the block's place in the whole forest's Morton order
  };
  const std::vector<Block>& blocks() const { return Blocks; }

  /// The value the simulation keeps in interior cell `cell` of the block with
  /// whole-forest id `id` (distinct for every cell and component of a forest of
  /// fewer than 1024 blocks of at most 16^3 cells, exact in float).
  static double value(std::int64_t id, const std::array<int, 3>& cell, int cellsPerSide,
                      int component);
  /// Where the simulation keeps it (interior cell of the block with index `block`).
  void* address(std::size_t block, const std::array<int, 3>& cell, int component);
  /// The stored value there, as double.
  double stored(std::size_t block, const std::array<int, 3>& cell, int component) const;
  /// FNV-1a over every byte of every block array, ghosts included.
  std::uint64_t checksum() const;

private:
  std::size_t offsetOf(const std::array<int, 3>& withGhosts, int component) const;
  std::size_t bufferOf(std::size_t block, int component) const;

  BlockForestOptions Options;
  std::unique_ptr<RandomForest> Whole;
  std::vector<std::vector<std::uint8_t>> Refinement;
  std::vector<std::vector<std::uint8_t>> Absent;
  std::vector<std::vector<std::uint8_t>> Masked;
  std::vector<std::vector<std::int64_t>> BlockIndex;
  std::vector<std::int64_t> RootIndex;
  std::vector<Block> Blocks;
  std::array<std::size_t, 3> Extent{{1, 1, 1}}; ///< cells per axis, ghosts included
  std::size_t ValueSize = 8;
  std::vector<std::vector<unsigned char>> Buffers;
  std::vector<const void*> BlockTable;                   ///< per block (per-block layouts)
  std::vector<std::vector<const void*>> ComponentTables; ///< per component and block
  ForestDescription Description;
};

} // namespace canopy::testing
