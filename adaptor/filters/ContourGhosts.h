// The leaves of other ranks a rank's contour needs, so that what the ranks draw
// together is the whole forest's contour: watertight across rank borders, with
// no cell drawn twice.
//
// A dual cell (DualTraversal.h) joins the leaves around one grid vertex. Where
// those leaves belong to several ranks, each rank sees only its own: without
// more, every rank drops the cell (a gap one dual cell wide along the border).
// Each rank therefore sends, once per execution, its **border leaves**: every
// visible leaf sharing a vertex with another rank's part (an absent cell, or a
// root cell whose tree is elsewhere), the leaves across their faces (what their
// boundary gradients are fitted to, LeafGradient.h), and the ancestors of both
// (so that a receiver can descend to them, and with level of detail or a
// maximum level stop at a coarser node holding its own value). A receiver plugs
// them into its traversal where its grid has an absent node or a tree
// elsewhere: a ghost node is a Leaf or Inner node there like a local one, a
// node no rank sent is Hidden.
//
// Why that is enough: a cell some rank draws has one of that rank's leaves, and
// every other leaf of the cell shares a vertex with it, so is a border leaf of
// its owner; a border leaf's boundary gradient is fitted to its face neighbours,
// sent too, so both ranks compute the same boundary vertices. Which rank draws
// a cell: the owner of its lowest slot's leaf (DualCellContour.h). A point is
// computed from its edge's ends in an order that does not depend on the rank
// (ContourPiece.h), so points on a shared edge are the same bits on both sides.
//
// Tested by ContourGhostLayer.* (tests/unit/ContourTest.cxx: split forests in
// one process, every rank's records handed to every rank, the union equal to
// the whole forest's contour cell for cell, each cell drawn once) and by
// mpi.contour_split.np{2,4} (the same through MPI).
#pragma once

#include "ContourField.h"
#include "HyperTreeAccess.h"
#include "ViewVolume.h"

#include <array>
#include <cstdint>
#include <deque>
#include <unordered_map>
#include <vector>

class vtkDataArray;

namespace canopy
{

class ContourGhosts
{
public:
  /// What one rank sends: per node, RecordHeader numbers (root cell, level,
  /// position; 1 a leaf, 0 an inner node, 2 one with other ranks' parts
  /// below), then the contoured value, then the components of
  /// each interpolated field, all as doubles (integers below 2^53).
  static constexpr std::size_t RecordHeader = 6;

  /// The records of `grid`'s border leaves, their face neighbours and their
  /// ancestors (full resolution; none for a grid with no other rank's part).
  /// `field` and `interpolated` (borrowed) give their values.
  /// `maximumLevel` and `view`: the contour's (DualTraversal.h), so that the
  /// border is the one of the forest the contour sees.
  static std::vector<double> collect(const HyperTreeAccess& grid, const ContourField& field,
                                     const std::vector<vtkDataArray*>& interpolated,
                                     int maximumLevel, const ViewOptions& view);

  /// The ghosts of `grid` (borrowed; must outlive this) from every rank's
  /// records (`records[r]`: rank r's, as collect() made them; `self`: this
  /// rank, whose own records are skipped). `components`: the interpolated
  /// fields' components, in order. Throws std::invalid_argument on records of
  /// the wrong shape (another grid's).
  ContourGhosts(const HyperTreeAccess& grid, const std::vector<std::vector<double>>& records,
                int self, const std::vector<int>& components);

  /// The ghost at a node of root cell `root` (its TreeAccess: the local tree,
  /// or a stand-in for a tree elsewhere), or -1.
  std::int64_t find(const TreeAccess& root, int level, const std::array<std::int64_t, 3>& ijk) const
  {
    if (Index.empty())
    {
      return -1;
    }
    const auto found = Index.find(Key{rootNumber(root.rootIJK), level, ijk});
    return found == Index.end() ? -1 : found->second;
  }
  /// The stand-in TreeAccess (geometry only) of a root cell whose tree is on
  /// another rank and sent ghosts, or nullptr.
  const TreeAccess* elsewhere(const std::array<unsigned int, 3>& rootIJK) const
  {
    const auto found = Elsewhere.find(rootNumber(rootIJK));
    return found == Elsewhere.end() ? nullptr : &Stand[found->second];
  }

  /// A leaf of its owner's grid.
  bool isLeaf(std::int64_t ghost) const { return Leaf[static_cast<std::size_t>(ghost)] == 1; }
  /// An inner node with parts of several ranks below (never a coarse leaf).
  bool mixed(std::int64_t ghost) const { return Leaf[static_cast<std::size_t>(ghost)] == 2; }
  /// The contoured value, and each interpolated field's components.
  const std::vector<double>& values() const { return Values; }
  double interpolated(std::size_t field, std::int64_t ghost, int component) const
  {
    return Fields[field]
                 [static_cast<std::size_t>(ghost) * static_cast<std::size_t>(Components[field]) +
                  static_cast<std::size_t>(component)];
  }
  std::size_t size() const { return Leaf.size(); }
  /// Bytes received from the other ranks (the exchange's cost).
  std::size_t bytesReceived() const { return Received; }

private:
  std::int64_t rootNumber(const std::array<unsigned int, 3>& ijk) const
  {
    const auto& roots = Grid.rootCells();
    return (static_cast<std::int64_t>(ijk[2]) * roots[1] + ijk[1]) * roots[0] + ijk[0];
  }
  struct Key
  {
    std::int64_t root;
    int level;
    std::array<std::int64_t, 3> ijk;
    bool operator==(const Key& o) const
    {
      return root == o.root && level == o.level && ijk == o.ijk;
    }
  };
  struct KeyHash
  {
    std::size_t operator()(const Key& k) const
    {
      std::uint64_t h = static_cast<std::uint64_t>(k.root) * 0x9E3779B97F4A7C15ull;
      h ^= (static_cast<std::uint64_t>(k.level) + (h << 6) + (h >> 2)) * 0xBF58476D1CE4E5B9ull;
      for (std::int64_t x : k.ijk)
      {
        h ^= (static_cast<std::uint64_t>(x) + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2)) *
             0x94D049BB133111EBull;
      }
      return static_cast<std::size_t>(h ^ (h >> 31));
    }
  };

  const HyperTreeAccess& Grid;
  std::unordered_map<Key, std::int64_t, KeyHash> Index;
  std::unordered_map<std::int64_t, std::size_t> Elsewhere;
  std::deque<TreeAccess> Stand; ///< stable addresses: DualNode points to them
  std::vector<unsigned char> Leaf;
  std::vector<double> Values;
  std::vector<int> Components;
  std::vector<std::vector<double>> Fields;
  std::size_t Received = 0;
};

} // namespace canopy
