// A selection frustum in VTK's two conventions, as six half-spaces.
//
// Planes: 24 numbers, (a, b, c, d) per plane, inside where a x + b y + c z + d >= 0:
// what vtkCamera::GetFrustumPlanes returns and vtkPlanes::SetFrustumPlanes takes
// (normals point inward). Corners: the eight points a vtkSelectionNode::FRUSTUM
// lists, in VTK's order near lower left, far lower left, near upper left, far upper
// left, near lower right, far lower right, near upper right, far upper right (bit 0:
// far, bit 1: upper, bit 2: right). Any six half-spaces are accepted: the region
// need not be a camera's frustum, nor bounded (the selection clips it to the grid).
#pragma once

#include "HalfSpace.h"

#include <array>
#include <string>
#include <vector>

namespace canopy
{

struct Frustum
{
  /// (a, b, c, d) per plane, inside where a x + b y + c z + d >= 0.
  std::array<std::array<double, 4>, 6> planes{};

  /// The planes through the faces of the hexahedron with these corners (VTK's
  /// order): each through the three corners VTK's vtkFrustumSelector uses, its
  /// normal turned toward the corners' centroid. Returns what is wrong with the
  /// corners (not finite, a face without area), or an empty string.
  static std::string fromCorners(const std::array<Vec3, 8>& corners, Frustum& frustum);

  /// What is wrong with the planes (a value not finite, a zero normal), or an
  /// empty string.
  std::string problem() const;

  /// The half-spaces n . (p - anchor) <= offset, unit normals pointing outward.
  std::vector<HalfSpace> halfSpaces(const Vec3& anchor) const;
};

} // namespace canopy
