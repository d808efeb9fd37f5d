// The mini-app's forest topology: a periodic unit domain split into a grid of
// root cells, each the root of a 2^d- or 3^d-ary refinement tree. Every rank
// holds the topology of every tree (one byte per node, as the trees' breadth-
// first refinement bytes) so that neighbour lookups never need communication;
// field values live only with the tree's owner (see LeafFields).
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace miniamr
{

/// A node's place: its level and integer position at that level, global over
/// the whole domain (root (i, j, k) at level 0, child c of p at p * b + c).
struct NodeKey
{
  int level = 0;
  std::array<std::int64_t, 3> position{{0, 0, 0}};
  bool operator==(const NodeKey& other) const
  {
    return level == other.level && position == other.position;
  }
};

struct NodeKeyHash
{
  std::size_t operator()(const NodeKey& key) const
  {
    std::uint64_t h = static_cast<std::uint64_t>(key.level) * 0x9E3779B97F4A7C15ULL;
    for (auto p : key.position)
    {
      h ^= static_cast<std::uint64_t>(p) + 0x9E3779B97F4A7C15ULL + (h << 6) + (h >> 2);
    }
    return static_cast<std::size_t>(h);
  }
};

/// One refinement tree, nodes breadth-first.
struct Tree
{
  struct Node
  {
    NodeKey key;
    std::int32_t firstChild = -1; ///< breadth-first index of child 0; -1 for a leaf
    std::int32_t leaf = -1;       ///< index among the tree's leaves (breadth-first); -1 if refined
  };
  std::int64_t rootIndex = 0;
  std::vector<Node> nodes;
  std::vector<std::uint8_t> refinement; ///< one byte per node: what Canopy reads
  std::int32_t leafCount = 0;
};

/// Where a node lives: tree and breadth-first index.
struct NodeRef
{
  std::int32_t tree = -1;
  std::int32_t node = -1;
};

class AmrForest
{
public:
  /// A forest of unrefined roots: `roots` per axis (the third ignored in 2D).
  AmrForest(int dimension, int branchFactor, std::array<int, 3> roots, int maxLevel);

  int dimension() const { return Dimension; }
  int branchFactor() const { return BranchFactor; }
  int children() const { return Children; }
  int maxLevel() const { return MaxLevel; }
  const std::array<int, 3>& roots() const { return Roots; }
  const std::vector<Tree>& trees() const { return Trees; }
  std::int64_t totalLeaves() const;
  std::int64_t totalNodes() const;

  /// Cells per axis at a level, over the whole domain (1 on the flat axis in 2D).
  std::int64_t cellsAcross(int axis, int level) const;
  /// Edge length of a cell along an axis at a level (the domain is the unit cube).
  double cellSize(int axis, int level) const;
  double cellVolume(int level) const;
  std::array<double, 3> cellLow(const NodeKey& key) const;
  std::array<double, 3> cellCenter(const NodeKey& key) const;

  /// The node with this key, if it exists.
  const Tree::Node* find(const NodeKey& key, NodeRef* where = nullptr) const;

  /// A face neighbour of a leaf: the leaf across the face and the face's area.
  struct FaceNeighbour
  {
    NodeRef leaf;
    const Tree::Node* node = nullptr;
    double area = 0.0;
    /// The finer of the two cells (its key), from which the face is measured.
    NodeKey finer;
    int finerSide = 0; ///< side of the finer cell the face is on (-1 or +1)
  };
  /// Every leaf across the face of `key` on `side` (-1/+1) of `axis` (periodic),
  /// in a fixed order: one same-level or coarser leaf, or the finer leaves
  /// touching the face.
  void faceNeighbours(const NodeKey& key, int axis, int side,
                      std::vector<FaceNeighbour>& out) const;

  /// The center of a face between two leaves, from the finer one: the same from
  /// both sides to the last bit (the coordinate along the axis comes from an
  /// integer face index, wrapped at the periodic boundary).
  std::array<double, 3> faceCenter(const FaceNeighbour& neighbour, int axis) const;

  /// Rebuilds every tree from per-leaf wishes (tree by tree, leaves breadth-first):
  /// +1 refine (below maxLevel), -1 may coarsen (a family coarsens when all its
  /// children are leaves that may), 0 keep. `onTree(t, oldTree, newTree)` is called
  /// per tree, e.g. to carry field values over.
  template <typename OnTree>
  void regrid(const std::vector<std::vector<std::int8_t>>& wishes, OnTree onTree);

  /// For the tree being rebuilt (valid inside regrid's callback): per new leaf,
  /// the old leaf it was kept or refined from, or the old leaves it coarsens.
  struct LeafOrigin
  {
    std::int32_t oldLeaf = -1;             ///< kept, or refined from, this old leaf
    std::vector<std::int32_t> oldChildren; ///< coarsened: its old children's leaf indices
  };
  const std::vector<LeafOrigin>& lastOrigins() const { return Origins; }

private:
  void index();
  void finish(Tree& tree) const;
  Tree rebuild(const Tree& old, const std::vector<std::int8_t>& wishes);

  int Dimension;
  int BranchFactor;
  int Children;
  std::array<int, 3> Roots;
  int MaxLevel;
  std::vector<Tree> Trees;
  std::unordered_map<NodeKey, NodeRef, NodeKeyHash> Index;
  std::vector<LeafOrigin> Origins;
};

template <typename OnTree>
void AmrForest::regrid(const std::vector<std::vector<std::int8_t>>& wishes, OnTree onTree)
{
  for (std::size_t t = 0; t < Trees.size(); ++t)
  {
    Tree rebuilt = rebuild(Trees[t], wishes[t]);
    onTree(t, Trees[t], rebuilt);
    Trees[t] = std::move(rebuilt);
  }
  index();
}

} // namespace miniamr
