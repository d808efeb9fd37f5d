// The colours a view-dependent filter draws when it is given a colour map: a
// leaf its own mapped colour; a node drawn for level of detail (smaller than
// the pixel threshold, standing for the leaves below it) the area-weighted
// average of its visible leaves' mapped colours. That is what a camera sees of
// those leaves: a pixel integrating light averages colours, not the values
// they come from; drawing the node's value (its volume average) mapped once is
// what made level of detail further from the truth than full resolution
// (docs/benchmarks.md, run time against image error).
//
// Colours are averaged as the image stores them (8-bit sRGB values, as the
// reference image of tests/support/ExactImage.h averages them). Masked and
// absent leaves are left out (their area does not count); a node with none
// visible keeps its own mapped colour.
#pragma once

#include "HyperTreeAccess.h"
#include "TreeTraversal.h"

#include <vtkType.h>

#include <array>
#include <cmath>
#include <vector>

class vtkDataArray;
class vtkScalarsToColors;

namespace canopy
{

using Rgb = std::array<double, 3>; ///< 0..255

/// A colour map sampled once into a table, read without touching VTK (so from
/// any thread): linear interpolation between 1024 samples over the map's range.
class ColorTable
{
public:
  /// `component`: the field's component mapped (-1: its magnitude).
  ColorTable(vtkScalarsToColors* map, vtkDataArray* values, int component);

  Rgb mapValue(double value) const;
  /// The mapped colour of cell `global`'s value.
  Rgb mapCell(vtkIdType global) const;

private:
  std::vector<Rgb> Table;
  double Low = 0;
  double Scale = 0; ///< samples per unit of value
  Rgb NanColor{{0, 0, 0}};
  vtkDataArray* Values;
  int Component;
};

/// Area-weighted average of the mapped colours of the visible leaves below `n`
/// (in `tree`) that acceptChild lets the walk reach (all, or a slice's cut);
/// `dimensions`: the dimension of the drawn pieces (2 for a 2D cell or a cut, 1
/// for a segment): a child's area is f^-dimensions of its parent's.
template <typename AcceptChild>
Rgb averageColor(const HyperTreeAccess& grid, const TreeAccess& tree, const WalkNode& n,
                 int dimensions, const ColorTable& table, const AcceptChild& acceptChild)
{
  Rgb sum{{0, 0, 0}};
  double weight = 0;
  const double shrink = std::pow(static_cast<double>(grid.branchFactor()), -dimensions);
  walkSubtree(
      grid, tree, n,
      [&](WalkNode& m)
      {
        if (grid.hasMask() && grid.isMasked(tree.globalIndex(m.node)))
        {
          return WalkStep::Skip;
        }
        if (!tree.isLeaf(m.node))
        {
          return WalkStep::Descend;
        }
        const double w = std::pow(shrink, m.level - n.level);
        const Rgb c = table.mapCell(tree.globalIndex(m.node));
        for (int k = 0; k < 3; ++k)
        {
          sum[k] += w * c[k];
        }
        weight += w;
        return WalkStep::Skip;
      },
      acceptChild);
  if (weight <= 0)
  {
    return table.mapCell(tree.globalIndex(n.node));
  }
  for (double& c : sum)
  {
    c /= weight;
  }
  return sum;
}

} // namespace canopy
