#include "SelectionMask.h"

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

/// Per-tree work: which local nodes are visible, and the selected leaves' bounds.
struct TreeMask
{
  std::vector<unsigned char> visible;
  std::array<double, 6> bounds{{1e300, -1e300, 1e300, -1e300, 1e300, -1e300}};

  void include(const Vec3& lo, const Vec3& hi)
  {
    for (int a = 0; a < 3; ++a)
    {
      bounds[2 * a] = std::min(bounds[2 * a], lo[a]);
      bounds[2 * a + 1] = std::max(bounds[2 * a + 1], hi[a]);
    }
  }
};

/// The mask's common part. `markTree(t, tree, mask)` marks tree t's visible
/// selected nodes (with their subtrees) in mask.visible and their bounds; the
/// ancestors, the nodes above other ranks' parts, the pure mask and the packing
/// are the same for every way of selecting.
template <typename MarkTree>
SelectionMaskResult buildSelectionMask(const HyperTreeAccess& grid, const ProgressShare& progress,
                                       const MarkTree& markTree)
{
  const auto& trees = grid.trees();
  std::vector<TreeMask> masks(trees.size());
  // Per cell: bit 0 visible, bit 1 pure (VTK's pure mask, PureMask.h).
  std::vector<unsigned char> visibleCells(static_cast<std::size_t>(grid.numberOfCells()), 0);
  const bool done = forEachTree(
      progress, static_cast<vtkIdType>(trees.size()),
      [&](vtkIdType t)
      {
        const TreeAccess& tree = trees[static_cast<std::size_t>(t)];
        TreeMask& mask = masks[static_cast<std::size_t>(t)];
        mask.visible.assign(static_cast<std::size_t>(tree.numberOfVertices), 0);
        auto& visible = mask.visible;
        markTree(static_cast<std::size_t>(t), tree, mask);
        // One reverse pass (children follow their parents in local order):
        // ancestors of visible nodes become visible (and so do nodes with
        // other ranks' parts below), then VTK's pure mark: hidden, or refined
        // with a marked child. Nodes below a hidden one keep whatever they
        // have: VTK's walk never reaches them. Bit 0 visible, bit 1 pure.
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
        if (tree.implicitGlobalIndex)
        {
          std::copy(visible.begin(), visible.end(),
                    visibleCells.begin() + static_cast<std::ptrdiff_t>(tree.globalIndexStart));
        }
        else
        {
          for (vtkIdType n = 0; n < tree.numberOfVertices; ++n)
          {
            visibleCells[static_cast<std::size_t>(tree.globalIndex(n))] =
                visible[static_cast<std::size_t>(n)];
          }
        }
        std::vector<unsigned char>().swap(visible);
      });
  SelectionMaskResult result;
  result.bounds = {{1e300, -1e300, 1e300, -1e300, 1e300, -1e300}};
  if (!done)
  {
    return result; // stopped: no mask
  }
  for (const TreeMask& mask : masks)
  {
    for (int a = 0; a < 3; ++a)
    {
      result.bounds[2 * a] = std::min(result.bounds[2 * a], mask.bounds[2 * a]);
      result.bounds[2 * a + 1] = std::max(result.bounds[2 * a + 1], mask.bounds[2 * a + 1]);
    }
  }
  // Packed eight cells a byte, most significant bit first (vtkBitArray's order);
  // cells of no tree (none here) stay masked.
  result.mask = vtkSmartPointer<vtkBitArray>::New();
  result.mask->SetName("vtkHyperTreeGridMask");
  result.pure = vtkSmartPointer<vtkBitArray>::New();
  const vtkIdType cells = grid.numberOfCells();
  result.mask->SetNumberOfValues(cells);
  result.pure->SetNumberOfValues(cells);
  unsigned char* maskBits = result.mask->GetPointer(0);
  unsigned char* pureBits = result.pure->GetPointer(0);
  vtkSMPTools::For(0, (cells + 7) / 8,
                   [&](vtkIdType begin, vtkIdType end)
                   {
                     for (vtkIdType byte = begin; byte < end; ++byte)
                     {
                       unsigned char masked = 0;
                       unsigned char pure = 0;
                       for (vtkIdType bit = 0; bit < 8; ++bit)
                       {
                         const vtkIdType cell = 8 * byte + bit;
                         const unsigned char flags =
                             cell < cells ? visibleCells[static_cast<std::size_t>(cell)] : 2;
                         masked = static_cast<unsigned char>(masked | (!(flags & 1) << (7 - bit)));
                         pure =
                             static_cast<unsigned char>(pure | (((flags >> 1) & 1) << (7 - bit)));
                       }
                       maskBits[byte] = masked;
                       pureBits[byte] = pure;
                     }
                   });
  result.mask->Modified();
  result.pure->Modified();
  return result;
}

