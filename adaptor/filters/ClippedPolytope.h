// A convex region of space clipped to a box, and an exact test of whether an
// axis-aligned box overlaps it with positive volume.
//
// The region (any half-spaces, bounded or not) is intersected with the box first,
// so it is a bounded polytope Q whose vertices are found once, by intersecting
// every three of the planes. A cell overlaps Q with positive volume exactly when
// no axis weakly separates them (separating-axis theorem for convex polytopes:
// the candidate axes are the coordinate axes, Q's face normals, and the cross
// products of the coordinate axes with Q's edge directions; extra candidates are
// harmless, since any axis that separates proves disjoint interiors). With the
// grid's bounds as the box, a cell (inside the grid) overlaps Q exactly when it
// overlaps the region.
#pragma once

#include "HalfSpace.h"

#include <array>
#include <vector>

namespace canopy
{

class ClippedPolytope
{
public:
  /// Half-spaces relative to `anchor`; the box [boxLo, boxHi] in world coordinates.
  ClippedPolytope(const std::vector<HalfSpace>& halfSpaces, const Vec3& anchor, const Vec3& boxLo,
                  const Vec3& boxHi);

  /// True when the clipped region has no volume: nothing overlaps it.
  bool empty() const { return Empty; }
  /// Whether [lo, hi] and the clipped region share a part of positive volume.
  bool overlaps(const Vec3& lo, const Vec3& hi) const;
  /// Vertices of the clipped region, relative to the anchor.
  const std::vector<Vec3>& vertices() const { return Vertices; }

private:
  Vec3 Anchor;
  bool Empty = true;
  std::vector<Vec3> Vertices;
  std::vector<Vec3> Axes;
  std::vector<std::array<double, 2>> Extents; ///< the region's [min, max] along each axis
};

} // namespace canopy
