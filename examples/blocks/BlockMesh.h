// The mesh of a block-AMR code (Athena++, Parthenon, FLASH style): a grid of root
// blocks, each the root of a quadtree (2D) or octree (3D) whose leaves are the
// blocks that hold cells. Every rank keeps the whole mesh (the keys of all
// blocks, tens of bytes each); block data lives on one rank only (block_advection.cxx).
//
// Blocks are ordered globally in Morton order: trees in root order (i fastest),
// each tree depth-first with children x fastest, then y, then z. Ranks own
// contiguous ranges of that order, so a tree may be split between ranks at any
// block boundary.
//
// Positions are integers: one unit is half the side of the finest cell the mesh
// may have, so every cell's centre and every face lie on integers.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace blocks
{

constexpr int CellsPerSide = 16; ///< a block holds CellsPerSide^d cells
constexpr int GhostCells = 2;    ///< ghost layers on each side of a block

using Point = std::array<std::int64_t, 3>;

/// Where a block is: its tree (root index), its level (0 = the root block) and
/// its position among the tree's blocks of that level (0 .. 2^level - 1 per axis).
struct BlockKey
{
  int tree = 0;
  int level = 0;
  Point at{{0, 0, 0}};
};

/// Where a block of an adapted mesh takes its values from, in the mesh before.
struct Origin
{
  enum class Kind
  {
    Inside, ///< the block lies in old block `block` (the same, or a refined part of it)
    Covers  ///< the block is the parent of the 2^d old blocks block .. block + 2^d - 1
  };
  Kind kind = Kind::Inside;
  std::int64_t block = 0;
};

class BlockMesh
{
public:
  /// `roots` root blocks per axis (1 on axes a 2D mesh does not have), blocks at
  /// most `maxLevel` levels below the roots. Starts with the root blocks.
  BlockMesh(int dimension, std::array<int, 3> roots, int maxLevel);

  int dimension() const { return Dimension; }
  int maxLevel() const { return MaxLevel; }
  int childrenPerBlock() const { return 1 << Dimension; }
  const std::array<int, 3>& roots() const { return Roots; }
  int numberOfTrees() const { return Roots[0] * Roots[1] * Roots[2]; }
  std::int64_t numberOfBlocks() const { return static_cast<std::int64_t>(Leaves.size()); }
  const BlockKey& block(std::int64_t b) const { return Leaves[static_cast<std::size_t>(b)]; }

  /// Side of a block's cells, and of the block, at a level (in units).
  std::int64_t cellSide(int level) const { return std::int64_t{2} << (MaxLevel - level); }
  std::int64_t blockSide(int level) const { return CellsPerSide * cellSide(level); }
  /// Lower corner of a block (units), and the domain's upper corner.
  Point corner(const BlockKey& key) const;
  const Point& domain() const { return Domain; }

  /// The block whose closed box holds the point (in the domain): on a face between
  /// blocks, the block on the upper side.
  std::int64_t locate(const Point& point) const;
  /// Every block overlapping the box [lo, hi) with nonzero volume (flat axes ignored).
  void blocksOverlapping(const Point& lo, const Point& hi, std::vector<std::int64_t>& out) const;

  /// The tree's blocks are blocks firstBlockOfTree(t) .. firstBlockOfTree(t + 1) - 1.
  std::int64_t firstBlockOfTree(int tree) const { return TreeFirstBlock[tree]; }

  /// One node of a tree (a block, or a refined block above blocks), for walking a
  /// tree breadth-first: children are nodes firstChild .. firstChild + 2^d - 1 of
  /// the same tree, the root is node 0. Its blocks are blocks [firstBlock, endBlock).
  struct Node
  {
    std::int32_t firstChild = -1; ///< -1: a block (a leaf of the tree)
    std::int64_t firstBlock = 0;
    std::int64_t endBlock = 0;
  };
  const std::vector<Node>& nodesOfTree(int tree) const { return Trees[tree]; }

  /// Adapts the mesh: `change` per block, +1 refine, -1 coarsen (only whole families
  /// of 2^d sibling blocks all asking for it are coarsened), 0 keep. Levels stay
  /// within [0, maxLevel] and the mesh 2:1 balanced across faces (a coarsening that
  /// would break the balance is cancelled, blocks are refined to restore it).
  /// Returns, per block of the new mesh, where its values come from.
  std::vector<Origin> adapt(const std::vector<int>& change);

private:
  void index();
  bool unbalanced(const BlockKey& key) const;

  int Dimension;
  int MaxLevel;
  std::array<int, 3> Roots;
  Point Domain{{0, 0, 0}};
  std::vector<BlockKey> Leaves;
  std::vector<std::vector<Node>> Trees;
  std::vector<std::int64_t> TreeFirstBlock;
};

} // namespace blocks
