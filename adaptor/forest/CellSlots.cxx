#include "CellSlots.h"

namespace canopy
{

CellSlots CellSlots::build(const ForestDescription& forest, const ForestLayout& layout)
{
  CellSlots slots;
  if (cellsAreSlots(layout))
  {
    return slots;
  }
  auto table = std::make_shared<IndexTable>(layout.totalNodes);
  std::int64_t* slotOfCell = table->data();
  for (std::size_t t = 0; t < forest.trees.size(); ++t)
  {
    const TreeDescription& tree = forest.trees[t];
    const TreeLayout& shape = layout.trees[t];
    std::int64_t* cells = slotOfCell + shape.firstCell;
    // Default storage: present nodes breadth-first, trees back to back.
    auto next = static_cast<std::int64_t>(shape.firstSlot);
    for (std::size_t n = 0; n < shape.numberOfNodes; ++n)
    {
      if (isAbsent(tree, n))
      {
        cells[n] = NoSlot;
      }
      else
      {
        cells[n] = tree.storageSlots ? tree.storageSlots[n] : next++;
      }
    }
  }
  slots.slotOfCell = std::move(table);
  return slots;
}

} // namespace canopy
