// A leaf's field gradient, estimated from the leaves across its faces: what a
// boundary dual vertex's value is extrapolated with (DualCellContour.h).
//
// Least squares over the visible face neighbours (the leaf across each face at
// the face's lowest corner, and at its highest where finer leaves meet it; in
// the same tree or the next one, coarser, as large or finer): g minimises sum (f_n - f_leaf - g .
// (c_n - c_leaf))^2. A linear field is reproduced exactly (to rounding) whenever the neighbours'
// offsets span the grid's dimension, which a leaf has unless masks or missing trees surround it;
// then the gradient is 0 (constant extrapolation).
//
// Tested through the contour: *.LinearField* in tests/unit/ContourTest.cxx (a
// linear field's contour exact up to the domain's boundary, binary and ternary).
#pragma once

#include "ContourField.h"
#include "DualTraversal.h"

#include <array>

namespace canopy
{

/// Centre of a node (the flat axis of a 2D grid: its single coordinate).
inline std::array<double, 3> nodeCentre(const HyperTreeAccess& grid, const DualNode& n)
{
  std::array<double, 3> lo;
  std::array<double, 3> hi;
  grid.nodeBounds(*n.tree, n.level, n.ijk, lo, hi);
  return {{0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])}};
}

class LeafGradient
{
public:
  /// Everything is borrowed and must outlive this.
  LeafGradient(const HyperTreeAccess& grid, const DualTraversal& dual, const ContourField& field)
      : Grid(grid), Dual(dual), Field(field)
  {
  }

  /// The gradient at `leaf` (a visible leaf), 3D (0 along a flat axis).
  std::array<double, 3> at(const DualNode& leaf) const;

  /// The visible leaf across `leaf`'s face normal to active axis i on side
  /// `upper` that touches the face's lowest corner (`farCorner`: its highest);
  /// kind Outside or Hidden when there is none.
  DualNode across(const DualNode& leaf, int i, bool upper, bool farCorner) const;

private:
  const HyperTreeAccess& Grid;
  const DualTraversal& Dual;
  const ContourField& Field;
};

} // namespace canopy
