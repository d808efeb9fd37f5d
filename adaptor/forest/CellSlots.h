// Which VTK cell (global index) each described node is, and which storage slot
// holds its values.
//
// Cells are numbered breadth-first over every described node, tree by tree:
// VTK's implicit global indices (one offset per tree, no per-node table, which
// costs 15-19 ns per node in Debian's VTK). With the default storage (slots
// breadth-first, no absent node) a cell *is* its slot and fields are plain VTK
// arrays over the simulation's memory. Otherwise (a slot map, or absent nodes of
// trees split between ranks) fields read their values through a cell -> slot
// table in which absent cells have no slot.
#pragma once

#include "ForestLayout.h"
#include "FreshMemory.h"
#include "StorageSlots.h"
#include <canopy/ForestDescription.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace canopy
{

struct CellSlots
{
  /// Entry of an absent cell in slotOfCell.
  static constexpr std::int64_t NoSlot = -1;
  /// Cell -> slot (NoSlot for absent cells); null when every cell is its own slot.
  std::shared_ptr<const IndexTable> slotOfCell;

  bool identity() const { return !slotOfCell; }

  /// One pass over the nodes when the forest has absent nodes; nothing otherwise.
  static CellSlots build(const ForestDescription& forest, const ForestLayout& layout);
};

/// The cell (VTK global index) of a node; see CellSlots.
inline std::size_t cellIndex(const TreeLayout& shape, std::size_t node)
{
  return shape.firstCell + node;
}

/// Whether every cell is its own storage slot (no table needed).
inline bool cellsAreSlots(const ForestLayout& layout)
{
  return !layout.explicitSlots && !layout.anyAbsent;
}

inline bool isAbsent(const TreeDescription& tree, std::size_t node)
{
  return tree.absent != nullptr && tree.absent[node] != 0;
}

} // namespace canopy
