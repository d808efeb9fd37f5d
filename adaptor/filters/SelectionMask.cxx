#include "SelectionMask.h"

#include "TreeTraversal.h"

#include <vtkBitArray.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <cstring>

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

} // namespace

SelectionMaskResult selectionMask(const HyperTreeAccess& grid,
                                  const std::vector<SelectedNode>& selected, bool invert,
                                  bool allowMasked)
{
  const auto& trees = grid.trees();
  // The selected nodes of each tree (selections by location come in points' order).
  std::vector<std::vector<const SelectedNode*>> byTree(trees.size());
  for (const SelectedNode& n : selected)
  {
    byTree[static_cast<std::size_t>(n.tree - trees.data())].push_back(&n);
  }
  auto hidden = [&](const TreeAccess& tree, vtkIdType node)
  {
    if (!grid.hasMask())
    {
      return false;
    }
    const vtkIdType global = tree.globalIndex(node);
    return grid.isAbsent(global) || (!allowMasked && grid.isMasked(global));
  };

  std::vector<TreeMask> masks(trees.size());
  // Per cell: bit 0 visible, bit 1 pure (VTK's pure mask, PureMask.h).
  std::vector<unsigned char> visibleCells(static_cast<std::size_t>(grid.numberOfCells()), 0);
  vtkSMPTools::For(
      0, static_cast<vtkIdType>(trees.size()),
      [&](vtkIdType begin, vtkIdType end)
      {
        std::vector<vtkIdType> stack;
        for (vtkIdType t = begin; t < end; ++t)
        {
          const TreeAccess& tree = trees[static_cast<std::size_t>(t)];
          TreeMask& mask = masks[static_cast<std::size_t>(t)];
          mask.visible.assign(static_cast<std::size_t>(tree.numberOfVertices), 0);
          auto& visible = mask.visible;
          // Selected subtrees: marked whole, but for what stays hidden.
          std::vector<unsigned char> chosen(invert ? visible.size() : 0, 0);
          for (const SelectedNode* n : byTree[static_cast<std::size_t>(t)])
          {
            if (invert)
            {
              chosen[static_cast<std::size_t>(n->node)] = 1;
              continue;
            }
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
                if (!hidden(tree, c))
                {
                  visible[static_cast<std::size_t>(c)] = 1;
                  stack.push_back(c);
                }
              }
            }
          }
          if (invert)
          {
            // The selectable leaves outside every selected subtree.
            Vec3 lo;
            Vec3 hi;
            walkTree(grid, tree,
                     [&](WalkNode& n)
                     {
                       if (chosen[static_cast<std::size_t>(n.node)] || hidden(tree, n.node))
                       {
                         return WalkStep::Skip;
                       }
                       if (tree.isLeaf(n.node))
                       {
                         visible[static_cast<std::size_t>(n.node)] = 1;
                         grid.nodeBounds(tree, n.level, n.ijk, lo, hi);
                         mask.include(lo, hi);
                         return WalkStep::Skip;
                       }
                       return WalkStep::Descend;
                     });
          }
          // Ancestors: children follow their parents in local order.
          for (vtkIdType n = tree.numberOfVertices; n-- > 0;)
          {
            auto& here = visible[static_cast<std::size_t>(n)];
            if (here || tree.isLeaf(n))
            {
              continue;
            }
            if (tree.hasAbsentDescendant(n))
            {
              here = 1; // another rank's parts below: never hidden here
              continue;
            }
            const vtkIdType first = tree.firstChild(n);
            for (vtkIdType c = first; c < first + grid.childrenPerNode() && !here; ++c)
            {
              here = visible[static_cast<std::size_t>(c)];
            }
          }
          // Pure: hidden, or visible, refined and with a pure child; children
          // first (reverse order). Nodes below a hidden one keep 0, as VTK's walk
          // never reaches them.
          std::vector<unsigned char> pure(visible.size(), 0);
          for (vtkIdType n = tree.numberOfVertices; n-- > 0;)
          {
            const auto k = static_cast<std::size_t>(n);
            if (!visible[k] || tree.isLeaf(n))
            {
              pure[k] = !visible[k];
              continue;
            }
            const vtkIdType first = tree.firstChild(n);
            for (vtkIdType c = first; c < first + grid.childrenPerNode() && !pure[k]; ++c)
            {
              pure[k] = pure[static_cast<std::size_t>(c)];
            }
          }
          for (vtkIdType n = 0; n < tree.numberOfVertices; ++n)
          {
            const auto k = static_cast<std::size_t>(n);
            visibleCells[static_cast<std::size_t>(tree.globalIndex(n))] =
                static_cast<unsigned char>(visible[k] | (pure[k] << 1));
          }
          std::vector<unsigned char>().swap(visible);
        }
      });

  SelectionMaskResult result;
  result.bounds = {{1e300, -1e300, 1e300, -1e300, 1e300, -1e300}};
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

} // namespace canopy
