// One explicit, callback-driven depth-first walk over a hypertree (in the spirit
// of p4est_iterate): the caller says, on entering each node, whether to descend
// into its children, skip them, or stop the walk. Children are entered in
// order (0 .. f^d - 1), so the order of what a caller collects is deterministic.
#pragma once

#include "HyperTreeAccess.h"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace canopy
{

/// A node as the walk enters it: its local index, level, integer position at its
/// level, and one bit the caller may set for the node's subtree (for example
/// "an ancestor is hidden"), inherited by its children.
struct WalkNode
{
  vtkIdType node;
  int level;
  std::array<std::int64_t, 3> ijk;
  bool inherited = false;
};

enum class WalkStep
{
  Descend, ///< enter the children (ignored at a leaf)
  Skip,    ///< not the children
  Stop     ///< end the walk
};

/// Calls enter(WalkNode&) on every node reached from `start` (its subtree);
/// enter may set `inherited` for the children. Only children c of a node n for
/// which acceptChild(n, c) holds are entered (a slice enters only the children
/// its plane crosses). Returns false when enter stopped the walk.
template <typename Enter, typename AcceptChild>
bool walkSubtree(const HyperTreeAccess& grid, const TreeAccess& tree, const WalkNode& start,
                 Enter&& enter, AcceptChild&& acceptChild)
{
  std::vector<WalkNode> stack;
  return walkSubtree(grid, tree, start, std::forward<Enter>(enter),
                     std::forward<AcceptChild>(acceptChild), stack);
}

/// The same with the caller's stack (cleared first): a caller walking many small
/// subtrees keeps one, allocated once.
template <typename Enter, typename AcceptChild>
bool walkSubtree(const HyperTreeAccess& grid, const TreeAccess& tree, const WalkNode& start,
                 Enter&& enter, AcceptChild&& acceptChild, std::vector<WalkNode>& stack)
{
  stack.assign(1, start);
  while (!stack.empty())
  {
    WalkNode n = stack.back();
    stack.pop_back();
    const WalkStep step = enter(n);
    if (step == WalkStep::Stop)
    {
      return false;
    }
    if (step == WalkStep::Skip || tree.isLeaf(n.node))
    {
      continue;
    }
    const vtkIdType first = tree.firstChild(n.node);
    // Pushed in reverse: children are entered in order.
    for (int c = grid.childrenPerNode(); c-- > 0;)
    {
      if (acceptChild(n, c))
      {
        stack.push_back({first + c, n.level + 1, grid.childPosition(n.ijk, c), n.inherited});
      }
    }
  }
  return true;
}

/// The deepest level of `tree` (its vtkHyperTree's count, within what integer
/// positions address): what a walk's per-level state is sized for, rather than
/// every level a grid can address (a walk per tree would allocate those).
inline int deepestLevel(const HyperTreeAccess& grid, const TreeAccess& tree)
{
  const int levels = tree.tree ? static_cast<int>(tree.tree->GetNumberOfLevels()) : 0;
  return levels > 0 && levels <= grid.maxLevel() ? levels - 1 : grid.maxLevel();
}

/// The whole tree, from its root.
template <typename Enter, typename AcceptChild>
bool walkTree(const HyperTreeAccess& grid, const TreeAccess& tree, Enter&& enter,
              AcceptChild&& acceptChild)
{
  return walkSubtree(grid, tree, WalkNode{0, 0, {{0, 0, 0}}, false}, std::forward<Enter>(enter),
                     std::forward<AcceptChild>(acceptChild));
}

/// Every child of every node the walk descends into.
template <typename Enter>
bool walkTree(const HyperTreeAccess& grid, const TreeAccess& tree, Enter&& enter)
{
  return walkTree(grid, tree, std::forward<Enter>(enter),
                  [](const WalkNode&, int) { return true; });
}

} // namespace canopy
