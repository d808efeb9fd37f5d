// The one rule of the filters for "has this grid's topology changed since my
// last execution?": the keys their memos compare (HyperTreeAccessCache keeps a
// grid's access, SelectionMaskMemo a selection's flags tree by tree).
//
// A tree is keyed on its identity (object, modified time, vertex count, child
// table, first global index) and on what Canopy's builder says of it in the
// grid's topology stamp (common/TopologyStamp.h: the build that last changed
// its refinement and its cells' marks). Its cells' marks (mask bits, absent
// parts) are then the stamp's revision; on a grid Canopy did not build, or one
// the stamp no longer vouches for (copied, its mask replaced, a tree refined in
// place), they are a fingerprint of the cells' mask bits and ghost marks. The
// grid is keyed on its shape (dimensions, the coordinates' values, the trees-
// elsewhere flag) and on its mask and ghost arrays (object, time, storage).
//
// A key compares equal only if everything it covers is the same: a stamp that
// does not vouch for a tree leaves that tree to its content key, never to an
// older revision. Tested by TopologyKeys.* and KeptSelectionMask.* (tests/unit).
#pragma once

#include "HyperTreeAccess.h"

#include <vtkType.h>

#include <cstdint>
#include <vector>

class vtkHyperTreeGrid;

namespace canopy
{

/// What one tree's memoized results depend on.
struct TreeTopologyKey
{
  vtkIdType index = -1;
  const void* tree = nullptr;
  vtkMTimeType treeTime = 0;
  vtkIdType vertices = 0;
  const void* elderChild = nullptr;
  std::size_t elderChildSize = 0;
  vtkIdType firstCell = -1;   ///< -1: explicit global indices
  std::uint64_t builder = 0;  ///< the stamp's builder; 0: not vouched for by a stamp
  std::uint64_t topology = 0; ///< the stamp's topology revision
  /// Its cells' mask bits and absent marks: the stamp's marks revision, or their
  /// fingerprint (computed only when asked for).
  std::uint64_t marks = 0;

  /// The same tree, topology and (with `numbering`) first global index.
  bool sameTopology(const TreeTopologyKey& o, bool numbering) const
  {
    return index == o.index && tree == o.tree && treeTime == o.treeTime && vertices == o.vertices &&
           elderChild == o.elderChild && elderChildSize == o.elderChildSize &&
           (!numbering || firstCell == o.firstCell) && builder == o.builder &&
           topology == o.topology;
  }
  bool operator==(const TreeTopologyKey& o) const
  {
    return sameTopology(o, true) && marks == o.marks;
  }
};

/// What a grid's memos depend on besides its trees.
struct GridTopologyKey
{
  const void* grid = nullptr;
  vtkMTimeType gridTime = 0; ///< 0 unless a tree has explicit global indices
  std::uint64_t shape = 0;   ///< dimension, branch factor, dimensions, coordinates, flag
  const void* mask = nullptr;
  vtkMTimeType maskTime = 0;
  const void* maskBits = nullptr;
  vtkIdType maskSize = 0;
  const void* ghosts = nullptr;
  vtkMTimeType ghostTime = 0;
  const void* ghostValues = nullptr;
  vtkIdType cells = 0;
  bool operator==(const GridTopologyKey& o) const;
};

/// The keys of `grid` (borrowed) and of each of its trees, in tree index order,
/// without their cells' marks (the grid's mask and ghost arrays cover them).
GridTopologyKey gridTopologyKey(vtkHyperTreeGrid* grid, std::vector<TreeTopologyKey>& trees);

/// The key of `tree` of the access `grid`, its cells' marks included (the
/// stamp's revision, or their fingerprint).
TreeTopologyKey treeTopologyKey(const HyperTreeAccess& grid, const TreeAccess& tree);

} // namespace canopy
