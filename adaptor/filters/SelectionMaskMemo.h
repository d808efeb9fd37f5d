// What a selection mask was, tree by tree, at a filter's last execution, so
// that the next execution redoes only the trees whose inputs changed: a selected
// region rebuilt every step walks the trees that changed since the last step,
// not the whole grid (docs/benchmarks.md measures how many a mini-app step changes).
//
// A tree's flags are kept when the selection is the same (the `selection`
// fingerprint the filter gives: mode, region, list or range, the values' array
// and its modified time, Invert, AllowMasked) and so is everything of the tree
// the flags depend on (TopologyKeys.h, the filters' one rule for what changed):
// the tree object and its modified time (VTK gives every new object a time later
// than any before, so an address reused by a new tree is noticed), its vertex
// count and child table (where it lives and its size: VTK 9.2 refines a tree in
// place, never coarsens it), what Canopy's builder stamped on it, the mask and
// absent marks of its cells (the stamp's revision, or their fingerprint), its
// root cell's box, and for selections that read cells by number (ids, values)
// its first global index. Trees with explicit global indices are always redone
// (their index tables would have to be compared node by node).
//
// The packed masks are kept too: when the grid has the same number of cells and
// every tree has the cells it had, the next mask is the last one with the
// redone trees' bits rewritten, copied out (two bits a cell); otherwise (a tree
// grew: the trees after it moved) it is packed anew from every tree's flags (a
// byte a cell, no walk).
//
// Memory kept between executions: a byte per node (the flags) and two bits per
// cell (the last mask and pure mask). Checking the keys costs a few words per
// tree and, on masked grids Canopy did not build, a hash of its cells' mask bits
// and ghost marks.
#pragma once

#include "HyperTreeAccess.h"
#include "TopologyKeys.h"

#include <vtkSmartPointer.h>

#include <array>
#include <cstdint>
#include <vector>

class vtkBitArray;

namespace canopy
{

/// One tree's part of a selection mask: per local node, bit 0 visible and bit 1
/// VTK's pure mark (PureMask.h); the bounds of its selected visible leaves.
struct SelectionTreeFlags
{
  std::vector<unsigned char> flags;
  std::array<double, 6> bounds{{1e300, -1e300, 1e300, -1e300, 1e300, -1e300}};

  void include(const std::array<double, 3>& lo, const std::array<double, 3>& hi)
  {
    for (int a = 0; a < 3; ++a)
    {
      bounds[2 * a] = lo[a] < bounds[2 * a] ? lo[a] : bounds[2 * a];
      bounds[2 * a + 1] = hi[a] > bounds[2 * a + 1] ? hi[a] : bounds[2 * a + 1];
    }
  }
};

class SelectionMaskMemo
{
public:
  /// Decides, for a selection fingerprinted `selection` on `grid`, which trees
  /// keep their flags from the last execution (kept()). `readsByCellNumber`:
  /// the selection reads cells by their global index (ids, values), so a tree
  /// whose cells are numbered from another first index is redone; other
  /// selections keep a tree that only moved (an earlier tree grew).
  void begin(const HyperTreeAccess& grid, std::uint64_t selection, bool readsByCellNumber);

  /// Whether tree t (its position in grid.trees()) keeps its flags.
  bool kept(std::size_t t) const { return Kept[t] != 0; }
  /// Tree t's flags: the kept ones, or where the caller writes new ones (each
  /// tree by one thread).
  SelectionTreeFlags& tree(std::size_t t) { return Current[t].flags; }
  const SelectionTreeFlags& tree(std::size_t t) const { return Current[t].flags; }

  /// The packed mask and pure mask (vtkBitArray's order) of every tree's flags,
  /// the last ones patched where possible; kept for the next execution.
  void pack(const HyperTreeAccess& grid, vtkSmartPointer<vtkBitArray>& mask,
            vtkSmartPointer<vtkBitArray>& pure);

  /// Forget everything (an aborted or failed execution).
  void clear();

  /// What the last execution did: trees kept, and nodes whose flags were
  /// computed anew.
  std::size_t keptTrees() const { return KeptTrees; }
  std::size_t recomputedNodes() const { return RecomputedNodes; }

private:
  struct TreeKey
  {
    TreeTopologyKey topology;
    std::uint64_t box = 0; ///< the root cell's box
    /// Whether flags made for `o` hold for this tree.
    bool sameFlags(const TreeKey& o, bool numbering) const
    {
      return topology.sameTopology(o.topology, numbering) && topology.marks == o.topology.marks &&
             box == o.box;
    }
  };
  struct TreeEntry
  {
    TreeKey key;
    SelectionTreeFlags flags;
  };
  static TreeKey keyOf(const HyperTreeAccess& grid, const TreeAccess& tree);

  std::uint64_t Selection = 0;
  std::vector<TreeEntry> Current; ///< by position in the grid's trees
  std::vector<unsigned char> Kept;
  /// Where each tree's cells were in the last packed masks (tree index, first
  /// cell, vertices; by position), and how many cells the grid had.
  std::vector<std::array<vtkIdType, 3>> LastRanges;
  vtkIdType LastCells = -1;
  std::vector<unsigned char> LastMask; ///< packed as vtkBitArray packs
  std::vector<unsigned char> LastPure;
  std::size_t KeptTrees = 0;
  std::size_t RecomputedNodes = 0;
};

} // namespace canopy
