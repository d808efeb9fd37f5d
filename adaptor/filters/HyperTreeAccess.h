// Direct, read-only access to a vtkHyperTreeGrid's trees for fast traversals.
//
// VTK's cursors cost a virtual call (and, in Debian's build, unoptimized code)
// per step; the filters instead read each tree's elder-child table and compute
// geometry themselves. A node is a leaf when it has no entry in the table or
// its entry is UINT_MAX; its children are elderChild .. elderChild + n - 1.
#pragma once

#include <vtkBitArray.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace canopy
{

struct TreeAccess
{
  vtkIdType treeIndex = 0;
  vtkHyperTree* tree = nullptr;
  const unsigned int* elderChild = nullptr;
  std::size_t elderChildSize = 0;
  bool implicitGlobalIndex = true;
  vtkIdType globalIndexStart = 0;
  std::array<double, 3> origin{{0, 0, 0}}; ///< lower corner of the root cell
  std::array<double, 3> size{{0, 0, 0}};   ///< root cell size (0 on flat axes)
  std::array<unsigned int, 3> rootIJK{{0, 0, 0}};
  /// Per local node: 1 when a strict descendant is masked (filled only for
  /// grids with a mask; empty otherwise, meaning "never").
  std::vector<unsigned char> maskedBelow;

  bool hasMaskedDescendant(vtkIdType node) const
  {
    return !maskedBelow.empty() && maskedBelow[static_cast<std::size_t>(node)] != 0;
  }
  /// Per local node: 1 when a strict descendant is absent (another rank's part of
  /// a split tree); filled only for grids with absent cells.
  std::vector<unsigned char> absentBelow;

  bool hasAbsentDescendant(vtkIdType node) const
  {
    return !absentBelow.empty() && absentBelow[static_cast<std::size_t>(node)] != 0;
  }

  vtkIdType numberOfVertices = 0;
  int childrenPerNode = 0;
  /// What the grid's topology stamp (TopologyStamp.h) says of this tree, when
  /// it vouches for it: its builder and the build that last changed its
  /// refinement; and, when it vouches for the grid's mask and ghost arrays too,
  /// the build that last changed its cells' marks. 0 where it does not vouch.
  std::uint64_t stampBuilder = 0;
  std::uint64_t stampTopology = 0;
  std::uint64_t stampMarks = 0;
  /// 3D surface memos, filled on first use and kept with the access (they depend
  /// on the topology only, not on the view, and on whether other ranks' parts
  /// are asked: memoRemote). Written only by the thread walking this tree.
  /// exposeMemo: 0 unknown, 1 nothing inside can be exposed, 2 may be.
  /// faceMemo: 3 bits per face (axis * 2 + side), AdaptiveSurfaceBuilder's FaceState.
  mutable std::vector<unsigned char> exposeMemo;
  mutable std::vector<std::uint32_t> faceMemo;
  mutable int memoRemote = -1;
  /// Unmasked leaves without a masked ancestor: the cells of a full 1D/2D
  /// surface. Counted only with index tables (a kept access); -1 otherwise.
  vtkIdType visibleLeaves = -1;
  /// The points of those cells (corners, and the corners of finer neighbours on
  /// their edges): counted by the first full surface of a kept access, -1 before.
  /// Written only by the thread walking this tree.
  mutable vtkIdType fullSurfacePoints = -1;

  /// As VTK's compact tree decides, plus a guard: a single-vertex tree is a
  /// leaf whatever its table says (vtkHyperTreeGridSource leaves a 0 there),
  /// and an entry pointing past the tree's vertices is never followed.
  bool isLeaf(vtkIdType node) const
  {
    if (static_cast<std::size_t>(node) >= elderChildSize || numberOfVertices == 1)
    {
      return true;
    }
    const unsigned int first = elderChild[node];
    return first == std::numeric_limits<unsigned int>::max() || first == 0 ||
           static_cast<vtkIdType>(first) + childrenPerNode > numberOfVertices;
  }
  vtkIdType firstChild(vtkIdType node) const { return elderChild[node]; }
  /// Explicit indices read once (when a pass over all nodes happens anyway):
  /// VTK's per-node virtual lookup is slow in Debian's build.
  std::vector<vtkIdType> globalTable;

  vtkIdType globalIndex(vtkIdType node) const
  {
    if (implicitGlobalIndex)
    {
      return globalIndexStart + node;
    }
    return globalTable.empty() ? tree->GetGlobalIndexFromLocal(node)
                               : globalTable[static_cast<std::size_t>(node)];
  }
};

/// The shape of a grid as the filters need it.
class HyperTreeAccess
{
public:
  /// `indexTables`: read every explicit global-index table once, here (worth it
  /// when the access is kept across executions: VTK's per-node virtual lookup is
  /// slow). `maskedDescendants`: flag the nodes with a masked descendant (3D grids
  /// with a mask; a pass over every node, which only the 3D surface needs).
  /// Absent-descendant flags are always computed for grids with absent cells.
  explicit HyperTreeAccess(vtkHyperTreeGrid* htg, bool indexTables = false,
                           bool maskedDescendants = true);

  /// Whether explicit global indices were read into tables.
  bool hasIndexTables() const { return IndexTables; }
  /// Whether masked-descendant flags were asked for (hasMaskedDescendant answers).
  bool hasMaskedDescendantFlags() const { return MaskedDescendants; }

  int dimension() const { return Dimension; }
  int branchFactor() const { return BranchFactor; }
  int childrenPerNode() const { return Children; }
  /// Axes along which cells have extent (1 in 1D, 2 in 2D, 3 in 3D), increasing.
  const std::vector<int>& activeAxes() const { return ActiveAxes; }
  /// Root cells per axis (1 on the flat axis).
  const std::array<unsigned int, 3>& rootCells() const { return RootCells; }
  /// Bounds of the whole root grid.
  const std::array<double, 6>& bounds() const { return Bounds; }

  const std::vector<TreeAccess>& trees() const { return Trees; }
  /// For child position c: its digit along each axis (-1 on an inactive axis).
  /// Active axes in increasing order, the first one fastest, as in VTK.
  const std::array<int, 3>& childDigits(int c) const
  {
    return ChildDigits[static_cast<std::size_t>(c)];
  }
  /// Tree at root cell (i, j, k), or nullptr when absent or out of range.
  const TreeAccess* treeAt(long i, long j, long k) const;
  /// Whether root cell (i, j, k) is in the grid, has no tree here, and its tree
  /// is on another rank (the grid says so: canopy::missingTreesElsewhereName).
  bool treeElsewhere(long i, long j, long k) const;

  /// Root point coordinates along an axis (a single value on a flat axis).
  const std::vector<double>& coordinates(int axis) const
  {
    return Coordinates[static_cast<std::size_t>(axis)];
  }
  /// Integer position of child c of the node at `parent` (one level down).
  std::array<std::int64_t, 3> childPosition(const std::array<std::int64_t, 3>& parent, int c) const
  {
    const auto& digit = ChildDigits[static_cast<std::size_t>(c)];
    std::array<std::int64_t, 3> ijk = parent;
    for (int a = 0; a < 3; ++a)
    {
      ijk[a] = digit[a] < 0 ? ijk[a] : ijk[a] * BranchFactor + digit[a];
    }
    return ijk;
  }

  /// Position (0 .. children-1) of the child of a node at `level` on the way
  /// down to the integer position `target` at `targetLevel` (> level).
  int childToward(int level, int targetLevel, const std::array<std::int64_t, 3>& target) const
  {
    if (BranchFactor == 2)
    {
      // Binary trees: the digit is a bit of the position (no division).
      const int shift = targetLevel - level - 1;
      int child = 0;
      int bit = 0;
      for (int a : ActiveAxes)
      {
        child |= static_cast<int>((target[static_cast<std::size_t>(a)] >> shift) & 1) << bit++;
      }
      return child;
    }
    const std::int64_t scale = CellsPerRoot[static_cast<std::size_t>(targetLevel - level - 1)];
    int child = 0;
    int weight = 1;
    for (int a : ActiveAxes)
    {
      child +=
          static_cast<int>((target[static_cast<std::size_t>(a)] / scale) % BranchFactor) * weight;
      weight *= BranchFactor;
    }
    return child;
  }

  /// Number of cells (nodes) of the grid: global indices are below it.
  vtkIdType numberOfCells() const { return NumberOfCells; }
  /// f^level, for levels the integer positions can represent (see maxLevel()).
  std::int64_t cellsPerRootAt(int level) const
  {
    return CellsPerRoot[static_cast<std::size_t>(level)];
  }
  int maxLevel() const { return static_cast<int>(CellsPerRoot.size()) - 1; }
  /// Box of the node at integer position ijk (per axis, in [0, f^level)) of a
  /// tree: origin + size * ijk / f^level, correctly rounded; the last node of a
  /// row ends exactly at the root's upper corner.
  void nodeBounds(const TreeAccess& tree, int level, const std::array<std::int64_t, 3>& ijk,
                  std::array<double, 3>& lo, std::array<double, 3>& hi) const
  {
    const std::int64_t cells = CellsPerRoot[static_cast<std::size_t>(level)];
    const double count = static_cast<double>(cells);
    for (int a = 0; a < 3; ++a)
    {
      if (tree.size[a] == 0)
      {
        lo[a] = hi[a] = tree.origin[a];
        continue;
      }
      lo[a] = tree.origin[a] + tree.size[a] * (static_cast<double>(ijk[a]) / count);
      hi[a] = ijk[a] + 1 == cells
                  ? tree.origin[a] + tree.size[a]
                  : tree.origin[a] + tree.size[a] * (static_cast<double>(ijk[a] + 1) / count);
    }
  }

  /// Lower bound along `axis` of the node at integer position `index` (along
  /// that axis) and `level`: the same value nodeBounds() gives.
  double nodeLower(const TreeAccess& tree, int level, int axis, std::int64_t index) const
  {
    const double count = static_cast<double>(CellsPerRoot[static_cast<std::size_t>(level)]);
    if (tree.size[axis] == 0)
    {
      return tree.origin[axis];
    }
    return tree.origin[axis] + tree.size[axis] * (static_cast<double>(index) / count);
  }

  bool hasMask() const { return Mask != nullptr; }
  /// Absent cells: parts of split trees another rank owns. Canopy's builder
  /// masks them and marks them DUPLICATECELL in VTK's ghost array; a masked
  /// cell without that mark is a hole. Absent cells are never shown or selected,
  /// and a node with absent descendants is never drawn as one piece (its
  /// pixels belong to several ranks).
  bool hasAbsent() const { return AnyAbsent; }
  /// Whether root cells without a tree have it on another rank.
  bool hasTreesElsewhere() const { return MissingTreesElsewhere; }
  bool isAbsent(vtkIdType globalIndex) const
  {
    return Ghosts != nullptr && globalIndex < GhostsSize &&
           (Ghosts[globalIndex] & AbsentGhostBit) != 0;
  }
  bool isMasked(vtkIdType globalIndex) const
  {
    // vtkBitArray stores the most significant bit first; read it inline. Cells
    // past the end of a short mask are unmasked.
    return MaskBits != nullptr && globalIndex < MaskSize &&
           ((MaskBits[globalIndex >> 3] >> (7 - (globalIndex & 7))) & 1) != 0;
  }

  /// The mask's packed bits (nullptr without a mask) and its length in cells;
  /// the ghost marks (nullptr without them) and their count: what the cells'
  /// hidden state is read from, for fingerprints of it.
  const unsigned char* maskBits() const { return MaskBits; }
  vtkIdType maskSize() const { return MaskSize; }
  const unsigned char* ghostMarks() const { return Ghosts; }
  vtkIdType ghostMarkCount() const { return GhostsSize; }

private:
  void computeHiddenBelow(TreeAccess& access, bool masked, bool absent) const;
  void countVisibleLeaves(TreeAccess& access) const;

  bool IndexTables = false;
  bool MaskedDescendants = true;

  int Dimension = 0;
  int BranchFactor = 2;
  int Children = 4;
  std::vector<int> ActiveAxes;
  std::array<unsigned int, 3> RootCells{{1, 1, 1}};
  std::array<double, 6> Bounds{{0, 0, 0, 0, 0, 0}};
  std::vector<TreeAccess> Trees;
  std::array<std::array<int, 3>, 27> ChildDigits{};
  std::array<std::vector<double>, 3> Coordinates;
  std::vector<std::int64_t> CellsPerRoot;
  vtkIdType NumberOfCells = 0;
  std::vector<std::int64_t> TreeAtRoot; ///< root cell -> position in Trees, or -1
  vtkBitArray* Mask = nullptr;
  const unsigned char* MaskBits = nullptr;
  vtkIdType MaskSize = 0;
  static constexpr unsigned char AbsentGhostBit = 1; ///< vtkDataSetAttributes::DUPLICATECELL
  const unsigned char* Ghosts = nullptr;
  vtkIdType GhostsSize = 0;
  bool AnyAbsent = false;
  bool MissingTreesElsewhere = false;
};

/// Name of the field-data flag (a one-value integer array, nonzero) with which
/// Canopy's builder says that root cells without a tree have it on another rank.
inline const char* missingTreesElsewhereName()
{
  return "CanopyMissingTreesElsewhere";
}

} // namespace canopy
