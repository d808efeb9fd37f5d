// The mini-app's zoomed view: a perspective camera on a region refined to the
// finest level (2D: where the first sphere moves; 3D: where a plane x = offset
// cuts the top face). It shows the adaptive surface at work: what is outside the
// view is culled, and cells far from the camera stop above their leaves once
// they are smaller than the pixel threshold.
#pragma once

#include "MiniAppOptions.h"

#include <string>
#include <vector>

namespace miniamr
{

/// surface_image.py's camera settings for the zoomed view ("--camera-position=x,y,z",
/// "--camera-focal-point=...", "--camera-view-up=..."), or nothing when the run has
/// no such object (2D: a sphere; 3D: a plane with normal x) to follow.
std::vector<std::string> zoomedViewCamera(const MiniAppOptions& options);

} // namespace miniamr
