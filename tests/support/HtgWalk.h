// Walks a vtkHyperTreeGrid tree with a cursor while tracking each node's
// breadth-first number, so tests can compare VTK's view with the simulation's.
#pragma once

#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedGeometryCursor.h>
#include <vtkNew.h>

#include <cstdint>
#include <vector>

namespace canopy::testing
{

/// Calls visit(cursor, breadthFirstNode) for every node of the tree at rootIndex
/// that a cursor can reach: VTK's cursors never descend below a masked node.
/// `refinement` is the simulation's breadth-first refinement bytes for that tree.
template <typename Visit>
void forEachNode(vtkHyperTreeGrid* htg, vtkIdType rootIndex,
                 const std::vector<std::uint8_t>& refinement, std::size_t children, Visit&& visit)
{
  std::vector<std::size_t> firstChild(refinement.size(), 0);
  std::size_t next = 1;
  for (std::size_t n = 0; n < refinement.size(); ++n)
  {
    if (refinement[n])
    {
      firstChild[n] = next;
      next += children;
    }
  }
  vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> cursor;
  htg->InitializeNonOrientedGeometryCursor(cursor, rootIndex);
  // Explicit recursion through a small lambda keeps the cursor shared.
  auto walk = [&](auto& self, std::size_t node) -> void
  {
    visit(cursor.GetPointer(), node);
    if (cursor->IsLeaf() || cursor->IsMasked())
    {
      return;
    }
    for (unsigned char c = 0; c < cursor->GetNumberOfChildren(); ++c)
    {
      cursor->ToChild(c);
      self(self, firstChild[node] + c);
      cursor->ToParent();
    }
  };
  walk(walk, 0);
}

/// Calls visit(cursor, ancestors) for every node VTK's cursors reach, masked ones
/// included (but nothing below a masked node), over all trees; `ancestors` holds
/// the global indices of the node's ancestors, root first.
template <typename Visit>
void forEachReachableNode(vtkHyperTreeGrid* htg, Visit&& visit)
{
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  htg->InitializeTreeIterator(it);
  vtkIdType index = 0;
  while (it.GetNextTree(index))
  {
    vtkNew<vtkHyperTreeGridNonOrientedGeometryCursor> cursor;
    htg->InitializeNonOrientedGeometryCursor(cursor, index);
    std::vector<vtkIdType> ancestors;
    auto walk = [&](auto& self) -> void
    {
      visit(cursor.GetPointer(), static_cast<const std::vector<vtkIdType>&>(ancestors));
      if (cursor->IsMasked() || cursor->IsLeaf())
      {
        return;
      }
      ancestors.push_back(cursor->GetGlobalNodeIndex());
      for (unsigned char c = 0; c < cursor->GetNumberOfChildren(); ++c)
      {
        cursor->ToChild(c);
        self(self);
        cursor->ToParent();
      }
      ancestors.pop_back();
    };
    walk(walk);
  }
}

/// Calls visit(cursor) for every node with no masked ancestor and not masked
/// itself (coarse nodes and leaves), over all trees, by VTK's own cursors: the
/// independent reference the filter tests compare against.
template <typename Visit>
void forEachVisibleNode(vtkHyperTreeGrid* htg, Visit&& visit)
{
  forEachReachableNode(
      htg,
      [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor, const std::vector<vtkIdType>&)
      {
        if (!cursor->IsMasked())
        {
          visit(cursor);
        }
      });
}

/// The same, for visible leaves only.
template <typename Visit>
void forEachVisibleLeaf(vtkHyperTreeGrid* htg, Visit&& visit)
{
  forEachVisibleNode(htg,
                     [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
                     {
                       if (cursor->IsLeaf())
                       {
                         visit(cursor);
                       }
                     });
}

/// A visible leaf as VTK's cursors see it.
struct LeafBox
{
  vtkIdType global;
  double bounds[6];
  unsigned int level;
};

/// Every visible leaf (no masked ancestor), in tree order.
inline std::vector<LeafBox> visibleLeafBoxes(vtkHyperTreeGrid* htg)
{
  std::vector<LeafBox> leaves;
  forEachVisibleLeaf(htg,
                     [&](vtkHyperTreeGridNonOrientedGeometryCursor* cursor)
                     {
                       LeafBox leaf;
                       leaf.global = cursor->GetGlobalNodeIndex();
                       cursor->GetBounds(leaf.bounds);
                       leaf.level = cursor->GetLevel();
                       leaves.push_back(leaf);
                     });
  return leaves;
}

} // namespace canopy::testing
