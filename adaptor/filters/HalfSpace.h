// Points and half-spaces as the filters' geometry uses them.
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

} // namespace canopy
