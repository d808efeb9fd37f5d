// Points and vectors as the filters' geometry uses them: the few operations on
// them that the view, the frustum and the clipped polytope share, and the
// corners of axis-aligned cells in the order every filter writes them.
#pragma once

#include <array>
#include <cstddef>

namespace canopy
{

using Vec3 = std::array<double, 3>;

inline double dot(const Vec3& a, const Vec3& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

inline Vec3 cross(const Vec3& a, const Vec3& b)
{
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}

inline Vec3 sub(const Vec3& a, const Vec3& b)
{
  return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
}

/// The ends of the axis-aligned segment [lo, hi] along axis u (its other
/// coordinates lo's): lo, then lo moved to hi along u. A 1D grid's cell.
inline std::array<Vec3, 2> segmentEnds(const Vec3& lo, const Vec3& hi, int u)
{
  std::array<Vec3, 2> e{{lo, lo}};
  e[1][static_cast<std::size_t>(u)] = hi[static_cast<std::size_t>(u)];
  return e;
}

/// The corners of the axis-aligned rectangle [lo, hi] in the plane of axes u and
/// v (its other coordinate lo's), counter-clockwise seen from u x v: (lo, lo),
/// (hi, lo), (hi, hi), (lo, hi). A 2D grid's cell, a slice's cut, a 3D face, a
/// layer of a hexahedron.
inline std::array<Vec3, 4> rectangleCorners(const Vec3& lo, const Vec3& hi, int u, int v)
{
  std::array<Vec3, 4> c;
  c.fill(lo);
  c[1][static_cast<std::size_t>(u)] = hi[static_cast<std::size_t>(u)];
  c[2][static_cast<std::size_t>(u)] = hi[static_cast<std::size_t>(u)];
  c[2][static_cast<std::size_t>(v)] = hi[static_cast<std::size_t>(v)];
  c[3][static_cast<std::size_t>(v)] = hi[static_cast<std::size_t>(v)];
  return c;
}

} // namespace canopy
