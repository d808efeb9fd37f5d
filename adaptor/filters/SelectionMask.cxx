#include "SelectionMask.h"

#include "SelectionMaskMemo.h"

#include "TreeProgress.h"
#include "TreeTraversal.h"

#include <vtkBitArray.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <cstring>
#include <functional>

namespace canopy
{

namespace
{

/// Completes a tree's flags from its marks, in one reverse pass (children
/// follow their parents in local order): ancestors of visible nodes become
/// visible (and so do nodes with other ranks' parts below), then VTK's pure
/// mark: hidden, or refined with a marked child. Nodes below a hidden one keep
/// whatever they have: VTK's walk never reaches them. Bit 0 visible, bit 1 pure.
void completeFlags(const HyperTreeAccess& grid, const TreeAccess& tree, SelectionTreeFlags& mask)
{
  auto& visible = mask.flags;
  const int children = grid.childrenPerNode();
  for (vtkIdType n = tree.numberOfVertices; n-- > 0;)
  {
    auto& flags = visible[static_cast<std::size_t>(n)];
    if (tree.isLeaf(n))
    {
      flags = static_cast<unsigned char>(flags ? 1 : 2);
      continue;
    }
    const vtkIdType first = tree.firstChild(n);
    unsigned char below = 0;
    for (vtkIdType c = first; c < first + children; ++c)
    {
      below |= visible[static_cast<std::size_t>(c)];
    }
    const bool shown = flags || (below & 1) || tree.hasAbsentDescendant(n);
    flags = static_cast<unsigned char>(shown ? 1 | (below & 2) : 2);
  }
}

/// The mask's common part. `markTree(t, tree, mask)` marks tree t's visible
/// selected nodes (with their subtrees) in mask.flags and their bounds, and
/// returns false; or writes the final flags itself and returns true. The
/// ancestors, the nodes above other ranks' parts, the pure mask and the packing
/// are the same for every way of selecting. Trees the memo keeps are not
/// marked again.
template <typename MarkTree>
SelectionMaskResult buildSelectionMask(const HyperTreeAccess& grid, const ProgressShare& progress,
                                       SelectionMaskMemo& kept, const MarkTree& markTree)
{
  const auto& trees = grid.trees();
  const bool done =
      forEachTree(progress, static_cast<vtkIdType>(trees.size()),
                  [&](vtkIdType t)
                  {
                    const auto position = static_cast<std::size_t>(t);
                    if (kept.kept(position))
                    {
                      return;
                    }
                    const TreeAccess& tree = trees[position];
                    SelectionTreeFlags& mask = kept.tree(position);
                    mask = SelectionTreeFlags();
                    mask.flags.assign(static_cast<std::size_t>(tree.numberOfVertices), 0);
                    if (!markTree(position, tree, mask))
                    {
                      completeFlags(grid, tree, mask);
                    }
                  });
  SelectionMaskResult result;
  result.bounds = {{1e300, -1e300, 1e300, -1e300, 1e300, -1e300}};
  if (!done)
  {
    kept.clear(); // stopped: no mask, and nothing half-made kept
    return result;
  }
  for (std::size_t t = 0; t < trees.size(); ++t)
  {
    const SelectionTreeFlags& mask = kept.tree(t);
    for (int a = 0; a < 3; ++a)
    {
      result.bounds[2 * a] = std::min(result.bounds[2 * a], mask.bounds[2 * a]);
      result.bounds[2 * a + 1] = std::max(result.bounds[2 * a + 1], mask.bounds[2 * a + 1]);
    }
  }
  kept.pack(grid, result.mask, result.pure);
  return result;
}

/// Marks the selectable leaves of a tree for which pick(node) holds, with their
/// bounds; subtrees whose root `skip` flags are left out.
template <typename Pick>
void markLeaves(const HyperTreeAccess& grid, const TreeAccess& tree, bool allowMasked,
                SelectionTreeFlags& mask, const Pick& pick,
                const std::vector<unsigned char>* skip = nullptr)
{
  Vec3 lo;
  Vec3 hi;
  walkTree(grid, tree,
           [&](WalkNode& n)
           {
             if ((skip && (*skip)[static_cast<std::size_t>(n.node)]) ||
                 unselectable(grid, tree, n.node, allowMasked))
             {
               return WalkStep::Skip;
             }
             if (!tree.isLeaf(n.node))
             {
               return WalkStep::Descend;
             }
             if (pick(n.node))
             {
               mask.flags[static_cast<std::size_t>(n.node)] = 1;
               grid.nodeBounds(tree, n.level, n.ijk, lo, hi);
               mask.include(lo, hi);
             }
             return WalkStep::Skip;
           });
}

} // namespace

SelectionMaskResult selectionMask(const HyperTreeAccess& grid,
                                  const std::vector<SelectedNode>& selected, bool invert,
                                  bool allowMasked, SelectionMaskMemo& memo,
                                  const ProgressShare& progress)
{
  const auto& trees = grid.trees();
  // The selected nodes of each tree (selections by location come in points' order).
  std::vector<std::vector<const SelectedNode*>> byTree(trees.size());
  for (const SelectedNode& n : selected)
  {
    byTree[static_cast<std::size_t>(n.tree - trees.data())].push_back(&n);
  }
  return buildSelectionMask(grid, progress, memo,
                            [&](std::size_t t, const TreeAccess& tree, SelectionTreeFlags& mask)
                            {
                              auto& visible = mask.flags;
                              if (invert)
                              {
                                // The selectable leaves outside every selected subtree.
                                std::vector<unsigned char> chosen(visible.size(), 0);
                                for (const SelectedNode* n : byTree[t])
                                {
                                  chosen[static_cast<std::size_t>(n->node)] = 1;
                                }
                                markLeaves(
                                    grid, tree, allowMasked, mask, [](vtkIdType) { return true; },
                                    &chosen);
                                return false;
                              }
                              // Selected subtrees: marked whole, but for what stays hidden.
                              std::vector<vtkIdType> stack;
                              for (const SelectedNode* n : byTree[t])
                              {
                                Vec3 lo;
                                Vec3 hi;
                                grid.nodeBounds(tree, n->level, n->ijk, lo, hi);
                                mask.include(lo, hi);
                                visible[static_cast<std::size_t>(n->node)] = 1;
                                stack.assign(1, n->node);
                                while (!stack.empty())
                                {
                                  const vtkIdType m = stack.back();
                                  stack.pop_back();
                                  if (tree.isLeaf(m))
                                  {
                                    continue;
                                  }
                                  for (vtkIdType c = tree.firstChild(m);
                                       c < tree.firstChild(m) + grid.childrenPerNode(); ++c)
                                  {
                                    if (!unselectable(grid, tree, c, allowMasked))
                                    {
                                      visible[static_cast<std::size_t>(c)] = 1;
                                      stack.push_back(c);
                                    }
                                  }
                                }
                              }
                              return false;
                            });
}

SelectionMaskResult selectionMaskOfLeaves(const HyperTreeAccess& grid,
                                          const std::function<bool(vtkIdType)>& picked, bool invert,
                                          bool allowMasked, SelectionMaskMemo& memo,
                                          const ProgressShare& progress)
{
  return buildSelectionMask(grid, progress, memo,
                            [&](std::size_t, const TreeAccess& tree, SelectionTreeFlags& mask)
                            {
                              markLeaves(grid, tree, allowMasked, mask,
                                         [&](vtkIdType node)
                                         { return picked(tree.globalIndex(node)) != invert; });
                              return false;
                            });
}

namespace
{

/// Whether a tree has a cell that stays hidden in a selected subtree.
bool hasHiddenCell(const HyperTreeAccess& grid, const TreeAccess& tree, bool allowMasked)
{
  for (vtkIdType n = 0; grid.hasMask() && n < tree.numberOfVertices; ++n)
  {
    if (unselectable(grid, tree, n, allowMasked))
    {
      return true;
    }
  }
  return false;
}

/// Marks the leaves of a tree the region selects (overlapping it; inverted, not
/// overlapping it) with their bounds; returns whether it wrote final flags.
bool markRegion(const HyperTreeAccess& grid, const TreeAccess& tree, const SelectionRegion& region,
                bool invert, bool allowMasked, SelectionTreeFlags& mask, std::size_t& examined)
{
  Vec3 lo;
  Vec3 hi;
  // A tree the region misses or holds whole, with no hidden cell, is selected
  // whole or not at all: its flags without a walk (every node visible and
  // unmarked, or hidden and marked pure).
  grid.nodeBounds(tree, 0, {{0, 0, 0}}, lo, hi);
  ++examined;
  const bool misses = region.empty || !region.overlaps(lo, hi);
  if ((misses || region.contains(lo, hi)) && !hasHiddenCell(grid, tree, allowMasked))
  {
    const bool selected = misses == invert;
    std::fill(mask.flags.begin(), mask.flags.end(), selected ? 1 : 2);
    if (selected)
    {
      mask.include(lo, hi);
    }
    return true;
  }
  // Otherwise leaf by leaf, descending only into nodes that overlap the region
  // (inverted: into every node; a leaf that misses it is selected).
  walkTree(grid, tree,
           [&](WalkNode& n)
           {
             ++examined;
             if (unselectable(grid, tree, n.node, allowMasked))
             {
               return WalkStep::Skip;
             }
             grid.nodeBounds(tree, n.level, n.ijk, lo, hi);
             const bool overlaps = !region.empty && region.overlaps(lo, hi);
             if (!overlaps && !invert)
             {
               return WalkStep::Skip; // nothing below can overlap: children lie inside
             }
             if (tree.isLeaf(n.node))
             {
               if (overlaps != invert)
               {
                 mask.flags[static_cast<std::size_t>(n.node)] = 1;
                 mask.include(lo, hi);
               }
               return WalkStep::Skip;
             }
             return WalkStep::Descend;
           });
  return false;
}

} // namespace

SelectionMaskResult selectionMaskOfRegion(const HyperTreeAccess& grid,
                                          const SelectionRegion& region, bool invert,
                                          bool allowMasked, SelectionMaskMemo& memo,
                                          std::size_t& visited, const ProgressShare& progress)
{
  std::vector<std::size_t> examined(grid.trees().size(), 0);
  SelectionMaskResult result = buildSelectionMask(
      grid, progress, memo,
      [&](std::size_t t, const TreeAccess& tree, SelectionTreeFlags& mask)
      { return markRegion(grid, tree, region, invert, allowMasked, mask, examined[t]); });
  for (std::size_t n : examined)
  {
    visited += n;
  }
  return result;
}

} // namespace canopy
