// Points, half-spaces and rectangles as the filters' geometry uses them.
#pragma once

#include <array>

namespace canopy
{

using Vec3 = std::array<double, 3>;

/// A half-space n . (p - anchor) <= offset, the anchor being chosen by its user
/// (a point near the region of interest): relative coordinates keep far-from-origin
/// domains (1e9) and tiny regions (1e-9) precise.
struct HalfSpace
{
  Vec3 normal;
  double offset;
};

/// The corners of the axis-aligned rectangle [lo, hi] in the plane of axes u and
/// v (its other coordinate lo's), counter-clockwise seen from u x v: (lo, lo),
/// (hi, lo), (hi, hi), (lo, hi). A 2D grid's cell, a slice's cut, a quad.
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
