// A camera's side planes as VTK computes them (vtkCamera::GetFrustumPlanes), as
// ConvexClip.h's planes: the brute-force view the culling tests compare with,
// independent of the filters' separating-axis tests.
#pragma once

#include "ConvexClip.h"

#include <vtkCamera.h>

#include <cmath>
#include <vector>

namespace canopy::testing
{

/// The four side planes (left, right, bottom, top) of the camera's frustum, moved
/// outward by `slack` (a distance; negative: inward). For perspective they meet at
/// the camera and keep only what is in front of it. The camera's clipping range
/// is set so wide that near and far planes never matter (the filters' view
/// volume has none).
inline std::vector<ClipPlane> cameraSidePlanes(vtkCamera* camera, double aspect, double slack)
{
  const double distance = camera->GetDistance();
  camera->SetClippingRange(distance / 1e9, distance * 1e9);
  double planes[24];
  camera->GetFrustumPlanes(aspect, planes);
  std::vector<ClipPlane> result;
  for (int p = 0; p < 4; ++p)
  {
    const double* h = planes + 4 * p;
    const double norm = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    result.push_back({{h[0], h[1], h[2], h[3] + slack * norm}});
  }
  return result;
}

} // namespace canopy::testing
