// Half-spaces as the filters' culling and selection regions use them.
#pragma once

#include "Vec3.h"

namespace canopy
{

/// A half-space n . (p - anchor) <= offset, the anchor being chosen by its user
/// (a point near the region of interest): relative coordinates keep far-from-origin
/// domains (1e9) and tiny regions (1e-9) precise.
struct HalfSpace
{
  Vec3 normal;
  double offset;
};

} // namespace canopy
