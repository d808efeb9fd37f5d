// A convex region (an intersection of half-spaces) cut by the plane a 2D grid
// lies in, or the line of a 1D grid, and clipped to the grid's bounds.
//
// The adaptive surface culls with the view volume's section, the selection
// with a frustum's: a cell of a 2D (1D) grid overlaps the region when its
// rectangle (segment) shares a part of positive area (length) with the section.
// 2D: a convex polygon and a separating-axis test; 1D: an interval.
#pragma once

#include "HalfSpace.h"
#include "HyperTreeAccess.h"

#include <array>
#include <vector>

namespace canopy
{

class GridSection
{
public:
  /// Precondition: grid.dimension() is 1 or 2. Half-spaces are relative to `anchor`.
  GridSection(const HyperTreeAccess& grid, const std::vector<HalfSpace>& halfSpaces,
              const Vec3& anchor);

  /// Whether the cell box [lo, hi] shares a part of positive area (2D) or
  /// length (1D) with the section.
  bool overlaps(const Vec3& lo, const Vec3& hi) const;
  /// True when the section has no area (2D) or length (1D): nothing overlaps it.
  bool empty() const { return Empty; }

private:
  /// Sutherland-Hodgman against nu u + nv v <= c.
  static std::vector<std::array<double, 2>> clip(const std::vector<std::array<double, 2>>& in,
                                                 double nu, double nv, double c);
  void cutPlane(const HyperTreeAccess& grid, const std::vector<HalfSpace>& halfSpaces,
                const Vec3& anchor);
  void cutLine(const HyperTreeAccess& grid, const std::vector<HalfSpace>& halfSpaces,
               const Vec3& anchor);

  int Dimension = 2;
  int U = 0; ///< first active axis (the only one in 1D)
  int V = 1; ///< second active axis (2D)
  double AnchorU = 0;
  double AnchorV = 0;
  bool Empty = true;
  /// 1D: the interval along U, relative to the anchor.
  double Low = 0;
  double High = 0;
  /// 2D: the polygon in (u, v) relative to the anchor, its separating axes and
  /// its extent along each.
  std::vector<std::array<double, 2>> Polygon;
  std::vector<std::array<double, 2>> Axes;
  std::vector<std::array<double, 2>> Intervals;
};

} // namespace canopy
