// VTK 9.2's "pure mask" of a hypertree grid, given rather than computed.
//
// vtkHyperTreeGrid::GetPureMask() marks a node when it is masked or, unmasked
// and refined, when one of its children is marked (interfaces aside), and
// computes it with a cursor walk over every node the first time it is asked:
// ShallowCopy asks (so does ParaView's vtkPVPostFilter after every filter), so
// each masked grid a pipeline passes on paid that walk, more than Canopy's
// selection itself. A filter that already knows the marks (the builder and
// SelectionMask do, in a reverse pass over the nodes) hands them to the grid instead.
//
// Header-only: the forest library (its builder's masks) and the filters (the
// selection's masks) both give it, and neither library links the other.
#pragma once

#include <vtkBitArray.h>
#include <vtkHyperTreeGrid.h>

namespace canopy
{

namespace detail
{

/// Reaches vtkHyperTreeGrid's protected pure-mask members (a pointer to member
/// formed in a derived class is a pointer to the base's member: well defined).
struct PureMaskOf : vtkHyperTreeGrid
{
  static void set(vtkHyperTreeGrid* grid, vtkBitArray* pure)
  {
    vtkBitArray* vtkHyperTreeGrid::*mask = &PureMaskOf::PureMask;
    bool vtkHyperTreeGrid::*initialized = &PureMaskOf::InitPureMask;
    if (pure)
    {
      pure->Register(grid);
    }
    if (vtkBitArray* old = grid->*mask)
    {
      old->UnRegister(grid);
    }
    grid->*mask = pure;
    grid->*initialized = true;
  }
};

} // namespace detail

/// Sets `pure` (one bit per cell, as GetPureMask() would compute it) as the
/// grid's pure mask; the grid holds a reference. Call after SetMask (which
/// drops any pure mask). Not for grids with interfaces (HasInterface).
inline void setPureMask(vtkHyperTreeGrid* grid, vtkBitArray* pure)
{
  detail::PureMaskOf::set(grid, pure);
}

} // namespace canopy
