// What Canopy's GridBuilder knows about a grid it built, written into the grid
// for the filters: per tree, the build at which its topology (refinement) and
// its cells' marks (mask bits, absent parts) last changed, and the build at
// which the grid's shape and topology arrays last changed. The one rule for
// "what changed": the builder decides it (it knows which trees it rebuilt, or
// the simulation's own revision says nothing changed), the filters' memos
// (HyperTreeAccessCache, SelectionMaskMemo) read it (filters/TopologyKeys.h).
//
// Why it cannot lie: the stamp also records the identity of everything it
// vouches for, as it was when stamped: the grid object, its mask and ghost
// arrays (object and modified time), and each tree (object, modified time,
// vertex count, child table). A reader trusts the stamp only for what still
// matches: a grid shallow-copied, a mask replaced or marked Modified(), a tree
// refined in place (more vertices) or Modified(), is not vouched for, and the
// memos fall back to keys computed from the grid's content. Checked by
// TopologyStamp.* (tests/unit).
//
// Stored as a field-data array (vtkTypeUInt64Array named topologyStampName):
// a header of HeaderValues values, then TreeValues per tree. Header-only: the
// forest library writes it and the filters read it, and neither links the other.
#pragma once

#include <vtkBitArray.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkFieldData.h>
#include <vtkHyperTree.h>
#include <vtkHyperTreeGrid.h>
#include <vtkNew.h>
#include <vtkTypeUInt64Array.h>
#include <vtkUnsignedCharArray.h>

#include <atomic>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

namespace canopy
{

inline constexpr const char* topologyStampName = "CanopyTopologyStamp";

/// What the stamp says about one tree.
struct TreeStamp
{
  std::uint64_t tree = 0;       ///< the vtkHyperTree's address when stamped
  std::uint64_t treeTime = 0;   ///< its modified time
  std::uint64_t vertices = 0;   ///< its vertex count
  std::uint64_t elderChild = 0; ///< its child table's address
  std::uint64_t topology = 0;   ///< the build that last changed its refinement
  std::uint64_t marks = 0;      ///< the build that last changed its cells' mask or absent marks
};

/// The builds at which a grid's parts last changed (the builder's side).
struct StampRevisions
{
  std::uint64_t builder = 0; ///< the builder's identity (one per GridBuilder)
  std::uint64_t arrays = 0;  ///< mask and ghost arrays
  /// Per tree (by its root cell's index): topology and marks revisions.
  std::unordered_map<vtkIdType, std::pair<std::uint64_t, std::uint64_t>> trees;
};

namespace topology_stamp_detail
{
constexpr std::uint64_t Magic = 0x43414E4F50590001ull; // "CANOPY", version 1
constexpr int HeaderValues = 9;
constexpr int TreeValues = 7; // tree index, then TreeStamp's fields

inline std::uint64_t address(const void* p)
{
  return static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(p));
}

inline vtkUnsignedCharArray* ghostsOf(vtkHyperTreeGrid* grid)
{
  return vtkUnsignedCharArray::SafeDownCast(
      grid->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()));
}
} // namespace topology_stamp_detail

/// A new identity for a builder's stamps (one per GridBuilder, one per
/// buildHyperTreeGrid call): revisions of different builders are never compared.
inline std::uint64_t newStampBuilder()
{
  static std::atomic<std::uint64_t> next{1};
  return next++;
}

