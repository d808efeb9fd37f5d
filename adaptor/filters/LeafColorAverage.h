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

#include <vtkDataArray.h>
#include <vtkType.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

class vtkScalarsToColors;

namespace canopy
{

using Rgb = std::array<double, 3>; ///< 0..255

/// A channel as the output's unsigned char colours store it: rounded, clamped.
inline unsigned char colorByte(double channel)
{
  return static_cast<unsigned char>(std::lround(std::clamp(channel, 0.0, 255.0)));
}

/// A colour map sampled once into a table, read without touching VTK (so from
/// any thread): linear interpolation between 1024 samples over the map's range
/// (of log10 of the value, for a logarithmic map).
/// Sampling costs (a diverging vtkColorTransferFunction converts through Lab per
/// value): a filter keeps its table while the map is unchanged (sampledFrom).
class ColorTable
{
public:
  explicit ColorTable(vtkScalarsToColors* map);

  /// Whether the table holds `map` as it is now (same object, not modified since).
  bool sampledFrom(vtkScalarsToColors* map) const;
  /// The field mapCell reads: `component` of `values` (-1: its magnitude). The
  /// array must outlive the calls.
  void setField(vtkDataArray* values, int component);

  Rgb mapValue(double value) const
  {
    Rgb c{{0, 0, 0}};
    addMappedValue(value, 1.0, c);
    return c;
  }
  /// The mapped colour of cell `global`'s value.
  Rgb mapCell(vtkIdType global) const
  {
    Rgb c{{0, 0, 0}};
    addMappedCell(global, 1.0, c);
    return c;
  }
  /// sum += weight * the mapped colour of `value` (inline: the colour average
  /// calls it once per leaf).
  void addMappedValue(double value, double weight, Rgb& sum) const
  {
    if (std::isnan(value))
    {
      for (int k = 0; k < 3; ++k)
      {
        sum[k] += weight * NanColor[k];
      }
      return;
    }
    // Non-positive values on a logarithmic map take its low end.
    double x = ((Log ? (value > 0 ? std::log10(value) : Low) : value) - Low) * Scale;
    x = x < 0 ? 0 : (x > Last ? Last : x);
    auto i = static_cast<std::size_t>(x);
    i = i + 1 < Table.size() ? i : Table.size() - 2;
    const double t = x - static_cast<double>(i);
    const Rgb& a = Table[i];
    const Rgb& b = Table[i + 1];
    for (int k = 0; k < 3; ++k)
    {
      sum[k] += weight * (a[k] + t * (b[k] - a[k]));
    }
  }
  void addMappedCell(vtkIdType global, double weight, Rgb& sum) const
  {
    addMappedValue(Component >= 0 ? Values->GetComponent(global, Component) : magnitude(global),
                   weight, sum);
  }

private:
  double magnitude(vtkIdType global) const;

  std::vector<Rgb> Table;
  double Low = 0;
  double Scale = 0; ///< samples per unit of value
  double Last = 0;  ///< the last sample's position
  bool Log = false; ///< sampled in log10 of the value (a logarithmic map)
  Rgb NanColor{{0, 0, 0}};
  const vtkScalarsToColors* Map;
  vtkMTimeType SampledAt = 0;
  vtkDataArray* Values = nullptr;
  int Component = 0;
};

/// acceptChild for a whole subtree (a surface's node).
struct EveryChild
{
  bool operator()(const WalkNode&, int) const { return true; }
};

namespace detail
{

/// Adds the visible leaves below `n` (of area `area`; a child's is `shrink`
/// times its parent's) to sum and weight. Recursive (depth at most the tree's
/// levels): no allocation per drawn node, which a stack-based walk would pay.
template <typename AcceptChild>
void addLeafColors(const HyperTreeAccess& grid, const TreeAccess& tree, const WalkNode& n,
                   double area, double shrink, const ColorTable& table,
                   const AcceptChild& acceptChild, Rgb& sum, double& weight)
{
  const vtkIdType global = tree.globalIndex(n.node);
  if (grid.hasMask() && grid.isMasked(global))
  {
    return;
  }
  if (tree.isLeaf(n.node))
  {
    table.addMappedCell(global, area, sum);
    weight += area;
    return;
  }
  const vtkIdType first = tree.firstChild(n.node);
  for (int c = 0; c < grid.childrenPerNode(); ++c)
  {
    if (acceptChild(n, c))
    {
      addLeafColors(grid, tree, {first + c, n.level + 1, grid.childPosition(n.ijk, c), false},
                    area * shrink, shrink, table, acceptChild, sum, weight);
    }
  }
}

/// The same for every child (a surface's node), from `node`, neither masked
/// nor a leaf, of area `area`: no child positions needed, and the leaf children
/// summed in locals (accumulating each leaf through a reference serializes the
/// walk on memory).
inline void addAllLeafColors(const HyperTreeAccess& grid, const TreeAccess& tree, vtkIdType node,
                             double area, double shrink, const ColorTable& table, Rgb& sum,
                             double& weight)
{
  const double childArea = area * shrink;
  const vtkIdType first = tree.firstChild(node);
  const int children = grid.childrenPerNode();
  Rgb leaves{{0, 0, 0}};
  double count = 0;
  for (int c = 0; c < children; ++c)
  {
    const vtkIdType child = first + c;
    const vtkIdType global = tree.globalIndex(child);
    if (grid.hasMask() && grid.isMasked(global))
    {
      continue;
    }
    if (tree.isLeaf(child))
    {
      table.addMappedCell(global, 1.0, leaves);
      count += 1;
    }
    else
    {
      addAllLeafColors(grid, tree, child, childArea, shrink, table, sum, weight);
    }
  }
  for (int k = 0; k < 3; ++k)
  {
    sum[k] += childArea * leaves[k];
  }
  weight += childArea * count;
}

} // namespace detail

/// Area-weighted average of the mapped colours of the visible leaves below `n`
/// (in `tree`) that acceptChild lets the walk reach (all, or a slice's cut);
/// `dimensions`: the dimension of the drawn pieces (2 for a 2D cell or a cut, 1
/// for a segment): a child's area is f^-dimensions of its parent's.
template <typename AcceptChild>
Rgb averageColor(const HyperTreeAccess& grid, const TreeAccess& tree, const WalkNode& n,
                 int dimensions, const ColorTable& table, const AcceptChild& acceptChild)
{
  const double shrink = std::pow(static_cast<double>(grid.branchFactor()), -dimensions);
  Rgb sum{{0, 0, 0}};
  double weight = 0;
  if constexpr (std::is_same_v<AcceptChild, EveryChild>)
  {
    // A drawn node is visible; a leaf is its own colour.
    if (tree.isLeaf(n.node))
    {
      return table.mapCell(tree.globalIndex(n.node));
    }
    detail::addAllLeafColors(grid, tree, n.node, 1.0, shrink, table, sum, weight);
  }
  else
  {
    detail::addLeafColors(grid, tree, n, 1.0, shrink, table, acceptChild, sum, weight);
  }
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