/// Whether a node stays hidden in a selected subtree: absent always, masked
/// unless masked cells may be selected.
bool hiddenNode(const HyperTreeAccess& grid, const TreeAccess& tree, vtkIdType node,
                bool allowMasked)
{
  if (!grid.hasMask())
  {
    return false;
  }
  const vtkIdType global = tree.globalIndex(node);
  return grid.isAbsent(global) || (!allowMasked && grid.isMasked(global));
}

/// Marks the selectable leaves of a tree for which pick(node) holds, with their
/// bounds; subtrees whose root `skip` flags are left out.
template <typename Pick>
void markLeaves(const HyperTreeAccess& grid, const TreeAccess& tree, bool allowMasked,
                TreeMask& mask, const Pick& pick, const std::vector<unsigned char>* skip = nullptr)
{
  Vec3 lo;
  Vec3 hi;
  walkTree(grid, tree,
           [&](WalkNode& n)
           {
             if ((skip && (*skip)[static_cast<std::size_t>(n.node)]) ||
                 hiddenNode(grid, tree, n.node, allowMasked))
             {
               return WalkStep::Skip;
             }
             if (!tree.isLeaf(n.node))
             {
               return WalkStep::Descend;
             }
             if (pick(n.node))
             {
               mask.visible[static_cast<std::size_t>(n.node)] = 1;
               grid.nodeBounds(tree, n.level, n.ijk, lo, hi);
               mask.include(lo, hi);
             }
             return WalkStep::Skip;
           });
}

} // namespace

SelectionMaskResult selectionMask(const HyperTreeAccess& grid,
                                  const std::vector<SelectedNode>& selected, bool invert,
                                  bool allowMasked, const ProgressShare& progress)
{
  const auto& trees = grid.trees();
  // The selected nodes of each tree (selections by location come in points' order).
  std::vector<std::vector<const SelectedNode*>> byTree(trees.size());
  for (const SelectedNode& n : selected)
  {
    byTree[static_cast<std::size_t>(n.tree - trees.data())].push_back(&n);
  }
  return buildSelectionMask(grid, progress,
                            [&](std::size_t t, const TreeAccess& tree, TreeMask& mask)
                            {
                              auto& visible = mask.visible;
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
                                return;
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
                                    if (!hiddenNode(grid, tree, c, allowMasked))
                                    {
                                      visible[static_cast<std::size_t>(c)] = 1;
                                      stack.push_back(c);
                                    }
                                  }
                                }
                              }
                            });
}

SelectionMaskResult selectionMaskOfLeaves(const HyperTreeAccess& grid,
                                          const std::function<bool(vtkIdType)>& picked, bool invert,
                                          bool allowMasked, const ProgressShare& progress)
{
  return buildSelectionMask(grid, progress,
                            [&](std::size_t, const TreeAccess& tree, TreeMask& mask)
                            {
                              markLeaves(grid, tree, allowMasked, mask,
                                         [&](vtkIdType node)
                                         { return picked(tree.globalIndex(node)) != invert; });
                            });
}

} // namespace canopy
