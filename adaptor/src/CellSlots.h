// Which VTK cell (global index) each described node is, and which storage slot
// holds its values.
//
// Without absent nodes a node's cell *is* its storage slot: VTK reads the
// simulation's arrays directly (one offset per tree for breadth-first storage,
// VTK's per-node table for slot maps). A forest with absent nodes (trees split
// between ranks) has cells the simulation holds no values for, so cells are
// numbered breadth-first over every described node instead (implicit in VTK, no
// table) and fields read their values through a cell -> slot table in which
// absent cells have no slot.
#pragma once

#include "StorageSlots.h"
#include "canopy/ForestDescription.h"
#include "canopy/ForestValidation.h"

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
  std::shared_ptr<const std::vector<std::int64_t>> slotOfCell;

  bool identity() const { return !slotOfCell; }

  /// One pass over the nodes when the forest has absent nodes; nothing otherwise.
  static CellSlots build(const ForestDescription& forest, const ForestLayout& layout);
};

/// The cell (VTK global index) of a node; see CellSlots.
inline std::size_t cellIndex(const ForestLayout& layout, const TreeDescription& tree,
                             const TreeLayout& shape, std::size_t node)
{
  return layout.anyAbsent ? shape.firstCell + node : storageSlot(tree, shape, node);
}

inline bool isAbsent(const TreeDescription& tree, std::size_t node)
{
  return tree.absent != nullptr && tree.absent[node] != 0;
}

} // namespace canopy