/// Writes the stamp of `grid` (borrowed) as it is now, with `revisions`.
inline void writeTopologyStamp(vtkHyperTreeGrid* grid, const StampRevisions& revisions)
{
  using namespace topology_stamp_detail;
  vtkNew<vtkTypeUInt64Array> stamp;
  stamp->SetName(topologyStampName);
  vtkBitArray* mask = grid->HasMask() ? grid->GetMask() : nullptr;
  vtkUnsignedCharArray* ghosts = ghostsOf(grid);
  const std::uint64_t header[HeaderValues] = {
      Magic,
      revisions.builder,
      address(grid),
      revisions.arrays,
      address(mask),
      mask ? mask->GetMTime() : 0,
      address(ghosts),
      ghosts ? ghosts->GetMTime() : 0,
      static_cast<std::uint64_t>(grid->GetMaxNumberOfTrees())};
  for (std::uint64_t value : header)
  {
    stamp->InsertNextValue(value);
  }
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  grid->InitializeTreeIterator(it);
  vtkIdType index = 0;
  std::uint64_t trees = 0;
  while (vtkHyperTree* tree = it.GetNextTree(index))
  {
    const auto known = revisions.trees.find(index);
    if (known == revisions.trees.end())
    {
      continue; // a tree the builder does not know: not vouched for
    }
    std::size_t size = 0;
    const unsigned int* elder = tree->GetElderChildIndexArray(size);
    const std::uint64_t values[TreeValues] = {
        static_cast<std::uint64_t>(index),
        address(tree),
        tree->GetMTime(),
        static_cast<std::uint64_t>(tree->GetNumberOfVertices()),
        address(elder),
        known->second.first,
        known->second.second};
    for (std::uint64_t value : values)
    {
      stamp->InsertNextValue(value);
    }
    ++trees;
  }
  stamp->SetValue(HeaderValues - 1, trees);
  grid->GetFieldData()->AddArray(stamp); // replaces an earlier build's
}

/// What a reader may trust of a grid's stamp.
struct TopologyStamp
{
  std::uint64_t builder = 0;
  /// The mask and ghost arrays are the ones stamped, unchanged: `arrays` holds.
  bool arraysVouched = false;
  std::uint64_t arrays = 0;
  std::unordered_map<vtkIdType, TreeStamp> trees; ///< by tree index

  /// The stamp's word on `tree` (index `index`) if it still vouches for it: the
  /// same object, modified time, vertex count and child table.
  const TreeStamp* vouchedTree(vtkIdType index, vtkHyperTree* tree) const
  {
    const auto found = this->trees.find(index);
    if (found == this->trees.end() || tree == nullptr)
    {
      return nullptr;
    }
    std::size_t size = 0;
    const unsigned int* elder = tree->GetElderChildIndexArray(size);
    const TreeStamp& s = found->second;
    using topology_stamp_detail::address;
    const bool same = s.tree == address(tree) && s.treeTime == tree->GetMTime() &&
                      s.vertices == static_cast<std::uint64_t>(tree->GetNumberOfVertices()) &&
                      s.elderChild == address(elder);
    return same ? &s : nullptr;
  }
};

/// The stamp of `grid` (borrowed), if Canopy's builder made it for this very
/// grid object; nothing otherwise (a grid Canopy did not build, or a copy).
inline std::optional<TopologyStamp> readTopologyStamp(vtkHyperTreeGrid* grid)
{
  using namespace topology_stamp_detail;
  auto* stamp =
      vtkTypeUInt64Array::SafeDownCast(grid->GetFieldData()->GetAbstractArray(topologyStampName));
  if (stamp == nullptr || stamp->GetNumberOfValues() < HeaderValues)
  {
    return std::nullopt;
  }
  std::vector<std::uint64_t> v(static_cast<std::size_t>(stamp->GetNumberOfValues()));
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    v[i] = static_cast<std::uint64_t>(stamp->GetValue(static_cast<vtkIdType>(i)));
  }
  const std::uint64_t trees = v[HeaderValues - 1];
  if (v[0] != Magic || v[2] != address(grid) ||
      static_cast<std::uint64_t>(stamp->GetNumberOfValues()) != HeaderValues + TreeValues * trees)
  {
    return std::nullopt;
  }
  TopologyStamp read;
  read.builder = v[1];
  vtkBitArray* mask = grid->HasMask() ? grid->GetMask() : nullptr;
  vtkUnsignedCharArray* ghosts = ghostsOf(grid);
  read.arraysVouched = v[4] == address(mask) && v[5] == (mask ? mask->GetMTime() : 0) &&
                       v[6] == address(ghosts) && v[7] == (ghosts ? ghosts->GetMTime() : 0);
  read.arrays = v[3];
  read.trees.reserve(static_cast<std::size_t>(trees));
  for (std::uint64_t t = 0; t < trees; ++t)
  {
    const std::uint64_t* e = v.data() + HeaderValues + TreeValues * t;
    read.trees[static_cast<vtkIdType>(e[0])] = TreeStamp{e[1], e[2], e[3], e[4], e[5], e[6]};
  }
  return read;
}

} // namespace canopy
