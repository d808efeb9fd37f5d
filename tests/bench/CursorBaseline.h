// What the wrap benchmarks share: the pieces of the "cursor + copy" baseline (what
// a user writes without Canopy: an empty vtkHyperTreeGrid with the forest's root
// grid, a vtkHyperTreeGridNonOrientedCursor that SubdivideLeaf's where the
// simulation refined, every value copied into new VTK arrays), the check that two
// grids hold the same topology and values, and the heap measure.
// Used by WrapBenchmark.cxx and BlockForestBenchmark.cxx.
#pragma once

#include <canopy/ForestDescription.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkHyperTreeGridNonOrientedCursor.h>
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <malloc.h>

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace canopy::bench
{

/// Heap bytes in use (small blocks + mmapped blocks), every arena.
inline std::size_t heapInUse()
{
  const struct mallinfo2 info = mallinfo2();
  return info.uordblks + info.hblkhd;
}

/// An empty grid with the forest's root grid (coordinates copied).
inline vtkSmartPointer<vtkHyperTreeGrid> emptyGridLike(const canopy::ForestDescription& d)
{
  auto htg = vtkSmartPointer<vtkHyperTreeGrid>::New();
  const auto& g = d.rootGrid;
  htg->SetDimensions(static_cast<unsigned>(g.pointsX), static_cast<unsigned>(g.pointsY),
                     static_cast<unsigned>(g.pointsZ));
  htg->SetBranchFactor(static_cast<unsigned>(d.branchFactor));
  for (int a = 0; a < 3; ++a)
  {
    const double* c = a == 0 ? g.x : a == 1 ? g.y : g.z;
    const std::size_t n = a == 0 ? g.pointsX : a == 1 ? g.pointsY : g.pointsZ;
    vtkNew<vtkDoubleArray> coords;
    coords->SetNumberOfTuples(static_cast<vtkIdType>(n));
    std::copy(c, c + n, coords->GetPointer(0));
    a == 0   ? htg->SetXCoordinates(coords)
    : a == 1 ? htg->SetYCoordinates(coords)
             : htg->SetZCoordinates(coords);
  }
  return htg;
}

/// Both grids must hold the same values at the same nodes, or the timing means
/// nothing: walks both with cursors in step, comparing leaves and values, over
/// every tree of `a`, or only the trees (root indices) in `only`.
inline bool sameContent(vtkHyperTreeGrid* a, vtkHyperTreeGrid* b,
                        const std::vector<std::string>& names,
                        const std::vector<vtkIdType>* only = nullptr)
{
  vtkHyperTreeGrid::vtkHyperTreeGridIterator trees;
  a->InitializeTreeIterator(trees);
  vtkIdType index = 0;
  vtkNew<vtkHyperTreeGridNonOrientedCursor> ca;
  vtkNew<vtkHyperTreeGridNonOrientedCursor> cb;
  bool same = true;
  int checked = 0;
  std::vector<vtkDataArray*> fa;
  std::vector<vtkDataArray*> fb;
  for (const auto& name : names)
  {
    fa.push_back(a->GetCellData()->GetArray(name.c_str()));
    fb.push_back(b->GetCellData()->GetArray(name.c_str()));
    if (!fa.back() || !fb.back())
    {
      return false;
    }
  }
  while (trees.GetNextTree(index) && same)
  {
    if (only && std::find(only->begin(), only->end(), index) == only->end())
    {
      continue;
    }
    a->InitializeNonOrientedCursor(ca, index);
    b->InitializeNonOrientedCursor(cb, index);
    auto walk = [&](auto& self) -> void
    {
      for (std::size_t f = 0; f < fa.size(); ++f)
      {
        for (int c = 0; c < fa[f]->GetNumberOfComponents(); ++c)
        {
          same = same && fa[f]->GetComponent(ca->GetGlobalNodeIndex(), c) ==
                             fb[f]->GetComponent(cb->GetGlobalNodeIndex(), c);
        }
      }
      ++checked;
      same = same && ca->IsLeaf() == cb->IsLeaf();
      if (!same || ca->IsLeaf())
      {
        return;
      }
      for (unsigned char c = 0; c < ca->GetNumberOfChildren(); ++c)
      {
        ca->ToChild(c);
        cb->ToChild(c);
        self(self);
        ca->ToParent();
        cb->ToParent();
      }
    };
    walk(walk);
  }
  return same && checked > 0;
}

} // namespace canopy::bench
